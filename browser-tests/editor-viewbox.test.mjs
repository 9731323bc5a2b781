// The editor when the deformed art leaves the drawing's viewBox: a drawing of ours (a flower
// in a pot, viewBox 0 0 100 200) opened through the file picker, two handles added, the top one
// dragged 60 units to the right so that the flower leaves the viewBox. The status line must say
// how many paths leave it and how far (the server's report, checked against the page's own
// computation of the exact curve bounds), the viewBox is outlined, and the export must offer
// both choices: "fit the art" writes a viewBox holding every exported path's exact bounds
// (computed here from the exported path data, independently of the library), tight on the
// sides that grew, width and height in proportion; "keep" writes the input's viewBox. The
// label on the flower goes with it in the export: its text element carries a transform that
// takes the flower's rest centre to the centre of the exported flower's exact bounds.

import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { clientPoint, drag } from './editor-page.mjs';
import { launchBrowser, outputFolder, startEditor } from './harness.mjs';

const VIEWPORT = { width: 1100, height: 760 };
// Longest wait for the server (precomputation, uploads), ms.
const WAIT = 60_000;

const VIEW_BOX = [0, 0, 100, 200];
// The label on the flower (its anchor, drawing units), and the flower's centre and radius.
const LABEL = [50, 33];
const FLOWER = { centre: [50, 30], r: 18 };
// Ours: a stem, a flower at its top and a pot at its bottom; width/height in millimetres to
// check that they grow in proportion with a fitted viewBox.
const DRAWING = `<svg xmlns="http://www.w3.org/2000/svg" viewBox="${VIEW_BOX.join(' ')}" width="50mm" height="100mm">
  <path id="stem" d="M50 190 C40 140 60 80 50 30" fill="none" stroke="#2a7d46" stroke-width="4"/>
  <circle id="flower" cx="50" cy="30" r="18" fill="#e0559a"/>
  <rect id="pot" x="30" y="170" width="40" height="25" fill="#a8642f"/>
  <text id="bloom" x="${LABEL[0]}" y="${LABEL[1]}" font-size="8" text-anchor="middle" fill="white">bloom</text>
</svg>
`;
// Handles (drawing units), away from every junction (a click on one changes its kind).
const HANDLES = [[35, 60], [50, 150]];
// The drag of the top handle, drawing units: the flower goes past x = 100.
const DRAG = [60, 0];

const out = outputFolder('editor-viewbox');
let browser;
let server;
let page;

const check = (...args) => out.check(...args);

before(async () => {
  browser = await launchBrowser({ viewport: VIEWPORT });
  server = await startEditor([]);
  page = await browser.context.newPage();
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto(server.url);
  await page.waitForSelector('body[data-booted]', { timeout: WAIT });
});

after(async () => {
  await browser?.close();
  await server?.close();
  out.finish();
});

// ---------------------------------------------------------------------------------------------
// Helpers



/** Cubics of path data made of M, C and Z commands (what the editor and the export write). */
function cubics(d) {
  const tokens = d.match(/[MCZmcz]|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?/g) ?? [];
  const result = [];
  let command = null;
  let numbers = [];
  let current = null;
  let start = null;
  const flush = () => {
    if (command === 'M') {
      current = [numbers[0], numbers[1]];
      start = current;
      numbers = numbers.slice(2); // implicit line-tos do not occur in our output
      assert.equal(numbers.length, 0, `M with more than one point in "${d.slice(0, 60)}"`);
    } else if (command === 'C') {
      assert.equal(numbers.length % 6, 0, `C with ${numbers.length} numbers`);
      for (let k = 0; k < numbers.length; k += 6) {
        const c = [current, [numbers[k], numbers[k + 1]], [numbers[k + 2], numbers[k + 3]], [numbers[k + 4], numbers[k + 5]]];
        result.push(c);
        current = c[3];
      }
    } else if (command === 'Z' || command === 'z') {
      current = start;
    }
    numbers = [];
  };
  for (const t of tokens) {
    if (/^[MCZmcz]$/.test(t)) {
      if (command) flush();
      if (t === 'm' || t === 'c') throw new Error(`relative command ${t} in "${d.slice(0, 60)}"`);
      command = t;
    } else {
      numbers.push(Number(t));
    }
  }
  if (command) flush();
  return result;
}

/**
 * The exact bounding box [x0, y0, x1, y1] of cubic Bézier curves: their end points and the
 * points where a coordinate's derivative, the quadratic 3[(1−t)²(P1−P0) + 2t(1−t)(P2−P1) +
 * t²(P3−P2)], vanishes for t in (0, 1).
 */
