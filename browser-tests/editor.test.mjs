// `splineskin serve` in a real browser: the binary is started, the page loaded in chromium, a
// drawing opened through the file picker, two handles added by clicking and one dragged with
// the mouse. The drawing's path data (read back from the DOM) must change, every smooth
// junction must keep its tangents parallel (as drawn), and the exported SVG must read back
// with the same curves. A malformed upload must show an error while the server goes on
// serving. On the paper authors' turtles (1 323 curves) the time of each frame drawn while
// dragging is measured in the page and printed (not asserted: timing depends on the machine).

import assert from 'node:assert/strict';
import { existsSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { clientPoint, drag, editorState, median, openThroughPicker, pathData } from './editor-page.mjs';
import { launchBrowser, outputFolder, REPO, splineskinOutput, startEditor } from './harness.mjs';

const ASSETS = join(REPO, 'crates', 'splineskin', 'assets');
const DEMO_SVG = join(ASSETS, 'demo.svg');
const TURTLES = join(
  REPO, '..', 'shared', 'data', 'vectorskinning', 'turtle-seven-stack', 'comparison', 'shepard ours',
  'turtles-seven-deformation.json',
);

const VIEWPORT = { width: 1100, height: 760 };
// Where the two handles go on the fish (drawing units): its head and the root of its tail,
// each more than 20 units from any junction (a click on a junction changes its kind).
const HANDLES = [[440, 215], [150, 210]];
// The drag of the head handle, drawing units.
const DRAG = [40, -50];
// A vertex moved by less than this (drawing units) has not moved.
const MOVED = 1;
// Longest wait for the server (precomputation, uploads), ms.
const WAIT = 60_000;

const out = outputFolder('editor');
let browser;
let server;
let page;

/** A test whose failure keeps the outputs folder. */
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





/**
 * Subpaths of path data made of M, C and Z commands (what the editor and our export write),
 * each as its list of points [x, y].
 */
function parseSubpaths(d) {
  const tokens = d.match(/[MCZmcz]|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?/g) ?? [];
  const subpaths = [];
  let current = null;
  let command = null;
  let numbers = [];
  const flush = () => {
    for (let k = 0; k + 1 < numbers.length; k += 2) current.push([numbers[k], numbers[k + 1]]);
    numbers = [];
  };
  for (const t of tokens) {
    if (/^[MCZmcz]$/.test(t)) {
      if (current) flush();
      command = t;
      if (t === 'M') {
        current = [];
        subpaths.push(current);
      } else if (t !== 'C' && t !== 'Z') {
        throw new Error(`unexpected path command ${t} in ${d.slice(0, 80)}`);
      }
    } else {
      numbers.push(Number(t));
    }
  }
  if (current) flush();
  assert.ok(command !== null || d.trim() === '', `no commands in "${d.slice(0, 80)}"`);
  return subpaths;
}

/** Chain points of every path (in drawing order) from the DOM's path data. */
function chainsFromDom(info, data) {
  const chains = new Array(info.paths.length);
  info.elements.forEach((e, k) => {
    const subpaths = parseSubpaths(data[k] ?? '');
    assert.equal(subpaths.length, e.end_path - e.first_path, `element ${k}: subpaths`);
    // Back to root user space (the DOM holds each element's local coordinates).
    const [a, b, c, d, ee, f] = e.to_local;
    const det = a * d - b * c;
    const toRoot = ([x, y]) => {
      const u = x - ee;
      const v = y - f;
      return [(d * u - c * v) / det, (-b * u + a * v) / det];
    };
    subpaths.forEach((s, i) => (chains[e.first_path + i] = s.map(toRoot)));
  });
  return chains;
}

/**
 * The signed angle (radians) from the incoming to the outgoing tangent at joint `joint` of a
 * chain, each tangent taken to the first control point distinct from the junction (as the
 * library's classification does), or null when a side has none.
 */
function junctionAngle(chain, closed, joint, eps) {
  const m = chain.length - 1;
  const p = 3 * joint;
  const centre = chain[p];
  const far = (q) => Math.hypot(q[0] - centre[0], q[1] - centre[1]) > eps;
  const before = [1, 2, 3].map((k) => chain[(p === 0 ? m : p) - k]).find((q) => q && far(q));
  const after = [1, 2, 3].map((k) => chain[(p === m ? 0 : p) + k]).find((q) => q && far(q));
  if (!before || !after || (!closed && (joint === 0 || p === m))) return null;
  const u = [centre[0] - before[0], centre[1] - before[1]];
  const v = [after[0] - centre[0], after[1] - centre[1]];
  return { angle: Math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1]), lu: Math.hypot(...u), lv: Math.hypot(...v) };
}



