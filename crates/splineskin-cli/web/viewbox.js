// The viewBox: whether the deformed art leaves the document's viewBox and where outlines fold
// over themselves (the server's report after each change), said in the status bar and ringed
// on the drawing.

import * as api from './api.js';
import { showError, showNote } from './messages.js';
import { editor } from './store.js';
import { FOLD_RADIUS } from './view.js';

function units(v) {
  return Number(v.toPrecision(4)).toString();
}

/**
 * Asks the server whether the drawing as shown leaves the document's viewBox and says so in
 * the status line; the latest answer wins. `body[data-viewbox]` is 'inside', 'outside' or
 * 'checking' (for the tests).
 */
export async function checkViewBox() {
  const seq = ++editor.viewBoxSeq;
  const { info } = editor;
  const points = Float64Array.from(editor.points);
  document.body.dataset.viewbox = 'checking';
  try {
    const report = await api.outside(info.id, points);
    if (seq !== editor.viewBoxSeq || info !== editor.info) return;
    editor.viewBoxReport = report;
    showViewBoxReport(report);
  } catch (e) {
    if (seq !== editor.viewBoxSeq) return;
    delete document.body.dataset.viewbox;
    if (e.status !== 404) showError(e);
  }
}

/** Crossings within this many CSS pixels of each other are ringed as one place. */
const FOLD_CLUSTER_PX = 14;
/** A place whose crossings (an even number: a loop) all lie within this many pixels is a fold
 * too small to see at this zoom: not ringed or counted (the command reports it exactly). */
const SUB_PIXEL = 0.5;

/**
 * The places to ring for `folds` at `unitsPerPixel`: each crossing joins the first place
 * started within FOLD_CLUSTER_PX of it (places are found through a grid of that cell size),
 * else starts one; each place is one ring around its crossings (at least FOLD_RADIUS), a place
 * of a sub-pixel loop left out. { marks: [{ at, radius }], counted, hidden }.
 */
export function foldMarks(folds, unitsPerPixel) {
  const reach = FOLD_CLUSTER_PX * unitsPerPixel;
  const grid = new Map();
  const places = [];
  const cellOf = (x, y) => [Math.floor(x / reach), Math.floor(y / reach)];
  for (const { at: [x, y] } of folds) {
    const [cx, cy] = cellOf(x, y);
    let place = null;
    for (let dx = -1; dx <= 1 && !place; dx++) {
      for (let dy = -1; dy <= 1 && !place; dy++) {
        place = (grid.get(`${cx + dx},${cy + dy}`) ?? []).find((p) => Math.hypot(p.start[0] - x, p.start[1] - y) <= reach) ?? null;
      }
    }
    if (!place) {
      place = { start: [x, y], points: [] };
      places.push(place);
      const key = `${cx},${cy}`;
      grid.set(key, [...(grid.get(key) ?? []), place]);
    }
    place.points.push([x, y]);
  }
  const marks = [];
  let hidden = 0;
  for (const { points } of places) {
    let [x0, x1, y0, y1] = [Infinity, -Infinity, Infinity, -Infinity];
    for (const [x, y] of points) [x0, x1, y0, y1] = [Math.min(x0, x), Math.max(x1, x), Math.min(y0, y), Math.max(y1, y)];
    const extent = Math.hypot(x1 - x0, y1 - y0) / unitsPerPixel;
    if (points.length % 2 === 0 && extent < SUB_PIXEL) {
      hidden += points.length;
      continue;
    }
    marks.push({ at: [(x0 + x1) / 2, (y0 + y1) / 2], radius: Math.max(FOLD_RADIUS, extent / 2 + 4) });
  }
  return { marks, counted: folds.length - hidden, hidden };
}

/**
 * Rings the folds of the last report in red (unless the user hid them: a click on the note)
 * and says how many in the status bar, both for the current zoom; `body[data-folds]` is the
 * report's count (for the tests).
 */
export function drawFoldMarks() {
  const folds = editor.viewBoxReport?.folds ?? [];
  document.body.dataset.folds = String(folds.length);
  const { view } = editor;
  if (!view) return;
  const { marks, counted, hidden } = foldMarks(folds, view.unitsPerPixel());
  const shown = editor.shown.folds;
  view.drawFolds(shown ? marks : []);
  editor.foldsShown = shown && marks.length > 0;
  const small = hidden ? `; ${hidden} more below a pixel at this zoom` : '';
  const toggle = shown ? 'click: hide the rings' : 'rings hidden: click to show';
  showNote(
    'fold-note',
    counted || hidden ? `${counted} fold${counted === 1 ? '' : 's'}: an outline crosses itself (red${small}; ${toggle})` : '',
    folds.map((f) => `path ${f.path}: curves ${f.curves[0]} and ${f.curves[1]}`).slice(0, 40).join('\n'),
  );
}

/** A click on the fold note hides the rings, or shows them again. */
export function toggleFoldMarks() {
  editor.shown.folds = !editor.shown.folds;
  drawFoldMarks();
}

export function showViewBoxReport(report) {
  drawFoldMarks();
  const outside = report?.outside ?? [];
  editor.view?.showViewBox(outside.length > 0);
  if (!report) {
    delete document.body.dataset.viewbox;
  } else {
    document.body.dataset.viewbox = outside.length ? 'outside' : 'inside';
  }
  if (!outside.length) {
    showNote('viewbox-note', '');
    return;
  }
  const far = outside[0];
  const n = outside.length;
  const [x, y, w, h] = report.fitted;
  showNote(
    'viewbox-note',
    `${n} path${n === 1 ? '' : 's'} leave${n === 1 ? 's' : ''} the viewBox (dashed), farthest ${far.element} by ${units(far.distance)} units`,
    outside.map((o) => `${o.element}: ${units(o.distance)}`).join('\n') +
      `\n\nExport with viewBox "keep" crops them; "fit art" writes viewBox ${[x, y, w, h].map(units).join(' ')}`,
  );
}