function cubicBounds(curves) {
  const box = [Infinity, Infinity, -Infinity, -Infinity];
  const take = (x, y) => {
    box[0] = Math.min(box[0], x);
    box[1] = Math.min(box[1], y);
    box[2] = Math.max(box[2], x);
    box[3] = Math.max(box[3], y);
  };
  const at = (c, t, i) => {
    const s = 1 - t;
    return s * s * s * c[0][i] + 3 * s * s * t * c[1][i] + 3 * s * t * t * c[2][i] + t * t * t * c[3][i];
  };
  for (const c of curves) {
    take(...c[0]);
    take(...c[3]);
    for (const i of [0, 1]) {
      // Derivative / 3 = a t² + b t + k.
      const d0 = c[1][i] - c[0][i];
      const d1 = c[2][i] - c[1][i];
      const d2 = c[3][i] - c[2][i];
      const a = d0 - 2 * d1 + d2;
      const b = 2 * (d1 - d0);
      const k = d0;
      const roots = [];
      if (Math.abs(a) < 1e-12 * (Math.abs(b) + Math.abs(k) + 1e-300)) {
        if (b !== 0) roots.push(-k / b);
      } else {
        const disc = b * b - 4 * a * k;
        if (disc >= 0) {
          const r = Math.sqrt(disc);
          roots.push((-b + r) / (2 * a), (-b - r) / (2 * a));
        }
      }
      for (const t of roots) {
        if (t > 0 && t < 1) take(at(c, t, 0), at(c, t, 1));
      }
    }
  }
  return box;
}

/** The exported document's root attributes and every path's `d`, parsed by the browser. */
function parseExport(p, text) {
  return p.evaluate((t) => {
    const doc = new DOMParser().parseFromString(t, 'image/svg+xml');
    const root = doc.documentElement;
    return {
      error: doc.querySelector('parsererror')?.textContent ?? null,
      viewBox: root.getAttribute('viewBox'),
      width: root.getAttribute('width'),
      height: root.getAttribute('height'),
      paths: [...doc.querySelectorAll('path')].map((e) => ({ id: e.id, d: e.getAttribute('d') })),
      texts: [...doc.querySelectorAll('text')].map((e) => ({ id: e.id, transform: e.getAttribute('transform') })),
    };
  }, text);
}

/** Exports with the viewBox choice `choice`, saves the file as `name`; resolves to its text. */
async function exportWith(choice, name) {
  await page.selectOption('#export-viewbox', choice);
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-svg')]);
  const file = join(out.path, name);
  await download.saveAs(file);
  return readFileSync(file, 'utf8');
}

// ---------------------------------------------------------------------------------------------

let report; // the server's report after the drag

