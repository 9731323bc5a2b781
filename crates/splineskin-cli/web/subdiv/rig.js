// The fitted cage from the rig's factors (POST /api/subdiv/rig): `c'_v = Σ_i T_i · B_i[v]`,
// `T_i` a 3 × 4 map per handle (rows), `B_i[v]` four numbers (Liu, Jacobson & Gingold 2014 §3:
// the fit is linear in the handles' maps, so the cage is a small product per frame).

/** The identity rotation, rows flat. */
export const IDENTITY_ROTATION = [1, 0, 0, 0, 1, 0, 0, 0, 1];

/**
 * The 3 × 4 map (rows, flat) of a handle placed at `rest`, turned by `rotation` (3 × 3 rows,
 * flat) about it and moved by `offset`: `x ↦ rest + offset + R (x − rest)`.
 */
export function handleMap({ rest, offset, rotation: r }) {
  const t = [0, 1, 2].map((k) => rest[k] + offset[k] - (r[3 * k] * rest[0] + r[3 * k + 1] * rest[1] + r[3 * k + 2] * rest[2]));
  return [r[0], r[1], r[2], t[0], r[3], r[4], r[5], t[1], r[6], r[7], r[8], t[2]];
}

/** `Rot(axis, angle) · r`: `r` (3 × 3 rows, flat) turned by `angle` radians about the unit `axis`. */
export function turned(r, axis, angle) {
  const [x, y, z] = axis;
  const c = Math.cos(angle);
  const s = Math.sin(angle);
  const k = 1 - c;
  const q = [
    c + x * x * k, x * y * k - z * s, x * z * k + y * s,
    y * x * k + z * s, c + y * y * k, y * z * k - x * s,
    z * x * k - y * s, z * y * k + x * s, c + z * z * k,
  ];
  const out = new Array(9);
  for (let i = 0; i < 3; i++) {
    for (let j = 0; j < 3; j++) {
      out[3 * i + j] = q[3 * i] * r[j] + q[3 * i + 1] * r[3 + j] + q[3 * i + 2] * r[6 + j];
    }
  }
  return out;
}

/**
 * Writes the fitted cage for `transforms` (one flat 3 × 4 map per handle) into `out`
 * (x, y, z per cage vertex), by `rig = { coefficients, n_vertices, n_handles }`.
 */
export function fitCage(rig, transforms, out) {
  const { coefficients: b, n_vertices: n, n_handles: h } = rig;
  for (let v = 0; v < n; v++) {
    let x = 0;
    let y = 0;
    let z = 0;
    for (let i = 0; i < h; i++) {
      const o = 4 * (v * h + i);
      const t = transforms[i];
      x += t[0] * b[o] + t[1] * b[o + 1] + t[2] * b[o + 2] + t[3] * b[o + 3];
      y += t[4] * b[o] + t[5] * b[o + 1] + t[6] * b[o + 2] + t[7] * b[o + 3];
      z += t[8] * b[o] + t[9] * b[o + 1] + t[10] * b[o + 2] + t[11] * b[o + 3];
    }
    out[3 * v] = x;
    out[3 * v + 1] = y;
    out[3 * v + 2] = z;
  }
  return out;
}

/** Writes column `i` of `weights` (`h` numbers per vertex) into `out`. */
export function weightColumn(weights, h, i, out) {
  for (let m = 0; m < out.length; m++) out[m] = weights[m * h + i];
  return out;
}

/** `T · (x, y, z)` for a flat 3 × 4 map `T`, added `w` times into `out` at `o`. */
function addMapped(t, x, y, z, w, out, o) {
  out[o] += w * (t[0] * x + t[1] * y + t[2] * z + t[3]);
  out[o + 1] += w * (t[4] * x + t[5] * y + t[6] * z + t[7]);
  out[o + 2] += w * (t[8] * x + t[9] * y + t[10] * z + t[11]);
}

/**
 * Linear blend skinning of `points` (x, y, z flat) by `weights` (`h` per point) and `transforms`,
 * into `out`: `Σ_i w_i T_i p`. Of the cage's vertices it is the naive method's cage; of the rest
 * surface's vertices, the skinned surface both methods are measured against.
 */
export function skin(points, weights, transforms, out) {
  const h = transforms.length;
  out.fill(0);
  for (let v = 0; v < points.length / 3; v++) {
    const x = points[3 * v];
    const y = points[3 * v + 1];
    const z = points[3 * v + 2];
    for (let i = 0; i < h; i++) {
      const w = weights[v * h + i];
      if (w !== 0) addMapped(transforms[i], x, y, z, w, out, 3 * v);
    }
  }
  return out;
}

/** Distances between the points of `a` and `b` (x, y, z flat), and their largest and RMS. */
export function distances(a, b, out) {
  let max = 0;
  let sum = 0;
  for (let v = 0; v < out.length; v++) {
    const d = Math.hypot(a[3 * v] - b[3 * v], a[3 * v + 1] - b[3 * v + 1], a[3 * v + 2] - b[3 * v + 2]);
    out[v] = d;
    max = Math.max(max, d);
    sum += d * d;
  }
  return { max, rms: Math.sqrt(sum / Math.max(1, out.length)) };
}
