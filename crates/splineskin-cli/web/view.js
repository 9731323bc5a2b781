// The drawing on screen: the opened document inside the page (its own <svg>, styles and all),
// the `d` of its imported elements rewritten from deformed chain points, and an overlay in the
// same user space with the handles, the junction markers and the weight field.

import { apply, compose, IDENTITY, inverse, isIdentity } from './affine.js';
import { CARRIED_MARKER, ELEMENT_MARKER as MARKER, JUNCTION_KINDS, PAINT_MARKER } from './constants.js';
import { fixedFormatter, pathOffsets, writePaths } from './pathdata.js';
import { StrokeFrames } from './stroke-frames.js';

const SVG_NS = 'http://www.w3.org/2000/svg';

/** Sizes of the overlay, in CSS pixels. */
export const HANDLE_RADIUS = 7;
export const RING_RADIUS = 34;
export const KNOB_SIZE = 9;
export const JUNCTION_RADIUS = 3.5;
/** Radius (pixels) of the red ring at a fold. */
export const FOLD_RADIUS = 9;
/** Margin shown around the drawing's viewBox, relative to its larger side. */
const VIEW_MARGIN = 0.05;
/** Closest and farthest zoom, as fractions of the opening frame's width shown. */
const MIN_ZOOM = 1 / 64;
const MAX_ZOOM = 8;

function svgElement(name, attributes = {}) {
  const e = document.createElementNS(SVG_NS, name);
  for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, v);
  return e;
}

