// Adaptive control points in the editor: a drawing of ours (one long stroke drawn as a single
// cubic, a stem) with three pins and inverse-distance weights. The top pin dragged sideways bends
// the stem into an S that one cubic cannot follow: the page's curve is measured against the
// skinned target computed here from the weights' formula (w_i ∝ 1/|x − p_i|², the target
// Σ w_i(x) T_i x of every rest point x), far off at first. With "add control points" on, the
// stem is split at rest where it falls short: the shown curve then follows the target within
// the tolerance, the artist's two anchors stay where they were, the inserted ones are ringed
// among the junctions and listed in the export's data-splineskin-inserted, and turning it off
// brings back the single cubic and its rig.

import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { clientPoint, drag, WAIT } from './editor-page.mjs';
import { launchBrowser, outputFolder, startEditor } from './harness.mjs';

const VIEWPORT = { width: 1100, height: 760 };
const VIEW_BOX = [0, 0, 100, 200];
const STEM = [[50, 190], [40, 140], [60, 80], [50, 30]];
const DRAWING = `<svg xmlns="http://www.w3.org/2000/svg" viewBox="${VIEW_BOX.join(' ')}">
  <path id="stem" d="M${STEM[0].join(' ')} C${STEM.slice(1).flat().join(' ')}" fill="none" stroke="#2a7d46" stroke-width="4"/>
</svg>
`;
// Pins off the stem's junctions (Alt-click places them anywhere): top, middle, bottom.
const HANDLES = [[50, 40], [52, 110], [50, 180]];
// The top pin's drag: the stem's top goes 45 units to the right, its middle and foot stay.
const DRAG = [45, 0];
// The tolerance asked, a fraction of the drawing's diagonal (the page's default).
const TOLERANCE = 1e-3;

const out = outputFolder('editor-adaptive');
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

/** The point of cubic `c` (four [x, y]) at `t`. */
function bezier(c, t) {
  const s = 1 - t;
  const w = [s * s * s, 3 * s * s * t, 3 * s * t * t, t * t * t];
  return [0, 1].map((i) => w.reduce((sum, wk, k) => sum + wk * c[k][i], 0));
}

/** The skinned target of rest point x: Σ w_i(x) T_i x, w_i ∝ 1/|x − p_i|² (Shepard, exponent 2). */
function skinned(x, handles, pose) {
  const w = handles.map((p) => 1 / ((x[0] - p[0]) ** 2 + (x[1] - p[1]) ** 2));
  const total = w.reduce((a, b) => a + b, 0);
  const out = [0, 0];
  pose.forEach(([a, b, c, d, e, f], i) => {
    out[0] += (w[i] / total) * (a * x[0] + c * x[1] + e);
    out[1] += (w[i] / total) * (b * x[0] + d * x[1] + f);
  });
  return out;
}

/** The shown chain points as cubics. */
function chainCubics(points) {
  const cubics = [];
  for (let k = 0; k + 6 < points.length; k += 6) {
    cubics.push([0, 1, 2, 3].map((j) => [points[k + 2 * j], points[k + 2 * j + 1]]));
  }
  return cubics;
}

/**
 * The largest distance from the target (dense samples of the skinned rest stem) to the shown
 * curve (dense samples of its cubics): the closest-point distance the fit's tolerance bounds.
 */
function targetDistance(state) {
  const shown = chainCubics(state.points).flatMap((c) => Array.from({ length: 401 }, (_, k) => bezier(c, k / 400)));
  let worst = 0;
  for (let k = 0; k <= 400; k++) {
    const t = skinned(bezier(STEM, k / 400), state.handles, state.pose);
    let best = Infinity;
    for (const p of shown) best = Math.min(best, Math.hypot(p[0] - t[0], p[1] - t[1]));
    worst = Math.max(worst, best);
  }
  return worst;
}

/** What the tests read of the page. */
function state() {
  return page.evaluate(() => {
    const e = window.splineskinEditor;
    return {
      points: [...e.points],
      rest: [...e.rest],
      handles: e.scene.handles,
      pose: e.scene.pose,
      info: { id: e.info.id, n_curves: e.info.n_curves, paths: e.info.paths },
      rig: e.rig?.id ?? null,
      answers: e.adaptive.answers,
    };
  });
}

// The diagonal the tolerance is a fraction of: the stem's control points' bounding box.
const xs = STEM.map((p) => p[0]);
const ys = STEM.map((p) => p[1]);
const DIAGONAL = Math.hypot(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys));

let bent; // the page's state with the single cubic, bent
let refined; // the same pose with control points added

