// Path data from chain points: the one writer of `d` attributes shared by the editor's view
// (view.js, every frame) and the JavaScript API (splineskin.js).
//
// A path of n cubic curves has 3n + 1 chain points x0, y0, x1, y1, … (a closed one's last point
// is its first, stored once): `M p0 C p1 p2 p3 p4 p5 p6 …`, then ` Z` where the document closed
// it so. A DocumentInfo (the server's, or the module's) lists each path's `n_points`, `closed`
// and `close_with_z`, in the order of the points.

/**
 * Where each path's chain points start in the points array (in points, not numbers), and how
 * many points there are in all: `{ offsets, nPoints }`.
 *
 * ```js
 * pathOffsets([{ n_points: 4 }, { n_points: 7 }]); // { offsets: [0, 4], nPoints: 11 }
 * ```
 */
export function pathOffsets(paths) {
  const offsets = [];
  let nPoints = 0;
  for (const p of paths) {
    offsets.push(nPoints);
    nPoints += p.n_points;
  }
  return { offsets, nPoints };
}

/**
 * The path data of paths `first` to `end` (exclusive) of `paths` at chain points `points`,
 * joined by spaces: each point written `format(x) format(y)`, after the affine map `T`
 * ([a, b, c, d, e, f]: x' = a x + c y + e, y' = b x + d y + f) where one is given.
 *
 * ```js
 * const paths = [{ n_points: 4, closed: false, close_with_z: false }];
 * writePaths(paths, [0], 0, 1, [0, 0, 1, 0, 2, 1, 3, 0], String);
 * // 'M0 0 C1 0 2 1 3 0'
 * ```
 */
export function writePaths(paths, offsets, first, end, points, format, T = null) {
  let d = '';
  for (let p = first; p < end; p++) {
    const path = paths[p];
    const o = offsets[p];
    const n = path.n_points;
    if (d) d += ' ';
    for (let i = 0; i < n; i++) {
      // A closed path's last point is its first (so that Z adds no segment).
      const q = path.closed && i === n - 1 ? o : o + i;
      let x = points[2 * q];
      let y = points[2 * q + 1];
      if (T) {
        const lx = T[0] * x + T[2] * y + T[4];
        y = T[1] * x + T[3] * y + T[5];
        x = lx;
      }
      d += (i === 0 ? 'M' : i % 3 === 1 ? ' C' : ' ') + format(x) + ' ' + format(y);
    }
    if (path.close_with_z) d += ' Z';
  }
  return d;
}

/**
 * A formatter writing numbers with `digits` decimals, as toFixed does (half away from zero
 * aside), about twice as fast: the per-frame path data of big drawings is mostly numbers.
 */
export function fixedFormatter(digits) {
  if (digits === 0) return (v) => String(Math.round(v));
  const scale = 10 ** digits;
  const zeros = '0'.repeat(digits);
  return (v) => {
    const r = Math.round(v * scale);
    const m = r < 0 ? -r : r;
    const whole = Math.trunc(m / scale);
    const fraction = String(m - whole * scale);
    return (r < 0 ? '-' : '') + whole + '.' + (fraction.length < digits ? zeros.slice(fraction.length) + fraction : fraction);
  };
}
