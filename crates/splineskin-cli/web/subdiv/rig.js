// The fitted cage from the rig's factors (POST /api/subdiv/rig): `c'_v = Σ_i T_i · B_i[v]`,
// `T_i` a 3 × 4 map per handle (rows), `B_i[v]` four numbers (Liu, Jacobson & Gingold 2014 §3:
// the fit is linear in the handles' maps, so the cage is a small product per frame).

/** The 3 × 4 map (rows, flat) moving everything by `d`. */
export function translation(d) {
  return [1, 0, 0, d[0], 0, 1, 0, d[1], 0, 0, 1, d[2]];
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

/** Column `i` of `weights` (`h` numbers per vertex), as f32 for drawing. */
export function weightColumn(weights, h, i) {
  const out = new Float32Array(weights.length / h);
  for (let m = 0; m < out.length; m++) out[m] = weights[m * h + i];
  return out;
}