check('dragging the art out of the viewBox is said in the status line and outlined', {}, async () => {
  const file = join(out.path, 'flower.svg');
  writeFileSync(file, DRAWING);
  await page.setInputFiles('#open-file', file);
  await page.waitForFunction(() => document.title.startsWith('flower.svg'), null, { timeout: WAIT });
  await page.waitForSelector('body[data-viewbox="inside"]', { timeout: WAIT });
  assert.ok(await page.isHidden('#viewbox-note'), 'at rest, nothing leaves the viewBox and nothing is said');
  assert.equal(await page.inputValue('#export-viewbox'), 'keep', 'the export keeps the viewBox by default');

  // Alt-click: a pin wherever asked, on the art or not.
  await page.keyboard.down('Alt');
  for (const h of HANDLES) {
    const [x, y] = await clientPoint(page, h);
    await page.mouse.click(x, y);
  }
  await page.keyboard.up('Alt');
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  await drag(page, HANDLES[0], DRAG, 12);
  await page.waitForSelector('body[data-viewbox="outside"]', { timeout: WAIT });

  report = await page.evaluate(() => window.splineskinEditor.viewBoxReport);
  assert.deepEqual(report.view_box, VIEW_BOX);
  assert.ok(report.outside.length >= 1, 'some path leaves');
  // The page's own exact bounds of what it shows agree with the server's report: every path
  // reported sticks out by the amount said, every other path stays inside.
  const shown = await page.evaluate(() =>
    [...document.getElementById('canvas').shadowRoot.querySelectorAll('[data-splineskin-element]')].map((e) => ({
      id: e.id,
      d: e.getAttribute('d'),
    })),
  );
  const digits = await page.evaluate(() => window.splineskinEditor.view.digits);
  const rounding = 10 ** -digits; // the page writes coordinates to `digits` decimals
  const [vx, vy, vw, vh] = VIEW_BOX;
  for (const { id, d } of shown) {
    const [x0, y0, x1, y1] = cubicBounds(cubics(d));
    const overshoot = Math.max(0, vx - x0, x1 - (vx + vw), vy - y0, y1 - (vy + vh));
    const said = report.outside.find((o) => o.element.startsWith(`${id === 'flower' ? 'circle' : id === 'pot' ? 'rect' : 'path'}#${id} `));
    if (overshoot > rounding) {
      assert.ok(said, `${id} leaves by ${overshoot} and is reported`);
      assert.ok(Math.abs(said.distance - overshoot) <= 2 * rounding, `${id}: reported ${said.distance}, shown ${overshoot}`);
    } else {
      assert.ok(!said || said.distance <= 2 * rounding, `${id} stays inside (${overshoot}) but is reported`);
    }
  }
  const far = report.outside[0];
  assert.ok(far.element.startsWith('circle#flower'), `the flower goes farthest: ${far.element}`);
  assert.ok(far.distance > 10, `by more than 10 units: ${far.distance}`);

  // The status line names how many paths and how far.
  const note = await page.textContent('#viewbox-note');
  const n = report.outside.length;
  assert.ok(await page.isVisible('#viewbox-note'), 'the note is shown');
  assert.match(note, new RegExp(`^${n} paths? leaves? the viewBox`), note);
  assert.ok(note.includes(`circle#flower (line 3) by ${Number(far.distance.toPrecision(4))} units`), note);
  assert.ok(
    await page.evaluate(() => document.getElementById('canvas').shadowRoot.querySelector('.ss-view-box').style.display !== 'none'),
    'the viewBox is outlined',
  );
  const shot = join(out.path, 'editor-viewbox-outside.png');
  await page.screenshot({ path: shot });
  console.log(`editor-viewbox: ${note}; screenshot ${shot}`);
});

check('export with "fit the art" writes a viewBox holding every path, "keep" the input\'s', {}, async () => {
  assert.ok(report, 'needs the drag test');
  const fit = await parseExport(page, await exportWith('fit', 'flower-fit.svg'));
  assert.equal(fit.error, null);
  const box = fit.viewBox.trim().split(/[\s,]+/).map(Number);
  assert.equal(box.length, 4);
  const [bx, by, bw, bh] = box;
  const scale = Math.hypot(bw, bh);
  const slack = 1e-9 * scale; // the export writes numbers that read back exactly
  const union = [VIEW_BOX[0], VIEW_BOX[1], VIEW_BOX[0] + VIEW_BOX[2], VIEW_BOX[1] + VIEW_BOX[3]];
  assert.equal(fit.paths.length, 3);
  for (const { id, d } of fit.paths) {
    const [x0, y0, x1, y1] = cubicBounds(cubics(d));
    assert.ok(
      x0 >= bx - slack && y0 >= by - slack && x1 <= bx + bw + slack && y1 <= by + bh + slack,
      `${id}: bounds ${[x0, y0, x1, y1]} outside the fitted viewBox ${box}`,
    );
    union[0] = Math.min(union[0], x0);
    union[1] = Math.min(union[1], y0);
    union[2] = Math.max(union[2], x1);
    union[3] = Math.max(union[3], y1);
  }
  // Tight: the fitted viewBox is the union of the input's and the art's bounds.
  const expected = [union[0], union[1], union[2] - union[0], union[3] - union[1]];
  box.forEach((v, k) => assert.ok(Math.abs(v - expected[k]) <= 1e-6 * scale, `viewBox ${box}, union ${expected}`));
  assert.ok(bw > VIEW_BOX[2] + 10, `it grew: ${box}`);
  // The page announced this viewBox (to its rounding of the points).
  report.fitted.forEach((v, k) => assert.ok(Math.abs(v - box[k]) <= 1e-3, `announced ${report.fitted}, written ${box}`));
  // width and height grow in proportion, in their unit.
  assert.ok(Math.abs(Number.parseFloat(fit.width) - (50 * bw) / VIEW_BOX[2]) < 1e-9 * 50 * bw, `width ${fit.width}`);
  assert.ok(fit.width.endsWith('mm') && fit.height.endsWith('mm'), `${fit.width} ${fit.height}`);
  assert.ok(Math.abs(Number.parseFloat(fit.height) - (100 * bh) / VIEW_BOX[3]) < 1e-9 * 100 * bh, `height ${fit.height}`);
  assert.match(await page.textContent('#message'), /viewBox grown to include the art/);

  const keep = await parseExport(page, await exportWith('keep', 'flower-keep.svg'));
  assert.equal(keep.error, null);
  assert.equal(keep.viewBox, VIEW_BOX.join(' '), 'keep writes the input viewBox');
  assert.equal(keep.width, '50mm');
  assert.equal(keep.height, '100mm');
  assert.deepEqual(keep.paths, fit.paths, 'the same geometry either way');
  assert.match(await page.textContent('#message'), /viewBox kept: art outside it is cropped/);

  // Both exports, rendered by the browser side by side, for a look.
  await page.evaluate(
    ([a, b]) => {
      const box = document.createElement('div');
      box.id = 'viewbox-exports';
      box.style.cssText = 'position:fixed;inset:0;display:flex;align-items:flex-start;gap:20px;padding:20px;background:#eee;z-index:100';
      for (const [label, text] of [['fit', a], ['keep', b]]) {
        const figure = document.createElement('figure');
        figure.style.cssText = 'margin:0;background:white;outline:1px solid #999';
        const img = document.createElement('img');
        img.src = `data:image/svg+xml;charset=utf-8,${encodeURIComponent(text)}`;
        img.style.cssText = 'height:600px;display:block';
        const caption = document.createElement('figcaption');
        caption.textContent = `viewBox ${label}`;
        figure.append(img, caption);
        box.append(figure);
      }
      document.body.append(box);
    },
    [readFileSync(join(out.path, 'flower-fit.svg'), 'utf8'), readFileSync(join(out.path, 'flower-keep.svg'), 'utf8')],
  );
  await page.waitForFunction(() => [...document.querySelectorAll('#viewbox-exports img')].every((i) => i.complete));
  const shot = join(out.path, 'editor-viewbox-exports.png');
  await page.screenshot({ path: shot });
  await page.evaluate(() => document.getElementById('viewbox-exports').remove());
  console.log(`editor-viewbox: fitted viewBox ${box}; screenshot ${shot}`);
});