export class DrawingView {
  /** Shows document `info` (the server's DocumentInfo) in `container` (its shadow root). */
  constructor(container, info) {
    const parsed = new DOMParser().parseFromString(info.svg, 'image/svg+xml');
    const failed = parsed.querySelector('parsererror');
    if (failed || parsed.documentElement.localName !== 'svg') {
      throw new Error(`${info.name}: the browser cannot show this document (${failed?.textContent ?? 'no <svg> root'})`);
    }
    // The page's content security policy already keeps a drawing's scripts from running;
    // they are removed too, so that nothing in the document reacts to the editor's events.
    for (const s of parsed.querySelectorAll('script')) s.remove();
    const root = document.importNode(parsed.documentElement, true);
    // The drawing lives in the container's shadow tree: its CSS and ids stay there (a drawing's
    // `<style>` cannot restyle the page, its ids cannot shadow the page's), and the page's CSS
    // stays out of it but for overlay.css.
    const shadow = container.shadowRoot ?? container.attachShadow({ mode: 'open' });
    const sheet = document.createElement('link');
    sheet.rel = 'stylesheet';
    sheet.href = 'overlay.css';
    // The drawing's own frame with a margin, so that a deformation may leave it a little;
    // user units (the drawing's coordinates) stay what they are.
    const [x, y, w, h] = info.view_box;
    const m = VIEW_MARGIN * Math.max(w, h);
    this.home = [x - m, y - m, w + 2 * m, h + 2 * m];
    this.frame = [...this.home];
    root.setAttribute('width', '100%');
    root.setAttribute('height', '100%');
    this.root = root;
    this.info = info;

    this.elements = new Array(info.elements.length).fill(null);
    for (const e of root.querySelectorAll(`[${MARKER}]`)) {
      const k = Number(e.getAttribute(MARKER));
      if (Number.isInteger(k) && k >= 0 && k < this.elements.length) this.elements[k] = e;
    }
    // The carried text and images (DocumentInfo.carried): each with its parent's map P to root
    // user space and its own transform, which writeCarried prefixes with P⁻¹ A P.
    this.carried = info.carried.map((P, j) => {
      const node = root.querySelector(`[${CARRIED_MARKER}="${j}"]`);
      return { node, P, inverseP: inverse(P), own: node?.getAttribute('transform') ?? '' };
    });
    // Each element's own copies of user-space gradients and patterns (DocumentInfo.painted):
    // their transform is M · G, M the element's local map, G the copy's own transform.
    // A fixed-orientation marker's copy turns: its orient is its own plus M's rotation.
    this.paints = [...root.querySelectorAll(`[${PAINT_MARKER}]`)].flatMap((node) => {
      const k = Number(node.getAttribute(PAINT_MARKER));
      const j = info.painted.indexOf(k);
      const toLocal = info.elements[k]?.to_local;
      if (j < 0 || !toLocal) return [];
      const place = { node, k, j, toLocal, toRoot: inverse(toLocal) };
      if (node.localName === 'marker') {
        const orient = Number(node.getAttribute('orient'));
        return Number.isFinite(orient) ? [{ ...place, name: 'orient', orient }] : [];
      }
      const name = node.localName === 'pattern' ? 'patternTransform' : 'gradientTransform';
      const G = /^matrix\(([^)]*)\)$/.exec(node.getAttribute(name)?.trim() ?? '')?.[1].split(/[\s,]+/).map(Number);
      return G?.length === 6 ? [{ ...place, name, G }] : [];
    });
    ({ offsets: this.offsets, nPoints: this.nPoints } = pathOffsets(info.paths));
    // Per element, its chain points [first, end) (writePaths), and the points last written.
    this.pointRanges = info.elements.map(({ first_path: first, end_path: end }) =>
      first < end ? [this.offsets[first], this.offsets[end - 1] + info.paths[end - 1].n_points] : [0, 0],
    );
    this.written = null;
    // Decimals of the written coordinates: 1e-5 of the view box's diagonal or finer.
    const diagonal = Math.hypot(w, h) || 1;
    this.digits = Math.min(8, Math.max(0, Math.ceil(5 - Math.log10(diagonal))));
    this.format = fixedFormatter(this.digits);
    // Per element, decimals for the same precision in its own units (`d` is written in them): a
    // flag's saltire drawn inside scale(128 160) needs two more than root units do.
    const formatters = new Map();
    this.formats = info.elements.map(({ to_local: T }) => {
      const toRoot = inverse(T);
      const scale = toRoot ? Math.max(Math.hypot(toRoot[0], toRoot[1]), Math.hypot(toRoot[2], toRoot[3])) : 1;
      const digits = Math.min(8, Math.max(0, Math.ceil(5 - Math.log10(diagonal / scale))));
      if (!formatters.has(digits)) formatters.set(digits, fixedFormatter(digits));
      return formatters.get(digits);
    });
    this.localMaps = info.elements.map((e) => (isIdentity(e.to_local) ? null : e.to_local));
    // The elements stroked inside a stretched local map L, drawn as Export SVG draws them.
    this.strokeFrames = new StrokeFrames(info, this.elements);