// ---------------------------------------------------------------------------------------------

let demo; // { info, restData, movedData }

check('the page opens a drawing, adds two handles, and the drawing follows a dragged one', {}, async () => {
  await openThroughPicker(page, DEMO_SVG);
  const { info, scene } = await editorState(page);
  assert.equal(scene.handles.length, 0, 'an SVG opens without handles');
  const restData = await pathData(page);
  assert.equal(restData.length, info.elements.length);

  for (const h of HANDLES) {
    const [x, y] = await clientPoint(page, h);
    await page.mouse.click(x, y);
  }
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  const placed = (await editorState(page)).scene;
  assert.equal(placed.handles.length, 2, 'two clicks, two handles');
  placed.handles.forEach((h, i) => {
    assert.ok(Math.hypot(h[0] - HANDLES[i][0], h[1] - HANDLES[i][1]) < 1, `handle ${i} at ${h}`);
  });
  assert.deepEqual(await pathData(page), restData, 'identity pose: the drawing is unchanged');

  await drag(page, HANDLES[0], DRAG, 12);
  const moved = await editorState(page);
  const T = moved.scene.pose[0];
  assert.ok(Math.abs(T[4] - DRAG[0]) < 1 && Math.abs(T[5] - DRAG[1]) < 1, `handle 0 moved by ${T.slice(4)}`);
  const movedData = await pathData(page);
  const restChains = chainsFromDom(info, restData);
  const movedChains = chainsFromDom(info, movedData);
  let movedPoints = 0;
  restChains.forEach((chain, p) => {
    assert.equal(movedChains[p].length, chain.length, `path ${p}: the same number of points`);
    chain.forEach((q, k) => {
      if (Math.hypot(movedChains[p][k][0] - q[0], movedChains[p][k][1] - q[1]) > MOVED) movedPoints++;
    });
  });
  const total = restChains.reduce((n, c) => n + c.length, 0);
  console.log(`editor: ${movedPoints} of ${total} chain points moved by more than ${MOVED}`);
  assert.ok(movedPoints > total / 4, 'the drag moved the drawing');

  // Smooth junctions (C¹, G¹; no overrides here) keep their tangents as parallel as drawn.
  // The DOM's coordinates are rounded to `digits` decimals: a tangent of length l may turn by
  // up to about 2·(√2/2·10^-digits)/l from rounding alone.
  const digits = await page.evaluate(() => window.splineskinEditor.view.digits);
  const rounding = Math.SQRT2 * 0.5 * 10 ** -digits;
  let smooth = 0;
  let worst = 0;
  info.paths.forEach((path, p) => {
    path.joints.forEach((kind, joint) => {
      if (kind !== 'C1' && kind !== 'G1') return;
      const eps = 1e-6;
      const rest = junctionAngle(restChains[p], path.closed, joint, eps);
      const now = junctionAngle(movedChains[p], path.closed, joint, eps);
      if (!rest || !now) return;
      smooth++;
      const tolerance = 2 * rounding * (1 / now.lu + 1 / now.lv + 1 / rest.lu + 1 / rest.lv) + 1e-9;
      const change = Math.abs(now.angle - rest.angle);
      worst = Math.max(worst, change);
      assert.ok(
        change <= tolerance,
        `path ${p} joint ${joint} (${kind}): tangent angle ${rest.angle} at rest, ${now.angle} dragged (tolerance ${tolerance})`,
      );
    });
  });
  console.log(`editor: ${smooth} smooth junctions keep their tangent angle (largest change ${worst.toExponential(2)} rad)`);
  assert.ok(smooth >= 10, `the fish has smooth junctions (${smooth} checked)`);

  const shot = join(out.path, 'editor-fish-dragged.png');
  await page.screenshot({ path: shot });
  console.log(`editor: screenshot ${shot}`);
  demo = { info, restData, movedData };
});