check('the exported label follows the flower it is on', {}, async () => {
  assert.ok(report, 'needs the drag test');
  const exported = await parseExport(page, readFileSync(join(out.path, 'flower-keep.svg'), 'utf8'));
  const label = exported.texts.find((t) => t.id === 'bloom');
  assert.ok(label, 'the label is exported');
  const m = /^matrix\(([^)]*)\)$/.exec(label.transform ?? '');
  assert.ok(m, `the label carries the deformation's map: transform="${label.transform}"`);
  const [a, b, c, d, e, f] = m[1].trim().split(/[\s,]+/).map(Number);
  const map = ([x, y]) => [a * x + c * y + e, b * x + d * y + f];
  // The flower, exported: the centre of its exact bounds.
  const flower = exported.paths.find((p) => p.id === 'flower');
  const [x0, y0, x1, y1] = cubicBounds(cubics(flower.d));
  const centre = [(x0 + x1) / 2, (y0 + y1) / 2];
  const carried = map(FLOWER.centre);
  const miss = Math.hypot(carried[0] - centre[0], carried[1] - centre[1]);
  const atRest = Math.hypot(FLOWER.centre[0] - centre[0], FLOWER.centre[1] - centre[1]);
  // The flower moves about as far as the drag (60 units); the label's map lands within a tenth
  // of the flower's radius of its centre.
  assert.ok(atRest > 30, `the flower moved: ${atRest}`);
  assert.ok(miss < 0.1 * FLOWER.r, `the label's map takes the flower's centre ${miss} from the exported flower's`);
  console.log(`editor-viewbox: label transform ${label.transform}; ${miss.toFixed(3)} units from the flower's centre (${atRest.toFixed(1)} at rest)`);
});

// A square whose corner pin is dragged across the opposite side folds its outline over
// itself: the page rings the crossings in red at the positions the server reports, on the
// crossing, and says how many; dragged back, the rings and the note go.
const SQUARE = `<svg xmlns="http://www.w3.org/2000/svg" viewBox="-20 -20 60 60">
  <path id="square" d="M0 0 L20 0 L20 20 L0 20 Z" fill="#c84"/>
</svg>
`;
const CORNERS = [[0, 0], [20, 0], [20, 20], [0, 20]];