    // The overlay is an <svg> of its own over the drawing's, its user space the drawing's less
    // an origin in the middle of the drawing's frame: far from 0 (say 3e7 units) the browser
    // draws coordinates in single precision, which would misplace and distort markers of a few
    // pixels; relative to the origin they stay small. It takes no pointer events (the editor
    // hit-tests handles itself), so the drawing under it does.
    this.origin = [x + w / 2, y + h / 2];
    this.overlayRoot = svgElement('svg', { class: 'ss-overlay-root', width: '100%', height: '100%' });
    // Placed over the drawing here too, not only by overlay.css: the sheet loads after the view
    // is shown, and until it has the overlay would sit below the drawing, and every click and
    // pin position read through it (toUser, toClient) would be off by the drawing's height.
    Object.assign(this.overlayRoot.style, { position: 'absolute', inset: '0', pointerEvents: 'none' });
    this.overlay = svgElement('g', { class: 'ss-overlay' });
    this.weightImage = svgElement('image', { class: 'ss-weights', preserveAspectRatio: 'none' });
    this.weightImage.style.display = 'none';
    // The weights' triangulated domain, posed (drawMesh).
    this.mesh = svgElement('path', { class: 'ss-mesh' });
    // The weight field on the posed drawing (showWeightMesh).
    this.weightMesh = svgElement('g', { class: 'ss-weights' });
    this.weightMesh.style.display = 'none';
    this.junctionPaths = Object.fromEntries(
      [...JUNCTION_KINDS, 'inserted'].map((k) => [k, svgElement('path', { class: `ss-junctions ${k}` })]),
    );
    this.handleLayer = svgElement('g', { class: 'ss-handles' });
    // Onion skin: the drawing at the keyframes before and after the shown time, outlined.
    this.onion = { before: svgElement('path', { class: 'ss-onion before' }), after: svgElement('path', { class: 'ss-onion after' }) };
    // The selection box while it is dragged.
    this.box = svgElement('rect', { class: 'ss-box' });
    this.box.style.display = 'none';
    // The document's viewBox, outlined while the deformed art leaves it (showViewBox).
    this.viewBoxFrame = svgElement('rect', {
      class: 'ss-view-box',
      x: x - this.origin[0],
      y: y - this.origin[1],
      width: w,
      height: h,
    });
    this.viewBoxFrame.style.display = 'none';
    // Where the deformation folds an outline over itself (drawFolds): red rings.
    this.folds = svgElement('path', { class: 'ss-folds' });
    this.overlay.append(
      this.weightImage,
      this.weightMesh,
      this.mesh,
      this.viewBoxFrame,
      this.onion.before,
      this.onion.after,
      ...Object.values(this.junctionPaths),
      this.folds,
      this.handleLayer,
      this.box,
    );
    this.overlayRoot.append(this.overlay);
    shadow.replaceChildren(sheet, root, this.overlayRoot);
    this.setFrame(this.frame);
  }

  /**
   * Whether the drawing's art is painted under client point (x, y): some element of the
   * document (not the editor's overlay) takes the pointer there, as the browser hit-tests it
   * (painted fill or stroke, the document's own `pointer-events`).
   */
  artAt(clientX, clientY) {
    return this.root
      .getRootNode()
      .elementsFromPoint(clientX, clientY)
      .some((e) => e !== this.root && this.root.contains(e));
  }

  /**
   * The client point on the art nearest to (clientX, clientY) within `radius` CSS pixels (the
   * point itself when the art is there; else the first hit on rings of 1, 2, … px, 16 directions
   * each), or null: a click just off a thin stroke still lands on it.
   */
  artNear(clientX, clientY, radius) {
    if (this.artAt(clientX, clientY)) return [clientX, clientY];
    for (let r = 1; r <= radius; r++) {
      for (let k = 0; k < 16; k++) {
        const a = (k * Math.PI) / 8;
        const [x, y] = [clientX + r * Math.cos(a), clientY + r * Math.sin(a)];
        if (this.artAt(x, y)) return [x, y];
      }
    }
    return null;
  }

  /**
   * Rings in red where the deformation folds an outline over itself: `marks` are
   * { at: [x, y] (drawing units), radius (CSS pixels) }; an empty list clears them.
   */
  drawFolds(marks) {
    const u = this.unitsPerPixel();
    const f = this.markFormat();
    const [ox, oy] = this.origin;
    this.folds.setAttribute(
      'd',
      marks
        .map(({ at: [px, py], radius }) => {
          const [x, y, r] = [px - ox, py - oy, radius * u];
          return `M${f(x - r)} ${f(y)}a${f(r)} ${f(r)} 0 1 0 ${f(2 * r)} 0a${f(r)} ${f(r)} 0 1 0 ${f(-2 * r)} 0z`;
        })
        .join(''),
    );
  }


  /** Outlines the document's viewBox (dashed), or hides the outline. */
  showViewBox(shown) {
    this.viewBoxFrame.style.display = shown ? '' : 'none';
  }

  /**
   * Shows the whole drawing again (the viewBox the document opened with), grown to hold every
   * point of `points` (say the posed handles) with a margin, so that nothing dragged out of
   * the drawing's frame stays out of sight.
   */
  fit(points = []) {
    const [x, y, w, h] = this.home;
    const margin = VIEW_MARGIN * Math.max(w, h);
    let [x0, y0, x1, y1] = [x, y, x + w, y + h];
    for (const [px, py] of points) {
      if (!(Number.isFinite(px) && Number.isFinite(py))) continue;
      x0 = Math.min(x0, px - margin);
      y0 = Math.min(y0, py - margin);
      x1 = Math.max(x1, px + margin);
      y1 = Math.max(y1, py + margin);
    }
    this.setFrame([x0, y0, x1 - x0, y1 - y0]);
  }

  /**
   * Zooms by `factor` (> 1: closer) keeping the drawing point under client (x, y) in place.
   * Only the shown frame (the root's viewBox) changes: the drawing's coordinates do not.
   */
  zoom(factor, clientX, clientY) {
    const [px, py] = this.toUser(clientX, clientY);
    const [x, y, w, h] = this.frame;
    const scale = Math.min(Math.max(1 / factor, (this.home[2] * MIN_ZOOM) / w), (this.home[2] * MAX_ZOOM) / w);
    this.setFrame([px - (px - x) * scale, py - (py - y) * scale, w * scale, h * scale]);
  }

  /** Moves the shown frame by (dx, dy) CSS pixels. */
  pan(dx, dy) {
    const u = this.unitsPerPixel();
    const [x, y, w, h] = this.frame;
    this.setFrame([x - dx * u, y - dy * u, w, h]);
  }

  /** Shows `frame` ([x, y, w, h], drawing units): the drawing's viewBox and the overlay's. */
  setFrame(frame) {
    this.frame = frame;
    const [x, y, w, h] = frame;
    this.root.setAttribute('viewBox', frame.join(' '));
    this.overlayRoot.setAttribute('viewBox', [x - this.origin[0], y - this.origin[1], w, h].join(' '));
  }

  /** The client point of drawing point p. */
  toClient([x, y]) {
    const m = this.overlay.getScreenCTM();
    const q = new DOMPoint(x - this.origin[0], y - this.origin[1]).matrixTransform(m);
    return [q.x, q.y];
  }

  /** User units per CSS pixel at the current size. */
  unitsPerPixel() {
    const m = this.overlay.getScreenCTM();
    if (!m) return 1;
    return 1 / Math.sqrt(Math.abs(m.a * m.d - m.b * m.c) || 1);
  }

  /** The root user space point under client coordinates (x, y). */
  toUser(clientX, clientY) {
    const m = this.overlay.getScreenCTM();
    if (!m) return [clientX, clientY];
    const p = new DOMPoint(clientX, clientY).matrixTransform(m.inverse());
    return [p.x + this.origin[0], p.y + this.origin[1]];
  }

  /**
   * A formatter of mark coordinates (relative to the origin): decimals enough for 1e-3 of a
   * pixel at the current zoom.
   */
  markFormat() {
    const digits = Math.min(12, Math.max(0, Math.ceil(3 - Math.log10(this.unitsPerPixel()))));
    if (this._markDigits !== digits) {
      this._markDigits = digits;
      this._markFormat = fixedFormatter(digits);
    }
    return this._markFormat;
  }

  /**
   * Rewrites the `d` of every imported element from chain points x0, y0, x1, y1, …. With a
   * `budgetMs` (a drag's frames on a big drawing), only the elements that time allows, those
   * whose points moved most since they were last written first (unmoved ones are left as they
   * are); returns whether a moved element was left for a later frame. Without one, every
   * element is written.
   */
  writePaths(points, budgetMs = Infinity) {
    const { info, offsets, formats } = this;
    const write = (k) => {
      const { first_path: first, end_path: end } = info.elements[k];
      const framed = this.strokeFrames.get(k);
      const T = framed ? framed.localMap : this.localMaps[k];
      this.elements[k].setAttribute('d', writePaths(info.paths, offsets, first, end, points, formats[k], T));
      if (framed?.stale) {
        if (framed.transform) this.elements[k].setAttribute('transform', framed.transform);
        else this.elements[k].removeAttribute('transform');
        framed.stale = false;
      }
      const [a, b] = this.pointRanges[k];
      this.written.set(points.subarray(2 * a, 2 * b), 2 * a);
    };
    if (!this.written || budgetMs === Infinity) {
      this.written ??= new Float64Array(points.length);
      for (let k = 0; k < info.elements.length; k++) if (this.elements[k]) write(k);
      return false;
    }
    // Each element's largest move since it was written, and the moved ones, most moved first.
    const count = info.elements.length;
    const { moves, order } = (this.writeOrder ??= { moves: new Float64Array(count), order: new Int32Array(count) });
    let nMoved = 0;
    for (let k = 0; k < count; k++) {
      if (!this.elements[k]) continue;
      const [a, b] = this.pointRanges[k];
      let most = 0;
      for (let i = 2 * a; i < 2 * b; i++) most = Math.max(most, Math.abs(points[i] - this.written[i]));
      // An element whose stroke frame turned is written again even if its points stand.
      if (most === 0 && this.strokeFrames.get(k)?.stale) most = Number.MIN_VALUE;
      moves[k] = most;
      if (most > 0) order[nMoved++] = k;
    }
    const moved = order.subarray(0, nMoved).sort((x, y) => moves[y] - moves[x]);
    const start = performance.now();
    let n = 0;
    while (n < nMoved && (n === 0 || performance.now() - start < budgetMs)) write(moved[n++]);
    return n < nMoved;
  }

  /**
   * Sets the stroke frames from `maps` (as writeCarried reads them; null: every frame the
   * identity), which the next writePaths writes (StrokeFrames.set). Returns whether one
   * changed.
   */
  setFrames(maps) {
    return this.strokeFrames.set(maps, this.carried.length);
  }

  /**
   * Carries each text and image, and each element's own user-space gradients and patterns, by
   * its best-fit map: `maps` holds six numbers per carried element, then per painted element,
   * root user space (the rig's carry operator, LiveRig.carryMaps), or is null for none (they
   * stand as the document has them). A text's or image's `transform` becomes `P⁻¹ A P` before
   * its own, a paint copy's transform `L⁻¹ A L · G`, a marker copy's orient its own plus the
   * rotation of `L⁻¹ A L` (`(F L)⁻¹ A L` for an element in a stroke frame `F`, setFrames), as
   * Export SVG writes them.
   */
  writeCarried(maps) {
    const n = this.carried.length;
    for (const { node, name, G, orient, k, j, toLocal, toRoot } of this.paints) {
      // L⁻¹ A L, or (F L)⁻¹ A L for an element drawn in its stroke frame F (setFrames).
      const inverseF = this.strokeFrames.get(k)?.inverseF ?? IDENTITY;
      const M = maps ? compose(toLocal, compose(inverseF, compose(maps.subarray(6 * (n + j), 6 * (n + j) + 6), toRoot))) : [1, 0, 0, 1, 0, 0];
      if (name === 'orient') {
        node.setAttribute('orient', String(orient + (Math.atan2(M[1] - M[2], M[0] + M[3]) * 180) / Math.PI));
      } else {
        node.setAttribute(name, `matrix(${compose(M, G).join(' ')})`);
      }
    }
    this.carried.forEach(({ node, P, inverseP, own }, j) => {
      if (!node) return;
      if (!maps) {
        if (own) node.setAttribute('transform', own);
        else node.removeAttribute('transform');
        return;
      }
      const M = compose(inverseP, compose(maps.subarray(6 * j, 6 * j + 6), P));
      node.setAttribute('transform', `matrix(${M.join(' ')}) ${own}`.trim());
    });
  }

  /**
   * The junctions: [{ path, joint, point }] for every joint that is not an open end, `point`
   * the chain point index.
   */
  junctions() {
    if (!this._junctions) {
      this._junctions = [];
      this.info.paths.forEach((path, p) => {
        path.joints.forEach((kind, joint) => {
          if (kind !== 'end') this._junctions.push({ path: p, joint, point: this.offsets[p] + 3 * joint });
        });
      });
    }
    return this._junctions;
  }

  /** Draws the junction markers at `points` with kinds from `kindOf(junction)`, or hides them. */
  drawJunctions(points, kindOf, visible) {
    const r = JUNCTION_RADIUS * this.unitsPerPixel();
    const data = Object.fromEntries([...JUNCTION_KINDS, 'inserted'].map((k) => [k, []]));
    if (visible) {
      const f = this.markFormat();
      const [ox, oy] = this.origin;
      for (const j of this.junctions()) {
        const x = points[2 * j.point] - ox;
        const y = points[2 * j.point + 1] - oy;
        const kind = kindOf(j);
        // Anchors that adaptive control points inserted (not the artist's): ringed.
        if (this.info.paths[j.path].inserted?.[j.joint]) {
          const R = 1.8 * r;
          data.inserted.push(`M${f(x - R)} ${f(y)}a${f(R)} ${f(R)} 0 1 0 ${f(2 * R)} 0a${f(R)} ${f(R)} 0 1 0 ${f(-2 * R)} 0z`);
        }
        const list = data[kind];
        if (!list) continue;
        if (kind === 'C0') {
          list.push(`M${f(x - r)} ${f(y - r)}h${f(2 * r)}v${f(2 * r)}h${f(-2 * r)}z`);
        } else if (kind === 'angle') {
          const s = 1.3 * r;
          list.push(`M${f(x)} ${f(y - s)}l${f(s)} ${f(s)}l${f(-s)} ${f(s)}l${f(-s)} ${f(-s)}z`);
        } else {
          list.push(`M${f(x - r)} ${f(y)}a${f(r)} ${f(r)} 0 1 0 ${f(2 * r)} 0a${f(r)} ${f(r)} 0 1 0 ${f(-2 * r)} 0z`);
        }
      }
    }
    for (const [k, path] of Object.entries(this.junctionPaths)) path.setAttribute('d', data[k].join(''));
  }

  /** The junction within `radius` pixels of user point p at `points`, or null. */
  junctionAt(points, p, radius = JUNCTION_RADIUS + 2) {
    const limit = radius * this.unitsPerPixel();
    let best = null;
    let bestDistance = limit;
    for (const j of this.junctions()) {
      const d = Math.hypot(points[2 * j.point] - p[0], points[2 * j.point + 1] - p[1]);
      if (d <= bestDistance) {
        best = j;
        bestDistance = d;
      }
    }
    return best;
  }

  /**
   * Draws handle markers at `positions` (posed), those of `selection` (indices) filled, and
   * the rotate ring and scale knob about `centre` (null: none).
   */
  drawHandles(positions, selection, centre = null) {
    const u = this.unitsPerPixel();
    const layer = this.handleLayer;
    layer.replaceChildren();
    const chosen = new Set(selection);
    const [ox, oy] = this.origin;
    if (centre) {
      const [x, y] = [centre[0] - ox, centre[1] - oy];
      layer.append(
        svgElement('circle', { class: 'ss-ring', cx: x, cy: y, r: RING_RADIUS * u, 'stroke-width': 5 * u }),
        svgElement('rect', {
          class: 'ss-knob',
          x: x + RING_RADIUS * u - (KNOB_SIZE / 2) * u,
          y: y - (KNOB_SIZE / 2) * u,
          width: KNOB_SIZE * u,
          height: KNOB_SIZE * u,
          'stroke-width': 1.5 * u,
        }),
      );
    }
    positions.forEach(([x, y], i) => {
      layer.append(
        svgElement('circle', {
          class: chosen.has(i) ? 'ss-handle selected' : 'ss-handle',
          cx: x - ox,
          cy: y - oy,
          r: HANDLE_RADIUS * u,
          'stroke-width': 2 * u,
          'data-handle': i,
        }),
      );
    });
  }

  /**
   * Draws the edges `edges` ([a, b] vertex pairs) of a mesh whose vertices are at `points`
   * (x0, y0, …, drawing units), or hides it (null).
   */
  drawMesh(points, edges) {
    if (!points) {
      this.mesh.setAttribute('d', '');
      return;
    }
    const [ox, oy] = this.origin;
    const f = this.markFormat();
    const at = (v) => `${f(points[2 * v] - ox)} ${f(points[2 * v + 1] - oy)}`;
    const parts = new Array(edges.length);
    for (let k = 0; k < edges.length; k++) parts[k] = `M${at(edges[k][0])}L${at(edges[k][1])}`;
    this.mesh.setAttribute('d', parts.join(''));
  }

  /** Shows the selection box [x0, y0, x1, y1] (drawing units), or hides it (null). */
  showBox(box) {
    if (!box) {
      this.box.style.display = 'none';
      return;
    }
    const [x0, y0, x1, y1] = box;
    const [ox, oy] = this.origin;
    for (const [k, v] of Object.entries({ x: x0 - ox, y: y0 - oy, width: x1 - x0, height: y1 - y0 })) this.box.setAttribute(k, v);
    this.box.style.display = '';
  }

  /**
   * Outlines the drawing with chain points `before` and `after` (x0, y0, …, root user units;
   * null: that outline hidden).
   */
  drawOnion(before, after) {
    this.onion.before.setAttribute('d', before ? this.outline(before) : '');
    this.onion.after.setAttribute('d', after ? this.outline(after) : '');
  }

  /** Path data of every path of the drawing at chain points `points`, relative to the origin. */
  outline(points) {
    const [ox, oy] = this.origin;
    const { paths } = this.info;
    return writePaths(paths, this.offsets, 0, paths.length, points, this.markFormat(), [1, 0, 0, 1, -ox, -oy]);
  }

  /**
   * Shows a weight field on the posed drawing: a `width × height` lattice of points (x0, y0,
   * … row by row, drawing units) with a weight each (`values`), every cell between four
   * neighbouring points filled with the colour (`colour(w)`: [r, g, b]) of their mean weight.
   * Cells of one colour (weights rounded to 1/64) share one path.
   */
  showWeightMesh(points, values, width, height, colour) {
    this.weightImage.style.display = 'none';
    const [ox, oy] = this.origin;
    const f = this.markFormat();
    const byColour = new Map();
    const at = (k) => `${f(points[2 * k] - ox)} ${f(points[2 * k + 1] - oy)}`;
    for (let r = 0; r + 1 < height; r++) {
      for (let c = 0; c + 1 < width; c++) {
        const k = r * width + c;
        const corners = [k, k + 1, k + width + 1, k + width];
        const w = corners.reduce((s, q) => s + values[q], 0) / 4;
        const bucket = Math.round(w * 64) / 64;
        const d = `M${at(corners[0])}L${at(corners[1])}L${at(corners[2])}L${at(corners[3])}Z`;
        const list = byColour.get(bucket);
        if (list) list.push(d);
        else byColour.set(bucket, [d]);
      }
    }
    // A hairline stroke of the cell's own colour closes the anti-aliasing seams between cells.
    const seam = 0.6 * this.unitsPerPixel();
    this.weightMesh.replaceChildren(
      ...[...byColour].map(([w, list]) => {
        const rgb = `rgb(${colour(w).join(' ')})`;
        return svgElement('path', { d: list.join(''), fill: rgb, stroke: rgb, 'stroke-width': seam });
      }),
    );
    this.weightMesh.style.display = '';
  }

  /** Shows the image at `url` over box [x0, y0, x1, y1] (user units), or hides it (null). */
  showWeights(url, box) {
    this.weightMesh.style.display = 'none';
    if (!url) {
      this.weightImage.style.display = 'none';
      return;
    }
    const [x0, y0, x1, y1] = box;
    this.weightImage.setAttribute('href', url);
    this.weightImage.setAttribute('x', x0 - this.origin[0]);
    this.weightImage.setAttribute('y', y0 - this.origin[1]);
    this.weightImage.setAttribute('width', x1 - x0);
    this.weightImage.setAttribute('height', y1 - y0);
    this.weightImage.style.display = '';
  }
}

/** Handle positions as posed: T_i applied to rest position p_i. */
export function posedHandles(scene) {
  return scene.handles.map((p, i) => apply(scene.pose[i], p));
}
