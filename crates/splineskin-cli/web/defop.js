// A drawing joined to a deformation operator, in the page: control points = G_spline · ψ(Q)
// (DESIGN.md top, "The join"; §4 "Evaluation"). The server trains the operator and sends
// G_spline and what ψ needs (POST /api/defop, crates/splineskin-editor/src/lib.rs); this
// file evaluates ψ exactly as the library does (crates/splineskin-defop/src/handle_basis.rs):
//
//   z = (Q − P) / scale,  z[2ℓ] = (q_ℓ.x − p_ℓ.x) / scale,  z[2ℓ+1] = (q_ℓ.y − p_ℓ.y) / scale
//   ψ = 1, z_a                                   (linear, 1 + 2n functions)
//       then z_a z_b, a ≤ b                      (quadratic)
//       then z_a z_b z_c, a ≤ b ≤ c              (cubic)
//     or then φ(‖z − z_k‖), φ(r) = r² log r = ½ r² log r², φ(0) = 0, one per centre z_k (tps)
//
// Q is where the handles are: q_ℓ = T_ℓ(p_ℓ) for handle ℓ's map T_ℓ and rest position p_ℓ, so
// only a handle's translation matters. Nothing is allocated per frame.

import { HANDLE_BASIS_KINDS } from './constants.js';
import { matVec } from './rig.js';

// The handle basis kinds the server names (HandleBasisKind::name).
export { HANDLE_BASIS_KINDS };

/** Number of functions |Ψ| of `kind` for n handles and m centres (HandleBasisKind::n_functions). */
export function nFunctions(kind, n, m) {
  const d = 2 * n;
  switch (kind) {
    case 'linear':
      return 1 + d;
    case 'quadratic':
      return 1 + d + (d * (d + 1)) / 2;
    case 'cubic':
      return 1 + d + (d * (d + 1)) / 2 + (d * (d + 1) * (d + 2)) / 6;
    case 'tps':
      return 1 + d + m;
    default:
      throw new Error(`unknown handle basis '${kind}' (expected ${HANDLE_BASIS_KINDS.join(', ')})`);
  }
}

/**
 * The operator rig: `info` is the server's x-splineskin-defop header (kind, scale, rest,
 * n_functions, n_centres, n_points), `data` the body: G_spline row-major
 * (2 · nPoints) × |Ψ|, then the centres row-major n_centres × 2n. `handles` are the page's rest
 * handles [[x, y], …] (where the maps T_ℓ apply).
 */
export class DefOpLiveRig {
  constructor(info, data, nPoints, handles) {
    const n = info.rest.length;
    if (n === 0 || n !== handles.length) {
      throw new Error(`the operator has ${n} handles; the scene has ${handles.length}`);
    }
    if (info.n_points !== nPoints) {
      throw new Error(`the operator writes ${info.n_points} points; the drawing has ${nPoints}`);
    }
    const nPsi = nFunctions(info.kind, n, info.n_centres);
    if (nPsi !== info.n_functions) {
      throw new Error(`the operator has ${info.n_functions} handle functions; a ${info.kind} basis has ${nPsi}`);
    }
    const size = 2 * nPoints * nPsi;
    const expected = size + info.n_centres * 2 * n;
    if (data.length !== expected) {
      throw new Error(`the operator holds ${data.length} numbers; ${expected} expected`);
    }
    if (!(Number.isFinite(info.scale) && info.scale > 0)) {
      throw new Error(`the operator's scale ${info.scale} is not a positive length`);
    }
    this.id = info.id;
    this.info = info;
    this.kind = info.kind;
    this.nPoints = nPoints;
    this.nHandles = n;
    this.scale = info.scale;
    this.G = data.subarray(0, size);
    this.centres = data.subarray(size);
    this.nCentres = info.n_centres;
    this.rest = Float64Array.from(info.rest.flat());
    this.handles = Float64Array.from(handles.flat());
    /** ψ(Q), then a 1 (the carry operator's constant column). */
    this.psiAndOne = new Float64Array(nPsi + 1);
    this.psiAndOne[nPsi] = 1;
    /** ψ(Q), |Ψ| values (a view of the same numbers); ψ[1 + a] = z_a. */
    this.psi = this.psiAndOne.subarray(0, nPsi);
    /** The carry operator (setCarry), and the maps it gives (carryMaps). */
    this.carry = null;
    this.carryOut = null;
    /** The rig whose maps stand in until this one's carry operator arrives (followsFrom). */
    this.carryFallback = null;
    /** The last configuration Q, x0, y0, x1, … (the rest until the first frame). */
    this.q = Float64Array.from(this.rest);
  }

