// The viewBox: whether the deformed art leaves the document's viewBox and where outlines fold
// over themselves (the server's report after each change), said in the status bar and ringed
// on the drawing.

import * as api from './api.js';
import { showError } from './messages.js';
import { editor } from './store.js';

const $ = (id) => document.getElementById(id);

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

/**
 * Rings the folds of the report in red and says how many in the status line;
 * `body[data-folds]` is their count (for the tests).
 */
function showFolds(report) {
  const folds = report?.folds ?? [];
  editor.view?.drawFolds(folds.map((f) => f.at));
  editor.foldsShown = folds.length > 0;
  document.body.dataset.folds = String(folds.length);
  const note = $('fold-note');
  note.hidden = folds.length === 0;
  note.textContent = folds.length
    ? `${folds.length} fold${folds.length === 1 ? '' : 's'}: an outline crosses itself (red)`
    : '';
  note.title = folds.map((f) => `path ${f.path}: curves ${f.curves[0]} and ${f.curves[1]}`).join('\n');
}

export function showViewBoxReport(report) {
  showFolds(report);
  const note = $('viewbox-note');
  const outside = report?.outside ?? [];
  editor.view?.showViewBox(outside.length > 0);
  if (!report) {
    delete document.body.dataset.viewbox;
  } else {
    document.body.dataset.viewbox = outside.length ? 'outside' : 'inside';
  }
  note.hidden = outside.length === 0;
  if (!outside.length) {
    note.textContent = '';
    return;
  }
  const far = outside[0];
  const n = outside.length;
  note.textContent =
    `${n} path${n === 1 ? '' : 's'} leave${n === 1 ? 's' : ''} the viewBox (dashed), ` +
    `farthest ${far.element} by ${units(far.distance)} units`;
  const [x, y, w, h] = report.fitted;
  note.title =
    outside.map((o) => `${o.element}: ${units(o.distance)}`).join('\n') +
    `\n\nExport with viewBox "keep" crops them; "fit art" writes viewBox ${[x, y, w, h].map(units).join(' ')}`;
}
