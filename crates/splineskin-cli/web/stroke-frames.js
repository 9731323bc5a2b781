// The stroke frames of the shown drawing: each element stroked inside a stretched local map L
// (a non-uniform scale or a shear; DocumentInfo's ElementInfo.stroke_frame) is drawn in the
// frame F L, F from its best-fit map, as Export SVG draws it (splineskin_svg::follow, stroke
// frames): its path data mapped by (F L)⁻¹, its `transform` its own then L⁻¹ F L.

import { apply, compose, IDENTITY, inverse, isIdentity } from './affine.js';
import { REFLECTION_MARGIN } from './constants.js';

/**
 * The stroke frame F of an element whose best-fit map is A, fitted on its region `region`
 * ({ centre: p̄, covariance: [cxx, cxy, cyy] }, DocumentInfo's ElementInfo.stroke_frame): the
 * best-fit rotation of the cross-covariance X = A C, or reflection where it fits better by
 * REFLECTION_MARGIN, moved so that F p̄ = A p̄ (splineskin_svg::follow::StrokeFrameRegion::frame).
 * Rotation: θ = atan2(x₂₁ − x₁₂, x₁₁ + x₂₂); reflection: θ = atan2(x₂₁ + x₁₂, x₁₁ − x₂₂),
 * Q = [cos, sin, sin, −cos].
 */
export function strokeFrame(A, { centre, covariance: [cxx, cxy, cyy] }) {
  const X = [A[0] * cxx + A[2] * cxy, A[1] * cxx + A[3] * cxy, A[0] * cxy + A[2] * cyy, A[1] * cxy + A[3] * cyy];
  const [a, b, c, d] = X;
  let Q;
  if (Math.hypot(a - d, b + c) > REFLECTION_MARGIN * Math.hypot(a + d, b - c)) {
    const t = Math.atan2(b + c, a - d);
    Q = [Math.cos(t), Math.sin(t), Math.sin(t), -Math.cos(t), 0, 0];
  } else {
    const t = Math.atan2(b - c, a + d);
    Q = [Math.cos(t), Math.sin(t), -Math.sin(t), Math.cos(t), 0, 0];
  }
  const [ax, ay] = apply(A, centre);
  const [qx, qy] = apply(Q, centre);
  Q[4] = ax - qx;
  Q[5] = ay - qy;
  return Q;
}

/** Per element in a stroke frame, its frame and what writing it needs. */
export class StrokeFrames {
  /**
   * The elements of `info` (the server's DocumentInfo) that have a stroke frame, `elements`
   * their nodes in the shown document (by element index). Each starts in the identity frame.
   */
  constructor(info, elements) {
    /** Element index → { j (its place in `painted`), region, toLocal, toRoot, own (its own
     * `transform`), F, inverseF, transform (to write), localMap (root → its path data, null
     * for the identity), stale (frame changed since its element was written) }. */
    this.byElement = new Map();
    info.painted.forEach((k, j) => {
      const region = info.elements[k]?.stroke_frame;
      const node = elements[k];
      if (!region || !node) return;
      const toLocal = info.elements[k].to_local;
      const toRoot = inverse(toLocal);
      if (!toRoot) return;
      const own = node.getAttribute('transform') ?? '';
      const localMap = isIdentity(toLocal) ? null : toLocal;
      this.byElement.set(k, { j, region, toLocal, toRoot, own, F: IDENTITY, inverseF: IDENTITY, transform: own, localMap, stale: false });
    });
  }

  /** Element `k`'s record, or undefined when it has no stroke frame. */
  get(k) {
    return this.byElement.get(k);
  }

  /**
   * Sets each frame from `maps` (six numbers per carried element, `nCarried` of them, then
   * per painted element, root user space; null: every frame the identity): `F` the best-fit
   * rotation of the element's region under its best-fit map `A` (strokeFrame), its path data
   * mapped by `(F L)⁻¹ = L⁻¹ F⁻¹`, its `transform` its own then `L⁻¹ F L`. Returns whether a
   * frame changed (its element is marked stale, to be written again).
   */
  set(maps, nCarried) {
    let changed = false;
    for (const framed of this.byElement.values()) {
      const { j, region, toLocal, toRoot, own } = framed;
      const at = 6 * (nCarried + j);
      const F = maps ? strokeFrame(maps.subarray(at, at + 6), region) : IDENTITY;
      const inverseF = inverse(F);
      if (!inverseF || F.every((v, i) => v === framed.F[i])) continue;
      const T = compose(toLocal, inverseF);
      Object.assign(framed, {
        F,
        inverseF,
        stale: true,
        transform: maps ? `${own} matrix(${compose(toLocal, compose(F, toRoot)).join(' ')})`.trim() : own,
        localMap: isIdentity(T) ? null : T,
      });
      changed = true;
    }
    return changed;
  }
}