  /** Writes Q = (T_ℓ(p_ℓ))_ℓ for `pose` (one map [a, b, c, d, e, f] per handle) into this.q. */
  configuration(pose) {
    const { handles, q } = this;
    for (let l = 0; l < this.nHandles; l++) {
      const T = pose[l];
      const x = handles[2 * l];
      const y = handles[2 * l + 1];
      q[2 * l] = T[0] * x + T[2] * y + T[4];
      q[2 * l + 1] = T[1] * x + T[3] * y + T[5];
    }
  }

  /** Writes ψ(this.q) into this.psi (HandleBasis::eval). */
  evalPsi() {
    const { psi, q, rest, scale } = this;
    const d = 2 * this.nHandles;
    psi[0] = 1;
    for (let a = 0; a < d; a++) psi[1 + a] = (q[a] - rest[a]) / scale;
    let next = 1 + d;
    if (this.kind === 'quadratic' || this.kind === 'cubic') {
      for (let a = 0; a < d; a++) {
        for (let b = a; b < d; b++) psi[next++] = psi[1 + a] * psi[1 + b];
      }
      if (this.kind === 'cubic') {
        for (let a = 0; a < d; a++) {
          for (let b = a; b < d; b++) {
            const zab = psi[1 + a] * psi[1 + b];
            for (let c = b; c < d; c++) psi[next++] = zab * psi[1 + c];
          }
        }
      }
    } else if (this.kind === 'tps') {
      const C = this.centres;
      for (let k = 0, base = 0; k < this.nCentres; k++, base += d) {
        let r2 = 0;
        for (let a = 0; a < d; a++) {
          const t = psi[1 + a] - C[base + a];
          r2 += t * t;
        }
        psi[next++] = r2 > 0 ? 0.5 * r2 * Math.log(r2) : 0;
      }
    }
  }

  /**
   * Takes the operator's carry operator (GET /api/defops/{id}/carry): per carried text or image,
   * then per painted element, six rows of |Ψ| + 1 coefficients (ψ(Q), then a constant), `nMaps`
   * maps in all. Ignored when its size does not fit.
   */
  setCarry(carry, nMaps) {
    if (nMaps === 0 || carry.length !== nMaps * 6 * this.psiAndOne.length) return;
    this.carry = carry;
    this.carryOut = new Float64Array(6 * nMaps);
    this.carryFallback = null;
  }

  /**
   * Until its own carry operator arrives, this rig (an operator that followed a drag) carries
   * text and paint by `old`'s maps, the rig it is blended in from, rather than leaving them at
   * rest for a moment (its ψ may have other functions: a thin-plate basis gains centres).
   */
  followsFrom(old) {
    this.carryFallback = old;
  }

  /**
   * The carried elements' best-fit maps at `pose` (six numbers each, root user space): the
   * carry operator's product with [ψ(Q), 1]; null until the operator is known.
   */
  carryMaps(pose) {
    if (!this.carry) return this.carryFallback?.carryMaps(pose) ?? null;
    this.configuration(pose);
    this.evalPsi();
    matVec(this.carry, this.psiAndOne, this.carryOut.length, this.carryOut);
    return this.carryOut;
  }

  /** Writes the deformed chain points x0, y0, x1, y1, … for `pose`: G_spline · ψ(Q). */
  deform(pose, out) {
    this.configuration(pose);
    this.evalPsi();
    matVec(this.G, this.psi, 2 * this.nPoints, out);
  }
}
