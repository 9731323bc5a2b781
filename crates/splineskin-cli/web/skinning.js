// Linear blend skinning in the page: a point x carried by the maps Tᵢ of a pose blended by its
// weights wᵢ(x), x' = Σᵢ wᵢ(x) Tᵢ x (Jacobson et al. 2011, eq. 1; DESIGN.md). The rig's own
// per-frame product (rig.js) is this formula folded into one matrix; the page uses the formula
// itself where it has weights at points of its own: the weight field and the mesh drawn posed,
// and the map given to a handle added on a posed drawing.
//
// Maps are [a, b, c, d, e, f]: x' = a x + c y + e, y' = b x + d y + f.

/**
 * Skins the points `rest` (x0, y0, x1, y1, … flat) by `pose`: `weight(k, i)` is handle i's
 * weight at point k. Returns `out` (a new array unless given).
 *
 * ```js
 * const pose = [[1, 0, 0, 1, 0, 0], [1, 0, 0, 1, 10, 0]];
 * skinPoints(pose, [0, 0], () => 0.5); // Float64Array [5, 0]
 * ```
 */
export function skinPoints(pose, rest, weight, out = new Float64Array(rest.length)) {
  const n = rest.length / 2;
  for (let k = 0; k < n; k++) {
    const x = rest[2 * k];
    const y = rest[2 * k + 1];
    let sx = 0;
    let sy = 0;
    for (let i = 0; i < pose.length; i++) {
      const w = weight(k, i);
      const T = pose[i];
      sx += w * (T[0] * x + T[2] * y + T[4]);
      sy += w * (T[1] * x + T[3] * y + T[5]);
    }
    out[2 * k] = sx;
    out[2 * k + 1] = sy;
  }
  return out;
}

/**
 * The blended map Σᵢ wᵢ Tᵢ of `pose` under weights `w` (one per map, summing to 1): where a
 * point with those weights goes, x' = (Σᵢ wᵢ Tᵢ) x.
 *
 * ```js
 * blendMaps([[1, 0, 0, 1, 0, 0], [1, 0, 0, 1, 10, 0]], [0.5, 0.5]); // [1, 0, 0, 1, 5, 0]
 * ```
 */
export function blendMaps(pose, w) {
  const T = [0, 0, 0, 0, 0, 0];
  pose.forEach((Ti, i) => Ti.forEach((v, c) => (T[c] += w[i] * v)));
  return T;
}