check('a fold is ringed in red where the outline crosses itself, and cleared when undone', {}, async () => {
  const file = join(out.path, 'square.svg');
  writeFileSync(file, SQUARE);
  await page.setInputFiles('#open-file', file);
  await page.waitForFunction(() => document.title.startsWith('square.svg'), null, { timeout: WAIT });
  await page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(() => ok()))));
  await page.waitForSelector('body[data-folds="0"]', { timeout: WAIT });
  await page.keyboard.down('Alt');
  for (const h of CORNERS) {
    const [x, y] = await clientPoint(page, h);
    await page.mouse.click(x, y);
  }
  await page.keyboard.up('Alt');
  const pins = await page.evaluate(() => window.splineskinEditor.scene.handles.length);
  assert.equal(pins, 4, 'a pin at every corner');
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  // Corner (20, 20) to (−10, 10): across the left side.
  await drag(page, CORNERS[2], [-30, -10], 12);
  await page.waitForFunction(() => Number(document.body.dataset.folds) > 0, null, { timeout: WAIT });
  const report = await page.evaluate(() => window.splineskinEditor.viewBoxReport);
  assert.ok(report.folds.length > 0);
  for (const f of report.folds) {
    // On the crossing: within the box of the dragged sides.
    assert.ok(f.at[0] >= -10 && f.at[0] <= 20 && f.at[1] >= 0 && f.at[1] <= 20, JSON.stringify(f));
  }
  const rings = await page.evaluate(() => document.getElementById('canvas').shadowRoot.querySelector('.ss-folds').getAttribute('d'));
  assert.equal((rings.match(/M/g) ?? []).length, report.folds.length, `one ring per fold: ${rings}`);
  const note = await page.textContent('#fold-note');
  assert.ok(await page.isVisible('#fold-note'), 'the fold note is shown');
  assert.match(note, new RegExp(`^${report.folds.length} folds?: an outline crosses itself`), note);
  const shot = join(out.path, 'editor-fold.png');
  await page.screenshot({ path: shot });
  console.log(`editor-viewbox: ${note} at ${report.folds.map((f) => f.at.map((v) => v.toFixed(2)).join(',')).join('; ')}; screenshot ${shot}`);
  // A click on the note hides the rings, another shows them again.
  const ringsNow = () => page.evaluate(() => document.getElementById('canvas').shadowRoot.querySelector('.ss-folds').getAttribute('d'));
  await page.click('#fold-note');
  assert.equal(await ringsNow(), '', 'hidden');
  assert.match(await page.textContent('#fold-note'), /rings hidden: click to show/);
  await page.click('#fold-note');
  assert.equal(await ringsNow(), rings, 'shown again');
  // Back where it was: no fold.
  await drag(page, [-10, 10], [30, 10], 12);
  await page.waitForSelector('body[data-folds="0"]', { timeout: WAIT });
  assert.ok(await page.isHidden('#fold-note'), 'no note without folds');
  const cleared = await page.evaluate(() => document.getElementById('canvas').shadowRoot.querySelector('.ss-folds').getAttribute('d'));
  assert.equal(cleared, '', 'the rings are cleared');
});

check('folds close together are ringed as one place, and loops below a pixel at the zoom are not counted', {}, async () => {
  const result = await page.evaluate(async () => {
    const { foldMarks } = await import('./viewbox.js');
    const fold = (x, y) => ({ path: 0, curves: [0, 1], at: [x, y] });
    // At 1 unit per pixel: three loops of two crossings within 0.2 px, two crossings 100 px
    // apart, and five crossings within 5 px of each other (far from the others).
    const tiny = [0, 1, 2].flatMap((k) => [fold(1000 + 40 * k + 0.05, 500.05), fold(1000 + 40 * k + 0.15, 500.15)]);
    const apart = [fold(100, 100), fold(200, 100)];
    const bunch = [0, 1, 2, 3, 4].map((k) => fold(600.2 + k, 600.5 + 0.5 * k));
    const at1 = foldMarks([...tiny, ...apart, ...bunch], 1);
    // Zoomed in 100 times (0.01 units per pixel) the tiny loops are 14 px across: counted.
    const at100 = foldMarks(tiny, 0.01);
    return { at1, at100 };
  });
  const { at1, at100 } = result;
  assert.equal(at1.hidden, 6, 'the three sub-pixel loops are set aside');
  assert.equal(at1.counted, 7);
  assert.equal(at1.marks.length, 3, `one ring each for the two apart, one for the bunch: ${JSON.stringify(at1.marks)}`);
  const bunch = at1.marks.find((m) => m.at[0] > 500 && m.at[0] < 700);
  assert.ok(bunch && bunch.radius >= 9, 'the bunch ringed at least as large as one fold');
  assert.equal(at100.hidden, 0);
  assert.equal(at100.counted, 6);
});