check('the exported SVG reads back with the same curves and the geometry shown', {}, async () => {
  assert.ok(demo, 'needs the drag test');
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-svg')]);
  const file = join(out.path, 'fish-deformed.svg');
  await download.saveAs(file);
  const text = readFileSync(file, 'utf8');
  // The browser parses it as SVG.
  const parsed = await page.evaluate((t) => {
    const doc = new DOMParser().parseFromString(t, 'image/svg+xml');
    return { error: doc.querySelector('parsererror')?.textContent ?? null, root: doc.documentElement.localName };
  }, text);
  assert.equal(parsed.error, null);
  assert.equal(parsed.root, 'svg');
  // The library reads it with as many curves as the drawing had.
  const summary = await splineskinOutput(['info', file]);
  const original = await splineskinOutput(['info', DEMO_SVG]);
  const curves = (s) => Number(/(\d+) curves in (\d+) paths/.exec(s)?.[1] ?? /(\d+) curves/.exec(s)?.[1]);
  assert.equal(curves(summary), demo.info.n_curves, `exported: ${summary.split('\n').slice(-3).join(' | ')}`);
  assert.equal(curves(original), demo.info.n_curves);
  // Its geometry is the one shown: the export and the page's document have the same elements
  // in the same order, and each imported element's points agree to the page's rounding.
  const pairs = await page.evaluate((t) => {
    const exported = [...new DOMParser().parseFromString(t, 'image/svg+xml').querySelectorAll('path')];
    const shown = [...document.getElementById('canvas').shadowRoot.querySelectorAll('path')].filter((e) => !e.closest('.ss-overlay'));
    return {
      counts: [exported.length, shown.length],
      pairs: shown
        .map((e, i) => [e.getAttribute('data-splineskin-element'), e.getAttribute('d'), exported[i]?.getAttribute('d')])
        .filter(([k]) => k !== null),
    };
  }, text);
  assert.equal(pairs.counts[0], pairs.counts[1], 'as many paths exported as shown');
  assert.equal(pairs.pairs.length, demo.info.elements.length);
  const digits = await page.evaluate(() => window.splineskinEditor.view.digits);
  let largest = 0;
  for (const [k, shownData, exportedData] of pairs.pairs) {
    const a = parseSubpaths(shownData).flat();
    const b = parseSubpaths(exportedData).flat();
    assert.equal(a.length, b.length, `element ${k}: points`);
    a.forEach((q, i) => (largest = Math.max(largest, Math.abs(q[0] - b[i][0]), Math.abs(q[1] - b[i][1]))));
  }
  assert.ok(largest <= 0.5 * 10 ** -digits + 1e-9, `exported and shown points differ by ${largest}`);
  // The text, styles and gradients of the original are kept; the text follows the dragged
  // pose by a transform written after its own attributes.
  const source = readFileSync(DEMO_SVG, 'utf8');
  for (const kept of source.match(/<(linearGradient|radialGradient|text)\b[^>]*>/g) ?? []) {
    const expected = kept.startsWith('<text') ? `${kept.slice(0, -1)} transform="matrix(` : kept;
    assert.ok(text.includes(expected), `export keeps ${kept} (as ${expected})`);
  }
});

check('a malformed SVG upload shows an error and the server keeps serving', {}, async () => {
  const bad = join(out.path, 'broken.svg');
  writeFileSync(bad, '<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C 10 10 20"/><g>');
  await page.setInputFiles('#open-file', bad);
  await page.waitForSelector('#error:not([hidden])', { timeout: WAIT });
  const message = await page.textContent('#error');
  console.log(`editor: the page says: ${message}`);
  assert.match(message, /broken\.svg/, 'the message names the file');
  // The drawing shown before stays, and the server answers the next requests.
  const { info } = await editorState(page);
  assert.equal(info.name, 'demo.svg');
  const response = await fetch(`${server.url}api/initial`);
  assert.equal(response.status, 200);
  await openThroughPicker(page, DEMO_SVG);
  assert.equal((await editorState(page)).info.name, 'demo.svg');
});

