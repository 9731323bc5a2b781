// The limit surface from the cage: each surface vertex is a sparse combination of cage
// vertices (its limit stencil, sent by POST /api/subdiv/open), `s_m = Σ_j w_mj c_j`; the normals
// are the area-weighted normals of the triangles around each vertex.

/**
 * Writes the surface positions for cage positions `cage` (x, y, z flat) into `out`
 * (3 · n_vertices), by the stencils `{offsets, indices, weights}`.
 */
export function tessellate(stencils, cage, out) {
  const { offsets, indices, weights } = stencils;
  const n = offsets.length - 1;
  for (let m = 0; m < n; m++) {
    let x = 0;
    let y = 0;
    let z = 0;
    for (let e = offsets[m]; e < offsets[m + 1]; e++) {
      const j = 3 * indices[e];
      const w = weights[e];
      x += w * cage[j];
      y += w * cage[j + 1];
      z += w * cage[j + 2];
    }
    out[3 * m] = x;
    out[3 * m + 1] = y;
    out[3 * m + 2] = z;
  }
  return out;
}

/** Writes unit vertex normals of `triangles` at `positions` into `out` (same length). */
export function vertexNormals(positions, triangles, out) {
  out.fill(0);
  for (let t = 0; t < triangles.length; t += 3) {
    const a = 3 * triangles[t];
    const b = 3 * triangles[t + 1];
    const c = 3 * triangles[t + 2];
    const ux = positions[b] - positions[a];
    const uy = positions[b + 1] - positions[a + 1];
    const uz = positions[b + 2] - positions[a + 2];
    const vx = positions[c] - positions[a];
    const vy = positions[c + 1] - positions[a + 1];
    const vz = positions[c + 2] - positions[a + 2];
    const nx = uy * vz - uz * vy;
    const ny = uz * vx - ux * vz;
    const nz = ux * vy - uy * vx;
    addTo(out, a, nx, ny, nz);
    addTo(out, b, nx, ny, nz);
    addTo(out, c, nx, ny, nz);
  }
  for (let v = 0; v < out.length; v += 3) {
    const length = Math.hypot(out[v], out[v + 1], out[v + 2]) || 1;
    out[v] /= length;
    out[v + 1] /= length;
    out[v + 2] /= length;
  }
  return out;
}

function addTo(out, v, x, y, z) {
  out[v] += x;
  out[v + 1] += y;
  out[v + 2] += z;
}

/** The centre and radius of the bounding sphere of the box around `positions`. */
export function bounds(positions) {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < positions.length; i += 3) {
    for (let k = 0; k < 3; k++) {
      lo[k] = Math.min(lo[k], positions[i + k]);
      hi[k] = Math.max(hi[k], positions[i + k]);
    }
  }
  const centre = lo.map((l, k) => (l + hi[k]) / 2);
  const radius = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 2 || 1;
  return { centre, radius };
}
