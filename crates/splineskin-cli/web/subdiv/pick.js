// What the pointer is over: points and triangles projected to the screen with the view's matrix.

/** `[x, y, depth]` in CSS pixels of a view `width × height` of the point `p`, or null behind. */
export function project(matrix, p, width, height) {
  const m = matrix;
  const x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
  const y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
  const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
  if (w <= 0) return null;
  return [((x / w + 1) / 2) * width, ((1 - y / w) / 2) * height, w];
}

/** The index of the point of `points` (x, y, z flat) within `radius` pixels of `at`, nearest first; null if none. */
export function pickPoint(matrix, points, at, { width, height, radius }) {
  let best = null;
  let bestDistance = radius;
  for (let i = 0; i < points.length / 3; i++) {
    const s = project(matrix, points.slice(3 * i, 3 * i + 3), width, height);
    if (!s) continue;
    const d = Math.hypot(s[0] - at[0], s[1] - at[1]);
    if (d <= bestDistance) {
      best = i;
      bestDistance = d;
    }
  }
  return best;
}

/** The nearest point of the triangles (over `positions`) under the screen point `at`, or null. */
export function pickSurface(matrix, positions, triangles, at, { width, height }) {
  const screen = new Float64Array(positions.length);
  for (let v = 0; v < positions.length / 3; v++) {
    const s = project(matrix, [positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]], width, height);
    screen.set(s ?? [NaN, NaN, NaN], 3 * v);
  }
  let best = null;
  let bestDepth = Infinity;
  for (let t = 0; t < triangles.length; t += 3) {
    const [a, b, c] = [3 * triangles[t], 3 * triangles[t + 1], 3 * triangles[t + 2]];
    const w = barycentric(screen, a, b, c, at);
    if (!w) continue;
    const depth = w[0] * screen[a + 2] + w[1] * screen[b + 2] + w[2] * screen[c + 2];
    if (depth < bestDepth) {
      bestDepth = depth;
      best = [0, 1, 2].map((k) => w[0] * positions[a + k] + w[1] * positions[b + k] + w[2] * positions[c + k]);
    }
  }
  return best;
}

/** Barycentric coordinates of `p` in the screen triangle `a, b, c` (offsets into `s`), or null outside. */
function barycentric(s, a, b, c, [px, py]) {
  const x0 = s[a];
  const y0 = s[a + 1];
  const d = (s[b + 1] - s[c + 1]) * (x0 - s[c]) + (s[c] - s[b]) * (y0 - s[c + 1]);
  if (!(Math.abs(d) > 1e-12)) return null;
  const l0 = ((s[b + 1] - s[c + 1]) * (px - s[c]) + (s[c] - s[b]) * (py - s[c + 1])) / d;
  const l1 = ((s[c + 1] - y0) * (px - s[c]) + (x0 - s[c]) * (py - s[c + 1])) / d;
  const l2 = 1 - l0 - l1;
  return l0 >= 0 && l1 >= 0 && l2 >= 0 ? [l0, l1, l2] : null;
}
