// splineskin's JavaScript API: deform vector art (cubic Bézier drawings from SVG) by point
// handles while keeping it splines, computed by splineskin's WebAssembly module in the page or
// in Node, no server. Types: splineskin.d.ts. Guide: docs/javascript.md.
//
//   const splineskin = await load();                  // splineskin.wasm next to this module
//   const drawing = splineskin.open(svgText, 'cat.svg');
//   const rig = drawing.rig({ pins: [[10, 20], [80, 30]] });   // smooth weights: the precompute
//   const points = new Float64Array(2 * drawing.nPoints);
//   rig.update([[1, 0, 0, 1, 0, 0], [1, 0, 0, 1, 15, -5]], points); // per frame, no allocation
//   drawing.pathData(points);  drawing.svg(points, { rig, pose });
//
// Every call goes through the editor's routes (crates/splineskin-editor), the same the editor
// page uses, answered synchronously by the module; failures throw SplineskinError with the
// module's message (naming the file and element).

import { isIdentity } from './affine.js';
import { pathOffsets, writePaths } from './pathdata.js';
import { matVec } from './rig.js';
import { loadEditor } from './wasm-editor.js';

/** A failure of the module: its message names the file and element concerned. */
export class SplineskinError extends Error {
  constructor(message, status) {
    super(message);
    this.name = 'SplineskinError';
    /** The editor route's status (400 bad input, 404 dropped, 413 too large, 500 a bug). */
    this.status = status;
  }
}

/**
 * Loads splineskin. `source`: the module's URL, a fetch Response, or its bytes (ArrayBuffer or
 * typed array); default `splineskin.wasm` next to this file (read from disk under Node; a
 * bundler such as Vite copies it into the build). `threads`: with the threaded module
 * (`splineskin-threads.wasm`), how many threads to compute on, started as worker threads under
 * Node or Web Workers in a worker of a cross-origin-isolated page (not on a page's main thread,
 * which may not wait); the one-thread module ignores it. `splineskin.threads` says how many run.
 */
export async function load(source = new URL('./splineskin.wasm', import.meta.url), { threads = 1 } = {}) {
  return new Splineskin(await loadEditor(source, { threads }));
}

const HEADERS = { 'x-splineskin': '1' };
const decoder = new TextDecoder();

/** The module: opens drawings. */
export class Splineskin {
  constructor(editor) {
    this._editor = editor;
    /** The threads the module computes on (1 unless the threaded module was given threads). */
    this.threads = editor.threads;
  }

  /** Answers a route; the response, or throws SplineskinError. */
  _call(method, path, body, headers = {}) {
    const response = this._editor.request(method, path, { body, headers: { ...HEADERS, ...headers } });
    if (response.status !== 200) {
      let message = `${method} ${path}: status ${response.status}`;
      try {
        message = JSON.parse(decoder.decode(response.body)).error ?? message;
      } catch {
        // not JSON: keep the status
      }
      throw new SplineskinError(message, response.status);
    }
    return response;
  }

  _json(method, path, body, headers) {
    return JSON.parse(decoder.decode(this._call(method, path, body, headers).body));
  }

  /**
   * Opens `text`: an SVG document, or a scene (our JSON format, its drawing inline, or the
   * paper authors' `*-deformation.json`). `name` names it in messages.
   */
  open(text, name = 'drawing.svg') {
    const info = this._json('POST', '/api/open', text, { 'x-file-name': encodeURIComponent(name) });
    return new Drawing(this, info);
  }
}

/** An opened drawing. */
export class Drawing {
  constructor(splineskin, info) {
    this._s = splineskin;
    /** The module's description of it (paths, elements, junction kinds, warnings, the scene opened). */
    this.info = info;
    /** Its file name. */
    this.name = info.name;
    /** Chain points of all paths (3 per cubic, plus 1 per open path). */
    this.nPoints = info.rest.length / 2;
    /** Cubic curves. */
    this.nCurves = info.n_curves;
    /** The root viewBox [x, y, width, height]. */
    this.viewBox = info.view_box;
    /** The rest chain points x0, y0, x1, y1, … (root user units). */
    this.rest = Float64Array.from(info.rest);
    /** What the user should know about what was opened. */
    this.warnings = info.warnings;
    /**
     * The document to show: the original text with every imported element written as a
     * `<path>` marked `data-splineskin-element="k"` (whose `d` elementPathData gives). Its own
     * scripts and event attributes are the caller's to neutralise (a content security policy).
     */
    this.document = info.svg;
    this._offsets = pathOffsets(info.paths).offsets;
  }

