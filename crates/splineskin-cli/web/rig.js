// The rig in the page: the operator O the server precomputed, and the per-frame product
// points = O · vec(T) (DESIGN.md §1 "Solving": precompute once, one dense mat-vec a frame).

/**
 * O is row-major (2 · nPoints) × (6 · nHandles): row 2k + d gives coordinate d of chain point
 * k, column 6i + c coefficient c of handle i's map [a, b, c, d, e, f].
 */
export class LiveRig {
  constructor(id, operator, nPoints, nHandles) {
    if (operator.length !== 2 * nPoints * 6 * nHandles) {
      throw new Error(
        `the rig operator holds ${operator.length} numbers; a drawing of ${nPoints} points with ` +
          `${nHandles} handles needs ${2 * nPoints * 6 * nHandles}`,
      );
    }
    this.id = id;
    this.operator = operator;
    this.nPoints = nPoints;
    this.nHandles = nHandles;
    this.coefficients = new Float64Array(6 * nHandles);
  }

  /** Writes the deformed chain points x0, y0, x1, y1, … for `pose` (one map per handle). */
  deform(pose, out) {
    const t = this.coefficients;
    for (let i = 0; i < this.nHandles; i++) {
      for (let c = 0; c < 6; c++) t[6 * i + c] = pose[i][c];
    }
    matVec(this.operator, t, 2 * this.nPoints, out);
  }
}

/**
 * out[r] = Σ_c M[r · cols + c] · x[c] for r < rows, with M row-major and cols = x.length: the
 * one dense product a frame costs.
 */
export function matVec(M, x, rows, out) {
  const cols = x.length;
  for (let r = 0, base = 0; r < rows; r++, base += cols) {
    let s = 0;
    for (let c = 0; c < cols; c++) s += M[base + c] * x[c];
    out[r] = s;
  }
}

/** Whether this machine stores numbers little-endian (the server sends them so). */
export function littleEndian() {
  return new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;
}