check('a drawing\'s CSS and ids stay inside it: the page keeps its toolbar and buttons', {}, async () => {
  const hostile = join(out.path, 'hostile.svg');
  writeFileSync(
    hostile,
    '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">' +
      '<style>button, header, #toolbar { display: none !important } path { stroke: red }</style>' +
      '<path id="export-svg" d="M10 50 C30 10 70 10 90 50" fill="none" stroke="black"/>' +
      '<script>document.title = "script ran"</script></svg>',
  );
  await openThroughPicker(page, hostile);
  assert.ok(await page.isVisible('#toolbar'), 'the toolbar is shown');
  assert.ok(await page.isVisible('button#export-svg'), 'the export button is shown');
  assert.equal(await page.evaluate(() => document.getElementById('export-svg').localName), 'button');
  assert.equal(await page.evaluate(() => document.title), 'hostile.svg — splineskin editor', 'no script ran');
  await openThroughPicker(page, DEMO_SVG);
});

// Without ../shared/data this test skips, except when CI is set: then it runs and fails.
const TURTLES_MISSING = !existsSync(TURTLES) && !process.env.CI && `${TURTLES} is missing`;

check('turtles: frame time while dragging (the authors\' 1 300-curve drawing, 3 handles)', { skip: TURTLES_MISSING }, async () => {
  const turtles = await startEditor([TURTLES]);
  const p = await browser.context.newPage();
  try {
    await p.goto(turtles.url);
    await p.waitForSelector('body[data-booted]', { timeout: WAIT });
    await p.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
    const { info, scene } = await editorState(p);
    console.log(`turtles: ${info.n_curves} curves, ${info.rest.length / 2} chain points, ${scene.handles.length} handles`);
    const before = await pathData(p);
    await p.evaluate(() => {
      const e = window.splineskinEditor;
      e.frameTimes.length = 0;
      e.productTimes.length = 0;
    });
    const posed = await p.evaluate(() => {
      const e = window.splineskinEditor;
      const [T, h] = [e.scene.pose[0], e.scene.handles[0]];
      return [T[0] * h[0] + T[2] * h[1] + T[4], T[1] * h[0] + T[3] * h[1] + T[5]];
    });
    const size = Math.max(info.view_box[2], info.view_box[3]);
    await drag(p, posed, [0.08 * size, 0.05 * size], 60);
    const times = await p.evaluate(() => ({
      frame: window.splineskinEditor.frameTimes,
      product: window.splineskinEditor.productTimes,
    }));
    // Frames are drawn at the display's pace (requestAnimationFrame), so how many of the 60
    // moves get one depends on the machine's load: the count is printed, not asserted beyond
    // "the drag drew" (it fell under 30 in about one run in five on a loaded 2-core machine).
    assert.ok(times.frame.length > 0, 'no frame drawn while dragging');
    console.log(
      `turtles: per-frame update in the page, median of ${times.frame.length} frames: ` +
        `${median(times.product).toFixed(3)} ms product O·vec(T), ` +
        `${median(times.frame).toFixed(3)} ms product + path data`,
    );
    const after = await pathData(p);
    assert.notDeepEqual(after, before, 'the drag moved the turtles');
    if (scene.flexible) {
      await p.waitForSelector('body[data-solve="done"]', { timeout: WAIT });
    }
    const shot = join(out.path, 'editor-turtles-dragged.png');
    await p.screenshot({ path: shot });
    console.log(`turtles: screenshot ${shot}`);
    // A reload while the server precomputes (harmonic weights on the turtles' domain): the
    // page comes back and the server serves it.
    await p.selectOption('#family', 'harmonic');
    assert.notEqual(await p.evaluate(() => document.body.dataset.rig), 'ready', 'precomputing');
    await p.reload();
    await p.waitForSelector('body[data-booted]', { timeout: WAIT });
    await p.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
    // Bounded biharmonic weights: the progress bar names the stages the server reports
    // (printed; how many a poll catches depends on the machine).
    await p.evaluate(() => (window.splineskinEditor.stagesSeen.length = 0));
    const started = Date.now();
    await p.selectOption('#family', 'bbw');
    await p.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
    const stages = await p.evaluate(() => window.splineskinEditor.stagesSeen.join(', '));
    console.log(`turtles: bbw weights and rig in ${((Date.now() - started) / 1000).toFixed(1)} s; stages shown: ${stages || 'none'}`);

    // A new handle with bbw weights: an inverse-distance rig stands in at once and follows a
    // drag; the bbw rig replaces it without touching the pose, and the drawing is then its
    // product at that pose (flexible G¹ off, so that the product is what is drawn).
    await p.setChecked('#flexible', false);
    await p.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
    await p.evaluate(() => {
      window.splineskinEditor.rigStates = [];
      new MutationObserver(() => window.splineskinEditor.rigStates.push(document.body.dataset.rig)).observe(
        document.body,
        { attributes: true, attributeFilter: ['data-rig'] },
      );
    });
    const spot = await p.evaluate(() => {
      // The middle of the first curve: on the art, not on a junction.
      const r = window.splineskinEditor.info.rest;
      const b = (k) => [r[2 * k], r[2 * k + 1]];
      const [p0, p1, p2, p3] = [b(0), b(1), b(2), b(3)];
      return [0, 1].map((d) => (p0[d] + 3 * p1[d] + 3 * p2[d] + p3[d]) / 8);
    });
    const [cx, cy] = await clientPoint(p, spot);
    await p.mouse.click(cx, cy);
    await p.waitForFunction(() => ['preview', 'ready'].includes(document.body.dataset.rig), null, { timeout: WAIT });
    // The new handle starts with the deformation's blended map there (the drawing is posed).
    const placedAt = (T, h) => [T[0] * h[0] + T[2] * h[1] + T[4], T[1] * h[0] + T[3] * h[1] + T[5]];
    const added = await editorState(p);
    const grabbed = placedAt(added.scene.pose[3], added.scene.handles[3]);
    const delta = [0.03 * size, -0.02 * size];
    await drag(p, grabbed, delta, 8);
    await p.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
    // The exact rig is blended in from the stand-in over BLEND_MS (follow.js): compare once the
    // blend is over and a frame has been drawn after it (on a loaded machine the check ran
    // mid-blend, 0.31 units from the exact product).
    await p.waitForFunction(() => !(window.splineskinEditor.rig.blendingUntil > performance.now()), null, { timeout: WAIT });
    await p.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
    const swap = await p.evaluate(() => {
      const e = window.splineskinEditor;
      const expected = new Float64Array(e.points.length);
      e.rig.deform(e.scene.pose, expected);
      let gap = 0;
      for (let k = 0; k < expected.length; k++) gap = Math.max(gap, Math.abs(expected[k] - e.points[k]));
      return {
        states: e.rigStates,
        preview: e.previewSeconds,
        ready: e.rigSeconds,
        pose: e.scene.pose,
        rest: e.scene.handles,
        handles: e.scene.handles.length,
        family: e.scene.weights.family,
        gap,
        preview_flag: e.rigPreview,
      };
    });
    console.log(
      `turtles, a 4th handle with bbw: coarse bbw stand-in after ${swap.preview?.toFixed(3)} s, ` +
        `bbw ready after ${swap.ready.toFixed(3)} s; states ${swap.states.join(' → ')}`,
    );
    assert.equal(swap.handles, 4);
    assert.equal(swap.family, 'bbw');
    assert.ok(swap.states.includes('preview'), `the stand-in was shown: ${swap.states.join(', ')}`);
    assert.equal(swap.states.at(-1), 'ready');
    assert.equal(swap.preview_flag, false, 'the bbw rig replaced the stand-in');
    const now = placedAt(swap.pose[3], swap.rest[3]);
    const travel = [now[0] - grabbed[0], now[1] - grabbed[1]];
    assert.ok(
      Math.hypot(travel[0] - delta[0], travel[1] - delta[1]) < 0.01 * size,
      `the new handle keeps its drag: moved by ${travel}, dragged by ${delta}`,
    );
    assert.ok(swap.gap <= 1e-9 * size, `the drawing is the bbw rig's product at the pose (gap ${swap.gap})`);
  } finally {
    await p.close();
    await turtles.close();
  }
});