  /**
   * Precomputes a rig: `pins` ([x, y] each, root user units), `weights` (`bbw`: smooth, the
   * default; `shepard`, `harmonic`, `biharmonic`), `flexible` (flexible G¹ junctions, solved by
   * `solve`), `junctions` ([{ path, joint, kind }] overrides). The seconds this takes are the
   * weights' solve (bounded biharmonic: a second or two on an icon).
   */
  rig({ pins, weights = 'bbw', flexible = false, junctions = [] } = {}) {
    if (!Array.isArray(pins) || pins.length === 0) throw new SplineskinError(`${this.name}: rig: expected pins, an array of [x, y]`, 400);
    const scene = {
      handles: pins.map(([x, y]) => [x, y]),
      pose: pins.map(() => [1, 0, 0, 1, 0, 0]),
      weights: { family: weights },
      junctions,
      flexible,
    };
    const response = this._s._call('POST', '/api/rig', JSON.stringify({ document: this.info.id, scene }));
    const bytes = response.body;
    const operator = new Float64Array(bytes.buffer, bytes.byteOffset, bytes.byteLength / 8);
    return new Rig(this, response.headers['x-splineskin-rig'], operator, pins.length, flexible);
  }

  /** Path data (`M … C … Z`) of every path at chain points `points`, root user units. */
  pathData(points) {
    this._check(points);
    const { paths } = this.info;
    return paths.map((_, p) => writePaths(paths, this._offsets, p, p + 1, points, String));
  }

  /**
   * Path data of every element of the document at chain points `points`, each in the element's
   * own coordinates: the `d` of the element marked `data-splineskin-element="k"` in `document`.
   */
  elementPathData(points) {
    this._check(points);
    const { paths } = this.info;
    return this.info.elements.map((e) => {
      // Root user space → the element's coordinates, point by point.
      const T = isIdentity(e.to_local) ? null : e.to_local;
      return writePaths(paths, this._offsets, e.first_path, e.end_path, points, String, T);
    });
  }

  /**
   * The SVG document with its paths at `points`, styles kept. With `rig` and its `pose`,
   * gradients, patterns, text and images follow the deformation; `viewBox: 'fit'` grows the
   * viewBox to include the art (`'keep'`, the default, leaves it).
   */
  svg(points, { rig, pose, viewBox = 'keep' } = {}) {
    this._check(points);
    let query = `viewbox=${encodeURIComponent(viewBox)}`;
    let body = Float64Array.from(points);
    if (rig) {
      query += `&rig=${encodeURIComponent(rig.id)}`;
      const coefficients = rig._coefficients(pose);
      body = new Float64Array([...points, ...coefficients]);
    }
    const path = `/api/documents/${encodeURIComponent(this.info.id)}/export?${query}`;
    return decoder.decode(this._s._call('POST', path, new Uint8Array(body.buffer)).body);
  }

  _check(points) {
    if (!points || points.length !== 2 * this.nPoints) {
      throw new SplineskinError(`${this.name}: expected ${2 * this.nPoints} numbers (x, y of ${this.nPoints} chain points), got ${points?.length}`, 400);
    }
  }
}

/** A precomputed rig: the operator O, `points = O · vec(T)` a frame. */
export class Rig {
  constructor(drawing, id, operator, nHandles, flexible) {
    this._drawing = drawing;
    this.id = id;
    /** O, row-major (2 · nPoints) × (6 · nHandles). */
    this.operator = operator;
    this.nHandles = nHandles;
    this.nPoints = drawing.nPoints;
    /** Whether `solve` runs the flexible G¹ solve. */
    this.flexible = flexible;
    this._t = new Float64Array(6 * nHandles);
  }

  /** The pose as 6 · nHandles numbers in `this._t` (from arrays [a, b, c, d, e, f] or flat). */
  _coefficients(pose) {
    const t = this._t;
    if (!pose || (pose.length !== this.nHandles && pose.length !== t.length)) {
      throw new SplineskinError(`${this._drawing.name}: expected a pose of ${this.nHandles} maps [a, b, c, d, e, f]`, 400);
    }
    if (pose.length === t.length && typeof pose[0] === 'number') {
      t.set(pose);
    } else {
      for (let i = 0; i < this.nHandles; i++) for (let c = 0; c < 6; c++) t[6 * i + c] = pose[i][c];
    }
    return t;
  }

  /**
   * Writes the deformed chain points for `pose` (one affine map [a, b, c, d, e, f] per pin, SVG
   * order, or 6 · nHandles numbers) into `out` (a Float64Array of 2 · nPoints): the per-frame
   * product, in JavaScript, allocating nothing. With flexible junctions this is the fixed-ratio
   * preview; `solve` gives the flexible result.
   */
  update(pose, out) {
    const t = this._coefficients(pose);
    const rows = 2 * this.nPoints;
    if (!out || out.length !== rows) throw new SplineskinError(`${this._drawing.name}: update: expected out of ${rows} numbers`, 400);
    matVec(this.operator, t, rows, out);
    return out;
  }

  /** The deformed chain points for `pose` solved by the module: flexible G¹ when the rig is flexible. */
  solve(pose) {
    const t = this._coefficients(pose);
    const maps = [];
    for (let i = 0; i < this.nHandles; i++) maps.push(Array.from(t.subarray(6 * i, 6 * i + 6)));
    const path = `/api/rigs/${encodeURIComponent(this.id)}/solve`;
    const bytes = this._drawing._s._call('POST', path, JSON.stringify({ pose: maps })).body;
    return new Float64Array(bytes.buffer, bytes.byteOffset, bytes.byteLength / 8);
  }
}
