// Affine maps as SVG matrices [a, b, c, d, e, f]: (x, y) ↦ (a x + c y + e, b x + d y + f),
// the order of the scene files and of the rig operator's columns.

export const IDENTITY = Object.freeze([1, 0, 0, 1, 0, 0]);

/** A ∘ B: B first, then A. */
export function compose(A, B) {
  return [
    A[0] * B[0] + A[2] * B[1],
    A[1] * B[0] + A[3] * B[1],
    A[0] * B[2] + A[2] * B[3],
    A[1] * B[2] + A[3] * B[3],
    A[0] * B[4] + A[2] * B[5] + A[4],
    A[1] * B[4] + A[3] * B[5] + A[5],
  ];
}

/** T applied to the point [x, y]. */
export function apply(T, [x, y]) {
  return [T[0] * x + T[2] * y + T[4], T[1] * x + T[3] * y + T[5]];
}

export function translation(dx, dy) {
  return [1, 0, 0, 1, dx, dy];
}

/** Rotation by `angle` radians about the point c (counter-clockwise in y-up terms). */
export function rotationAbout(angle, [cx, cy]) {
  const cos = Math.cos(angle);
  const sin = Math.sin(angle);
  return [cos, sin, -sin, cos, cx - cos * cx + sin * cy, cy - sin * cx - cos * cy];
}

/** Uniform scale by s about the point c. */
export function scaleAbout(s, [cx, cy]) {
  return [s, 0, 0, s, cx - s * cx, cy - s * cy];
}

export function isIdentity(T, tolerance = 0) {
  return T.every((v, k) => Math.abs(v - IDENTITY[k]) <= tolerance);
}

/** The inverse of T, or null when T is singular. */
export function inverse(T) {
  const [a, b, c, d, e, f] = T;
  const det = a * d - b * c;
  if (!(Math.abs(det) > 0) || !Number.isFinite(det)) return null;
  return [d / det, -b / det, -c / det, a / det, (c * f - d * e) / det, (b * e - a * f) / det];
}
