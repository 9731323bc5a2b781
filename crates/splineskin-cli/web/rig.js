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
    /** The pose's coefficients, then a 1 (the carry operator's constant column). */
    this.coefficients = new Float64Array(6 * nHandles + 1);
    this.coefficients[6 * nHandles] = 1;
    /** The pose's coefficients alone (a view of the same numbers: the operator's columns). */
    this.poseCoefficients = this.coefficients.subarray(0, 6 * nHandles);
    /** The carry operator (setCarry), and the maps it gives (carryMaps). */
    this.carry = null;
    this.carryOut = null;
  }

  /** Writes `pose`'s coefficients (one map per handle) into `this.coefficients`. */
  setPose(pose) {
    const t = this.coefficients;
    for (let i = 0; i < this.nHandles; i++) {
      for (let c = 0; c < 6; c++) t[6 * i + c] = pose[i][c];
    }
  }

  /**
   * Takes the rig's carry operator (GET /api/rigs/{id}/carry): per carried text or image, then
   * per painted element, six rows of 6h + 1 coefficients (the pose's, then a constant), `nMaps`
   * maps in all. Ignored when its size does not fit.
   */
  setCarry(carry, nMaps) {
    if (nMaps === 0 || carry.length !== nMaps * 6 * (6 * this.nHandles + 1)) return;
    this.carry = carry;
    this.carryOut = new Float64Array(6 * nMaps);
  }

  /**
   * The carried elements' best-fit maps at `pose` (six numbers each, root user space): the
   * carry operator's product with [vec(T), 1]; null until the operator is known.
   */
  carryMaps(pose) {
    if (!this.carry) return null;
    this.setPose(pose);
    matVec(this.carry, this.coefficients, this.carryOut.length, this.carryOut);
    return this.carryOut;
  }

  /**
   * Writes the deformed chain points x0, y0, x1, y1, … for `pose` (one map per handle). With
   * `exact` false (a drag's frames), only the columns of the maps that changed since the last
   * product are applied to it, `points += O[:, changed] · Δt` (a pin dragged among h costs a
   * 1/h of the product); with `exact` (the default) the whole product, which is what every
   * settled drawing shows.
   */
  deform(pose, out, exact = true) {
    this.setPose(pose);
    const t = this.poseCoefficients;
    const cols = t.length;
    const last = (this.last ??= {
      t: new Float64Array(cols),
      points: new Float64Array(2 * this.nPoints),
      valid: false,
      columns: new Int32Array(cols),
      deltas: new Float64Array(cols),
    });
    let n = 0;
    for (let c = 0; c < cols; c++) {
      if (t[c] === last.t[c]) continue;
      last.columns[n] = c;
      last.deltas[n++] = t[c] - last.t[c];
    }
    if (!exact && last.valid && 2 * n < cols) {
      addColumns(this.operator, cols, last.columns, last.deltas, n, 2 * this.nPoints, last.points);
    } else {
      matVec(this.operator, t, 2 * this.nPoints, last.points);
      last.valid = true;
    }
    last.t.set(t);
    out.set(last.points);
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

/**
 * out[r] += Σ_{k < n} M[r · cols + columns[k]] · deltas[k] for r < rows (M row-major, `cols`
 * wide): the product's change when only some columns' coefficients changed.
 */
export function addColumns(M, cols, columns, deltas, n, rows, out) {
  for (let r = 0, base = 0; r < rows; r++, base += cols) {
    let s = 0;
    for (let k = 0; k < n; k++) s += M[base + columns[k]] * deltas[k];
    out[r] += s;
  }
}

/** Whether this machine stores numbers little-endian (the server sends them so). */
export function littleEndian() {
  return new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;
}