check('a stem bent into an S is split where it falls short, keeping its anchors', {}, async () => {
  const file = join(out.path, 'stem.svg');
  writeFileSync(file, DRAWING);
  await page.setInputFiles('#open-file', file);
  await page.waitForFunction(() => document.title.startsWith('stem.svg'), null, { timeout: WAIT });
  await page.selectOption('#family', 'shepard');
  await page.keyboard.down('Alt');
  for (const h of HANDLES) {
    const [x, y] = await clientPoint(page, h);
    await page.mouse.click(x, y);
  }
  await page.keyboard.up('Alt');
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  await drag(page, HANDLES[0], DRAG, 10);
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  bent = await state();
  assert.equal(bent.info.n_curves, 1);
  const before = targetDistance(bent);
  // One cubic cannot follow the S: far beyond the tolerance.
  assert.ok(before > 5 * TOLERANCE * DIAGONAL, `one cubic is off by ${before} (tolerance ${TOLERANCE * DIAGONAL})`);

  await page.check('#adaptive');
  await page
    .waitForFunction(() => window.splineskinEditor.info.n_curves > 1, null, { timeout: WAIT })
    .catch(async (e) => {
      const seen = await page.evaluate(() => ({
        status: document.getElementById('message').textContent,
        error: document.getElementById('error').textContent,
        refine: document.body.dataset.refine ?? null,
        answers: window.splineskinEditor.adaptive.answers,
      }));
      throw new Error(`no control points added: ${JSON.stringify(seen)} (${e.message})`);
    });
  await page.waitForSelector('body[data-refine="idle"]', { timeout: WAIT });
  refined = await state();
  const answer = refined.answers.at(-1);
  assert.equal(answer.refined, true);
  assert.ok(answer.met && answer.worst <= TOLERANCE, `the server's fit is within ${answer.worst}`);
  assert.deepEqual(refined.pose, bent.pose, 'the pose is kept');
  assert.notEqual(refined.rig, bent.rig, 'the refined drawing has its own rig');
  const after = targetDistance(refined);
  // The closest-point distance is at most the parametric one the server bounds (and the
  // sampling here adds a little).
  assert.ok(after <= 1.05 * TOLERANCE * DIAGONAL, `the refined stem is off by ${after} (tolerance ${TOLERANCE * DIAGONAL})`);
  // The artist's anchors, at rest, where they were; as many inserted as curves added.
  const flags = refined.info.paths[0].inserted;
  const n = refined.info.n_curves;
  assert.equal(flags.length, n + 1);
  assert.equal(flags.filter((b) => b).length, n - 1);
  assert.deepEqual([flags[0], flags[n]], [false, false]);
  for (const [j, k] of [[0, 0], [n, 3]]) {
    for (const i of [0, 1]) assert.ok(Math.abs(refined.rest[6 * j + i] - STEM[k][i]) <= 1e-12 * DIAGONAL, `anchor ${k} moved`);
  }
  // The rest pieces trace the input curve: each inserted anchor is a point of the stem.
  for (let j = 1; j < n; j++) {
    const a = [refined.rest[6 * j], refined.rest[6 * j + 1]];
    let best = Infinity;
    for (let k = 0; k <= 20000; k++) {
      const p = bezier(STEM, k / 20000);
      best = Math.min(best, Math.hypot(p[0] - a[0], p[1] - a[1]));
    }
    assert.ok(best <= 1e-3, `inserted anchor ${j} off the stem by ${best}`);
  }
  console.log(
    `editor-adaptive: one cubic off by ${before.toFixed(3)} units, ${n} curves off by ${after.toFixed(4)} ` +
      `(tolerance ${(TOLERANCE * DIAGONAL).toFixed(4)}; server's parametric worst ${(answer.worst * DIAGONAL).toFixed(4)})`,
  );
});

check('the inserted anchors are ringed among the junctions and marked in the export', {}, async () => {
  assert.ok(refined, 'needs the refinement test');
  await page.check('#show-junctions');
  const rings = await page.evaluate(
    () => document.getElementById('canvas').shadowRoot.querySelector('.ss-junctions.inserted').getAttribute('d') ?? '',
  );
  const n = refined.info.n_curves;
  assert.equal((rings.match(/M/g) ?? []).length, n - 1, 'one ring per inserted anchor');
  const shot = join(out.path, 'editor-adaptive.png');
  await page.screenshot({ path: shot });
  await page.uncheck('#show-junctions');
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-svg')]);
  const file = join(out.path, 'stem-deformed.svg');
  await download.saveAs(file);
  const svg = readFileSync(file, 'utf8');
  const marks = svg.match(/data-splineskin-inserted="([^"]*)"/);
  assert.ok(marks, 'the export lists the inserted anchors');
  const flags = refined.info.paths[0].inserted;
  const listed = flags.flatMap((b, k) => (b ? [`0:${k}`] : []));
  assert.equal(marks[1], listed.join(' '));
  const d = svg.match(/<path[^>]* d="([^"]*)"/)[1];
  const numbers = d.match(/[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?/g) ?? [];
  assert.equal(numbers.length, 2 + 6 * n, `the exported stem has ${n} cubics: ${d}`);
  console.log(`editor-adaptive: screenshot ${shot}; export marks ${marks[1]}`);
});

check('turning it off brings back the drawing as opened and its rig', {}, async () => {
  assert.ok(refined, 'needs the refinement test');
  await page.uncheck('#adaptive');
  await page.waitForFunction(() => window.splineskinEditor.info.n_curves === 1, null, { timeout: WAIT });
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  const back = await state();
  assert.equal(back.rig, bent.rig, 'the first rig is used again (nothing changed that it depends on)');
  assert.deepEqual(back.points, bent.points, 'the single cubic, bent as before');
});
