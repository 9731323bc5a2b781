// The editor's tools in a real browser, on the bundled fish (`splineskin serve` without a file:
// five handles, its first pose): reset, rotate and scale (modifier keys and on-canvas widgets),
// undo and redo, delete, changing a junction's kind by clicking it, another weight family with
// its weight field, flexible G¹ solved on mouse-up, and a saved scene reopened by drag and drop.

import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { REPO, launchBrowser, outputFolder, startEditor } from './harness.mjs';

const REPO_ASSETS = join(REPO, 'crates', 'splineskin', 'assets');

const VIEWPORT = { width: 1100, height: 760 };
const WAIT = 60_000;
// Angles and scales read back from a map set by a mouse drag: the pointer moves by whole CSS
// pixels, about 0.6 drawing units here, so a few hundredths.
const DRAG_TOLERANCE = 0.03;

const out = outputFolder('editor-tools');
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
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
});

after(async () => {
  await browser?.close();
  await server?.close();
  out.finish();
});

const scene = () => page.evaluate(() => structuredClone(window.splineskinEditor.scene));
const shownData = () =>
  page.evaluate(() => [...document.getElementById('canvas').shadowRoot.querySelectorAll('[data-splineskin-element]')].map((e) => e.getAttribute('d')));

/** Client coordinates of drawing point p. */
function client(p) {
  return page.evaluate(([x, y]) => {
    return window.splineskinEditor.view.toClient([x, y]);
  }, p);
}

/** Handle i's posed position (drawing units). */
async function posed(i) {
  const s = await scene();
  const [T, [x, y]] = [s.pose[i], s.handles[i]];
  return [T[0] * x + T[2] * y + T[4], T[1] * x + T[3] * y + T[5]];
}

/** Units per CSS pixel. */
const unitsPerPixel = () => page.evaluate(() => window.splineskinEditor.view.unitsPerPixel());

async function mouseDrag(from, to, { steps = 8, modifier } = {}) {
  if (modifier) await page.keyboard.down(modifier);
  await page.mouse.move(...from);
  await page.mouse.down();
  for (let k = 1; k <= steps; k++) {
    await page.mouse.move(from[0] + ((to[0] - from[0]) * k) / steps, from[1] + ((to[1] - from[1]) * k) / steps);
  }
  await page.mouse.up();
  if (modifier) await page.keyboard.up(modifier);
}

async function waitRig() {
  await page.waitForFunction(() => document.body.dataset.rig === 'ready' || document.body.dataset.rig === 'error', null, {
    timeout: WAIT,
  });
  const error = await page.evaluate(() => (document.body.dataset.rig === 'error' ? document.getElementById('error').textContent : null));
  assert.equal(error, null);
}

check('the bundled fish opens posed; reset pose brings back the rest drawing', async () => {
  const s = await scene();
  assert.equal(s.handles.length, 5);
  assert.ok(s.pose.some((T) => T.some((v, k) => Math.abs(v - [1, 0, 0, 1, 0, 0][k]) > 1e-9)), 'posed');
  const restShown = await page.evaluate(() => {
    const e = window.splineskinEditor;
    return e.info.rest.every((v, k) => Math.abs(v - e.points[k]) < 1e-9);
  });
  assert.equal(restShown, false, 'the pose deforms the drawing');
  await page.click('#reset-pose');
  const atRest = await page.evaluate(() => {
    const e = window.splineskinEditor;
    return e.info.rest.every((v, k) => Math.abs(v - e.points[k]) < 1e-9 * (1 + Math.abs(v)));
  });
  assert.equal(atRest, true, 'reset: the drawing is at rest');
});

check('Shift-drag rotates a handle about itself, the square scales it, undo and redo step back and forth', async () => {
  const centre = await client(await posed(1));
  // Select handle 1 with a click (no move), then Shift-drag from it: 90 pixels of horizontal
  // travel turn it by 45°.
  await page.mouse.click(...centre);
  await mouseDrag(centre, [centre[0] + 90, centre[1] + 20], { modifier: 'Shift' });
  let T = (await scene()).pose[1];
  assert.ok(Math.abs(Math.atan2(T[1], T[0]) - Math.PI / 4) < 1e-9, `Shift-drag: rotated by ${Math.atan2(T[1], T[0])} rad`);
  await page.click('#undo');
  // The ring: dragged a quarter turn around the handle.
  const u = await unitsPerPixel();
  const ring = await page.evaluate(() => Number(document.getElementById('canvas').shadowRoot.querySelector('.ss-ring').getAttribute('r')));
  const r = ring / u;
  await mouseDrag([centre[0] - r, centre[1]], [centre[0], centre[1] - r], { steps: 12 });
  let s = await scene();
  T = s.pose[1];
  const angle = Math.atan2(T[1], T[0]);
  assert.ok(Math.abs(angle - Math.PI / 2) < DRAG_TOLERANCE, `ring: rotated by ${angle} rad`);
  assert.ok(Math.abs(Math.hypot(T[0], T[1]) - 1) < 1e-9, 'a rotation, no scale');
  const [px, py] = await posed(1);
  const [hx, hy] = s.handles[1];
  assert.ok(Math.hypot(px - hx, py - hy) < 1e-6, 'about the handle itself');

  // The scale knob: the square on the ring, to the right of the handle; dragged outwards by half
  // the ring's radius.
  const knob = [centre[0] + r, centre[1]];
  await mouseDrag(knob, [knob[0] + r / 2, knob[1]]);
  s = await scene();
  T = s.pose[1];
  const scale = Math.hypot(T[0], T[1]);
  assert.ok(Math.abs(scale - 1.5) < DRAG_TOLERANCE, `scaled by ${scale}`);
  assert.ok(Math.abs(Math.atan2(T[1], T[0]) - angle) < 1e-9, 'the rotation is kept');
  await page.screenshot({ path: join(out.path, 'rotated-scaled.png') });

  await page.click('#undo');
  T = (await scene()).pose[1];
  assert.ok(Math.abs(Math.hypot(T[0], T[1]) - 1) < 1e-9, 'undo: the scale is gone');
  await page.click('#undo');
  T = (await scene()).pose[1];
  assert.deepEqual(T, [1, 0, 0, 1, 0, 0], 'undo: the rotation is gone');
  await page.keyboard.press('Control+Shift+Z');
  T = (await scene()).pose[1];
  assert.ok(Math.abs(Math.atan2(T[1], T[0]) - angle) < 1e-12, 'redo: rotated again');
});

check('delete removes the selected handle; undo brings it back', async () => {
  const centre = await client(await posed(4));
  await page.mouse.click(...centre);
  assert.equal(await page.evaluate(() => window.splineskinEditor.selected), 4);
  await page.keyboard.press('Delete');
  await waitRig();
  assert.equal((await scene()).handles.length, 4);
  await page.keyboard.press('Control+Z');
  await waitRig();
  assert.equal((await scene()).handles.length, 5);
});

check('clicking a junction changes its kind, and the rig is built with it', async () => {
  await page.keyboard.press('Escape');
  // Junction editing is a mode: the markers are hidden until "junctions" is checked.
  assert.equal(await page.isChecked('#show-junctions'), false, 'junction markers are hidden by default');
  await page.check('#show-junctions');
  // The G¹ junction farthest from every handle (a click near a handle selects the handle).
  const target = await page.evaluate(() => {
    const e = window.splineskinEditor;
    const handles = e.scene.handles.map(([x, y], i) => {
      const T = e.scene.pose[i];
      return [T[0] * x + T[2] * y + T[4], T[1] * x + T[3] * y + T[5]];
    });
    let best = null;
    for (const j of e.view.junctions()) {
      if (e.info.paths[j.path].joints[j.joint] !== 'G1') continue;
      const at = [e.points[2 * j.point], e.points[2 * j.point + 1]];
      const d = Math.min(...handles.map(([x, y]) => Math.hypot(x - at[0], y - at[1])));
      if (!best || d > best.d) best = { path: j.path, joint: j.joint, at, d };
    }
    return best;
  });
  await page.mouse.click(...(await client(target.at)));
  await waitRig();
  const s = await scene();
  assert.deepEqual(s.junctions, [{ path: target.path, joint: target.joint, kind: 'angle' }], 'G¹ → fixed angle');
  assert.equal(s.handles.length, 5, 'no handle added');
});

check('another weight family: harmonic weights are computed and the weight field is shown', async () => {
  await page.selectOption('#family', 'harmonic');
  await waitRig();
  assert.equal((await scene()).weights.family, 'harmonic');
  // At rest the field is an image over the drawing's frame.
  if (!(await page.isDisabled('#reset-pose'))) await page.click('#reset-pose');
  await page.mouse.click(...(await client(await posed(2))));
  await page.check('#show-weights');
  await page.waitForFunction(() => {
    const image = document.getElementById('canvas').shadowRoot.querySelector('.ss-weights');
    return image.style.display !== 'none' && image.getAttribute('href')?.startsWith('data:image/png');
  }, null, { timeout: WAIT });
  // Under handle 2 the field is bright (weight near 1: the yellow end of viridis).
  const shot = join(out.path, 'weight-field.png');
  await page.screenshot({ path: shot });
  console.log(`editor-tools: screenshot ${shot}`);

  // Posed, the field follows the drawing: its brightest cells (weight 1) sit around handle 2
  // where the pose puts it, not where it rests.
  const rest = (await scene()).handles[2];
  const from = await client(await posed(2));
  await mouseDrag(from, [from[0] + 90, from[1] - 60]);
  const moved = await posed(2);
  await page.waitForFunction(() => {
    const mesh = document.getElementById('canvas').shadowRoot.querySelector('g.ss-weights');
    return mesh.style.display !== 'none' && mesh.children.length > 10;
  }, null, { timeout: WAIT });
  const bright = await page.evaluate(() => {
    const { view } = window.splineskinEditor;
    const mesh = view.root.getRootNode().querySelector('g.ss-weights');
    const yellow = [253, 231, 37];
    let best = null;
    for (const path of mesh.children) {
      const rgb = path.getAttribute('fill').match(/[\d.]+/g).map(Number);
      const d = Math.hypot(...rgb.map((v, k) => v - yellow[k]));
      if (!best || d < best.d) best = { d, path };
    }
    // The brightest cells' corners, drawing units.
    const numbers = best.path.getAttribute('d').match(/-?[\d.]+/g).map(Number);
    const corners = [];
    for (let k = 0; k < numbers.length; k += 2) corners.push([numbers[k] + view.origin[0], numbers[k + 1] + view.origin[1]]);
    return corners;
  });
  const u = await unitsPerPixel();
  const nearest = (p) => Math.min(...bright.map((q) => Math.hypot(q[0] - p[0], q[1] - p[1])));
  await page.screenshot({ path: join(out.path, 'weight-field-posed.png') });
  // The grid's cells are about 12 pixels; the handle is 150 pixels from where it rests.
  assert.ok(nearest(moved) < 25 * u, `the brightest cells are at the posed handle (${nearest(moved)} units away)`);
  assert.ok(nearest(rest) > 60 * u, `none is left where the handle rests (${nearest(rest)} units away)`);
  await page.click('#undo');
  await page.uncheck('#show-weights');
});

check('flexible G¹: the server solves each pose on mouse-up and the page shows it', async () => {
  await page.check('#flexible');
  await waitRig();
  const before = await shownData();
  const centre = await client(await posed(0));
  await mouseDrag(centre, [centre[0] + 40, centre[1] - 30]);
  await page.waitForSelector('body[data-solve="done"]', { timeout: WAIT });
  const after = await shownData();
  assert.notDeepEqual(after, before);
  const finite = await page.evaluate(() => window.splineskinEditor.points.every(Number.isFinite));
  assert.ok(finite);
});

check('a flexible solve stays when the carry maps of the text arrive after it', async () => {
  // The rig's carry operator (the label's best-fit maps) held back until its solve is done:
  // its arrival moves the text and must not draw the rig's plain product over the solve.
  let release;
  const held = new Promise((ok) => (release = ok));
  await page.route('**/api/rigs/*/carry', async (route) => {
    await held;
    await route.continue();
  });
  try {
    await page.uncheck('#flexible');
    await waitRig();
    await page.check('#flexible');
    await page.waitForFunction(() => {
      const e = window.splineskinEditor;
      return e.rigState === 'ready' && !e.rigPreview && JSON.parse(e.rigKey)[3] === true && document.body.dataset.solve === 'done';
    }, null, { timeout: WAIT });
    const solved = await page.evaluate(() => [...window.splineskinEditor.points]);
    const rigId = await page.evaluate(() => window.splineskinEditor.rig.id);
    release();
    await page.waitForFunction((id) => document.body.dataset.carry === id, rigId, { timeout: WAIT });
    const after = await page.evaluate(() => [...window.splineskinEditor.points]);
    assert.deepEqual(after, solved, 'the carry maps redrew the points');
  } finally {
    release();
    await page.unroute('**/api/rigs/*/carry');
  }
});

check('a saved scene reopens by drag and drop as it was', async () => {
  const saved = await scene();
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#save-scene')]);
  const file = join(out.path, 'fish-scene.json');
  await download.saveAs(file);
  const text = readFileSync(file, 'utf8');
  assert.equal(JSON.parse(text).splineskin_scene, 1);
  await page.evaluate((t) => {
    const transfer = new DataTransfer();
    transfer.items.add(new File([t], 'fish-scene.json', { type: 'application/json' }));
    document.getElementById('stage').dispatchEvent(new DragEvent('drop', { dataTransfer: transfer, bubbles: true, cancelable: true }));
  }, text);
  await page.waitForFunction(() => document.title.startsWith('fish-scene.json'), null, { timeout: WAIT });
  await waitRig();
  const reopened = await scene();
  assert.deepEqual(reopened, saved);
});

check('the wheel zooms about the pointer and Fit shows the whole drawing again', async () => {
  // The pointer sits on whole pixels: zoom about the pixel nearest handle 0.
  const handle = await client(await posed(0));
  const at = handle.map(Math.round);
  const before = await unitsPerPixel();
  await page.mouse.move(...at);
  await page.mouse.wheel(0, -400);
  await page.waitForFunction((u) => window.splineskinEditor.view.unitsPerPixel() < u * 0.9, before);
  const after = await unitsPerPixel();
  console.log(`editor-tools: zoomed in ${(before / after).toFixed(2)}×`);
  // The pixel under the pointer stays; the handle's offset from it grows by the zoom.
  const still = await client(await posed(0));
  const expected = at.map((p, d) => p + (before / after) * (handle[d] - p));
  assert.ok(
    Math.hypot(still[0] - expected[0], still[1] - expected[1]) < 0.25,
    `the point under the pointer stays: handle ${handle} → ${still}, expected ${expected}`,
  );
  // Handles still follow the pointer when zoomed.
  const s0 = await scene();
  await mouseDrag(still, [still[0] + 50, still[1]]);
  const T = (await scene()).pose[0];
  assert.ok(Math.abs(T[4] - s0.pose[0][4] - 50 * after) < 2 * after, 'a 50-pixel drag moves by 50 pixels of the zoomed view');
  await page.click('#fit');
  assert.ok(Math.abs((await unitsPerPixel()) - before) < 1e-9 * before);
});

check('a click on the art adds a handle, on empty canvas deselects, Alt-click adds one anywhere; Ctrl+Z works after clicking a checkbox', async () => {
  const state = () => page.evaluate(() => ({ n: window.splineskinEditor.scene.handles.length, selected: window.splineskinEditor.selected }));
  const artAt = (p) => page.evaluate(([x, y]) => window.splineskinEditor.view.artAt(x, y), p);
  const n0 = (await scene()).handles.length;
  // Empty canvas: near the frame's top-left corner, away from the fish.
  const home = await page.evaluate(() => window.splineskinEditor.view.home);
  const empty = await client([home[0] + 0.02 * home[2], home[1] + 0.02 * home[3]]);
  assert.equal(await artAt(empty), false, 'the corner is empty canvas');
  await page.mouse.click(...(await client(await posed(0))));
  assert.deepEqual(await state(), { n: n0, selected: 0 });
  await page.mouse.click(...empty);
  assert.deepEqual(await state(), { n: n0, selected: null }, 'a click on empty canvas deselects and adds nothing');
  // Alt-click: a pin anywhere, here outside the art.
  await page.keyboard.down('Alt');
  await page.mouse.click(...empty);
  await page.keyboard.up('Alt');
  assert.deepEqual(await state(), { n: n0 + 1, selected: n0 });
  await waitRig();
  // On the art: a spot near handle 0 where the fish is painted, clear of every handle.
  const handles = [];
  for (let i = 0; i < n0 + 1; i++) handles.push(await client(await posed(i)));
  let onArt = null;
  for (let r = 20; r <= 60 && !onArt; r += 10) {
    for (let a = 0; a < 8 && !onArt; a++) {
      const p = [handles[0][0] + r * Math.cos((a * Math.PI) / 4), handles[0][1] + r * Math.sin((a * Math.PI) / 4)];
      if (handles.every((h) => Math.hypot(h[0] - p[0], h[1] - p[1]) > 15) && (await artAt(p))) onArt = p;
    }
  }
  assert.ok(onArt, 'the fish is painted near handle 0');
  const junctions = await page.isChecked('#show-junctions');
  if (junctions) await page.click('#show-junctions'); // no junction marker under the click
  await page.mouse.click(...onArt);
  assert.deepEqual(await state(), { n: n0 + 2, selected: n0 + 1 });
  await waitRig();
  // The checkbox has the focus now; Ctrl+Z and Delete still reach the editor.
  await page.click('#show-junctions');
  assert.equal(await page.evaluate(() => document.activeElement.id), 'show-junctions');
  await page.keyboard.press('Control+z');
  assert.equal((await state()).n, n0 + 1, 'Ctrl+Z with a checkbox focused undoes the last handle');
  await waitRig();
  await page.mouse.click(...(await client(await posed(n0))));
  await page.focus('#show-junctions');
  await page.keyboard.press('Delete');
  assert.equal((await state()).n, n0, 'Delete with a checkbox focused deletes the selected handle');
  await waitRig();
  if (!junctions) await page.click('#show-junctions');
});

check('Fit shows a handle dragged out of the drawing\'s frame', async () => {
  // Zoom out, drag handle 0 far to the right of the drawing, then Fit.
  const canvas = await page.evaluate(() => {
    const r = document.getElementById('canvas').getBoundingClientRect();
    return [r.left, r.top, r.right, r.bottom];
  });
  const middle = [(canvas[0] + canvas[2]) / 2, (canvas[1] + canvas[3]) / 2];
  await page.mouse.move(...middle);
  await page.mouse.wheel(0, 600);
  await page.waitForTimeout(100);
  const from = await client(await posed(0));
  const to = [canvas[2] - 5, from[1]];
  await mouseDrag(from, to);
  const home = await page.evaluate(() => window.splineskinEditor.view.home);
  const [x] = await posed(0);
  assert.ok(x > home[0] + home[2], `the handle is right of the drawing's frame (${x} > ${home[0] + home[2]})`);
  await page.click('#fit');
  const shown = await client(await posed(0));
  assert.ok(
    shown[0] > canvas[0] && shown[0] < canvas[2] && shown[1] > canvas[1] && shown[1] < canvas[3],
    `after Fit the handle is on the canvas: ${shown} in ${canvas}`,
  );
  // The drawing's frame is still all shown.
  const corner = await client([home[0] + home[2], home[1] + home[3]]);
  assert.ok(corner[0] <= canvas[2] + 1 && corner[1] <= canvas[3] + 1, 'the drawing is in view too');
  await page.click('#undo');
  await waitRig();
  await page.click('#fit');
});

check('an operator family moves pins only: no rotate or scale widgets, no hidden turns', async () => {
  // Turn handle 1 first (weights: the fish's own family), then switch to an operator.
  const centre = await client(await posed(1));
  await page.mouse.click(...centre);
  await mouseDrag(centre, [centre[0] + 90, centre[1]], { modifier: 'Shift' });
  const turned = (await scene()).pose[1];
  assert.ok(Math.abs(turned[1]) > 0.1, 'handle 1 is turned');
  const posedBefore = await posed(1);
  await page.selectOption('#family', 'defop-arap');
  await waitRig();
  const s = await scene();
  for (const [i, T] of s.pose.entries()) {
    assert.deepEqual(T.slice(0, 4), [1, 0, 0, 1], `handle ${i}: a translation`);
  }
  const posedAfter = await posed(1);
  assert.ok(Math.hypot(posedAfter[0] - posedBefore[0], posedAfter[1] - posedBefore[1]) < 1e-9, 'the pin stays where it was');
  assert.match(await page.textContent('#notice'), /turns and scales were set aside/);
  // No ring or square on the selected handle; Shift-drag and Alt-drag translate.
  await page.mouse.click(...(await client(await posed(1))));
  assert.equal(await page.evaluate(() => document.getElementById('canvas').shadowRoot.querySelectorAll('.ss-ring, .ss-knob').length), 0);
  for (const modifier of ['Shift', 'Alt']) {
    const at = await client(await posed(1));
    await mouseDrag(at, [at[0] + 40, at[1] + 10], { modifier });
    const T = (await scene()).pose[1];
    assert.deepEqual(T.slice(0, 4), [1, 0, 0, 1], `${modifier}-drag: still a translation`);
  }
  // Undo brings back the turn with the weights it was made with.
  await page.click('#undo');
  await page.click('#undo');
  await page.click('#undo');
  await waitRig();
  assert.deepEqual((await scene()).pose[1], turned);
  // Back on a family that turns pins: the notice that they were set aside is gone. (Another
  // may show: on a loaded machine a drag's frames can run past their budget, and the page then
  // says that big drawings redraw the parts that move most first.)
  const notice = (await page.isHidden('#notice')) ? '' : await page.textContent('#notice');
  assert.doesNotMatch(notice, /set aside/, `the notice went: ${notice}`);
});

check('the toolbar fits one row at 1280 px, with the mesh families\' margin field or the operators\' samples field', async () => {
  await page.setViewportSize({ width: 1280, height: 760 });
  // The two fields the weights menu shows by family (never both), each shown in turn.
  const heights = await page.evaluate(() => {
    const fields = ['margin-label', 'defop-samples-label'].map((id) => document.getElementById(id));
    const was = fields.map((f) => f.hidden);
    const height = () => document.getElementById('toolbar').getBoundingClientRect().height;
    const out = fields.map((shown) => {
      fields.forEach((f) => (f.hidden = f !== shown));
      return [shown.id, height()];
    });
    fields.forEach((f, k) => (f.hidden = was[k]));
    return out;
  });
  const button = await page.evaluate(() => document.getElementById('fit').getBoundingClientRect().height);
  await page.setViewportSize(VIEWPORT);
  for (const [field, toolbar] of heights) {
    assert.ok(toolbar < 2 * button, `with ${field}: the toolbar is ${toolbar} px high, a button ${button} px`);
  }
});

check('a box selects several pins; dragging one moves them all, the ring turns them about their centre; Shift-click adds and removes', async () => {
  const selection = () => page.evaluate(() => [...window.splineskinEditor.selection].sort());
  const before = [await posed(0), await posed(1)];
  // A box around handles 0 and 1 (drawing units), dragged from its corner.
  const margin = 15 * (await unitsPerPixel());
  const x0 = Math.min(before[0][0], before[1][0]) - margin;
  const y0 = Math.min(before[0][1], before[1][1]) - margin;
  const x1 = Math.max(before[0][0], before[1][0]) + margin;
  const y1 = Math.max(before[0][1], before[1][1]) + margin;
  await mouseDrag(await client([x0, y0]), await client([x1, y1]));
  assert.deepEqual(await selection(), [0, 1], 'the box selected the two pins inside it');
  const n = (await scene()).handles.length;
  await page.screenshot({ path: join(out.path, 'box-selected.png') });

  // Dragging pin 0 moves pin 1 by the same amount.
  const from = await client(before[0]);
  await mouseDrag(from, [from[0] + 40, from[1] + 25]);
  const moved = [await posed(0), await posed(1)];
  const d0 = [moved[0][0] - before[0][0], moved[0][1] - before[0][1]];
  const d1 = [moved[1][0] - before[1][0], moved[1][1] - before[1][1]];
  assert.ok(Math.hypot(...d0) > 10, 'pin 0 moved');
  assert.ok(Math.hypot(d0[0] - d1[0], d0[1] - d1[1]) < 1e-9, `pin 1 moved with it: ${d1} vs ${d0}`);
  assert.equal((await scene()).handles.length, n, 'nothing added');

  // The ring is about the selection's centre: a quarter turn of the ring turns both pins about it.
  const centre = [(moved[0][0] + moved[1][0]) / 2, (moved[0][1] + moved[1][1]) / 2];
  const ring = await page.evaluate(() => {
    const r = document.getElementById('canvas').shadowRoot.querySelector('.ss-ring');
    const [ox, oy] = window.splineskinEditor.view.origin;
    return [Number(r.getAttribute('cx')) + ox, Number(r.getAttribute('cy')) + oy, Number(r.getAttribute('r'))];
  });
  assert.ok(Math.hypot(ring[0] - centre[0], ring[1] - centre[1]) < 1e-9, 'the ring is at the centre of the selection');
  const c = await client(centre);
  const r = ring[2] / (await unitsPerPixel());
  await mouseDrag([c[0] - r, c[1]], [c[0], c[1] - r], { steps: 12 });
  const T = (await scene()).pose[0];
  const angle = Math.atan2(T[1], T[0]);
  assert.ok(Math.abs(angle - Math.PI / 2) < DRAG_TOLERANCE, `turned by ${angle} rad`);
  for (const [i, p] of moved.entries()) {
    const [x, y] = [p[0] - centre[0], p[1] - centre[1]];
    const want = [centre[0] + Math.cos(angle) * x - Math.sin(angle) * y, centre[1] + Math.sin(angle) * x + Math.cos(angle) * y];
    const got = await posed(i);
    assert.ok(Math.hypot(got[0] - want[0], got[1] - want[1]) < 1e-6, `pin ${i} turned about the centre: ${got} vs ${want}`);
  }

  // Shift-click adds pin 2, and takes it out again; a plain click selects one pin alone.
  const third = await client(await posed(2));
  await page.keyboard.down('Shift');
  await page.mouse.click(...third);
  assert.deepEqual(await selection(), [0, 1, 2]);
  await page.mouse.click(...third);
  await page.keyboard.up('Shift');
  assert.deepEqual(await selection(), [0, 1]);
  await page.mouse.click(...(await client(await posed(1))));
  assert.deepEqual(await selection(), [1]);
  // Undo twice: the turn, then the move.
  await page.click('#undo');
  await page.click('#undo');
  await waitRig();
  const back = [await posed(0), await posed(1)];
  for (const i of [0, 1]) assert.ok(Math.hypot(back[i][0] - before[i][0], back[i][1] - before[i][1]) < 1e-9, `pin ${i} back`);
});

check('far from the origin (3e7 units) a pin lands where it is clicked and is drawn round', async () => {
  // A drawing whose coordinates are all about 3e7: single precision there is 2 units apart.
  const file = join(out.path, 'far.svg');
  writeFileSync(
    file,
    '<svg xmlns="http://www.w3.org/2000/svg" width="400" height="400" viewBox="30000000 30000000 100 100">' +
      '<path id="far" d="M30000010 30000010 C30000040 30000000 30000060 30000020 30000090 30000010 L30000090 30000090 L30000010 30000090 Z" fill="#f80" stroke="#333"/></svg>',
  );
  await page.setInputFiles('#open-file', file);
  await page.waitForFunction(() => window.splineskinEditor.info?.name.endsWith('far.svg'), null, { timeout: WAIT });
  // Alt-click at a point a third of a unit off the single-precision grid.
  const target = [30000050.3, 30000050.7];
  const at = await client(target);
  await page.keyboard.down('Alt');
  await page.mouse.click(...at);
  await page.keyboard.up('Alt');
  const s = await scene();
  assert.equal(s.handles.length, 1);
  const u = await unitsPerPixel();
  const [hx, hy] = s.handles[0];
  assert.ok(Math.hypot(hx - target[0], hy - target[1]) < 1.5 * u, `the pin is where clicked: ${hx}, ${hy}`);
  const shown = await page.evaluate(() => {
    const r = document.getElementById('canvas').shadowRoot.querySelector('.ss-handle').getBoundingClientRect();
    return [r.left + r.width / 2, r.top + r.height / 2, r.width, r.height];
  });
  assert.ok(Math.hypot(shown[0] - at[0], shown[1] - at[1]) < 1.5, `the marker is drawn at the click: ${shown} vs ${at}`);
  assert.ok(Math.abs(shown[2] - shown[3]) < 0.5, `round: ${shown[2]} × ${shown[3]} px`);
  await page.screenshot({ path: join(out.path, 'far.png') });
});

check('show mesh draws the weights\' triangle mesh, carried by the pose; inverse-distance weights say they have none', async () => {
  // The bundled scene with its drawing inline (an upload carries no folder to find it in).
  const scene = JSON.parse(readFileSync(join(REPO_ASSETS, 'demo-scene.json'), 'utf8'));
  scene.svg_text = readFileSync(join(REPO_ASSETS, scene.svg), 'utf8');
  delete scene.svg;
  const file = join(out.path, 'mesh-scene.json');
  writeFileSync(file, JSON.stringify(scene));
  await page.setInputFiles('#open-file', file);
  await page.waitForFunction(() => window.splineskinEditor.info?.name.endsWith('mesh-scene.json'), null, { timeout: WAIT });
  await waitRig();
  await page.selectOption('#family', 'harmonic');
  await waitRig();
  await page.check('#show-mesh');
  await page.waitForFunction(() => Number(document.body.dataset.mesh) > 100, null, { timeout: WAIT });
  const meshData = () => page.evaluate(() => document.getElementById('canvas').shadowRoot.querySelector('.ss-mesh').getAttribute('d'));
  const before = await meshData();
  assert.ok(before.length > 1000, 'edges drawn');
  await page.screenshot({ path: join(out.path, 'mesh.png') });
  const from = await client(await posed(2));
  await mouseDrag(from, [from[0] + 60, from[1] - 40]);
  await page.waitForFunction((d) => document.getElementById('canvas').shadowRoot.querySelector('.ss-mesh').getAttribute('d') !== d, before, { timeout: WAIT });
  await page.screenshot({ path: join(out.path, 'mesh-posed.png') });
  await page.selectOption('#family', 'shepard');
  await waitRig();
  await page.waitForFunction(() => /have no mesh/.test(document.getElementById('message').textContent), null, { timeout: WAIT });
  assert.equal(await meshData(), '', 'no mesh drawn');
  await page.uncheck('#show-mesh');
});

check('the margin field grows the smooth weights\' domain around the art: two discs apart are two parts, a wider margin joins them', async () => {
  // Two discs of radius 20 whose edges are 10 units apart (a diagonal of about 107 units):
  // with the default 1 % margin each is its own part, with 10 % (about 11 units each way) the
  // grown discs overlap and are one part.
  const svg =
    '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 40">' +
    '<circle cx="20" cy="20" r="20" fill="#4a8"/><circle cx="70" cy="20" r="20" fill="#a48"/></svg>';
  const scene = {
    splineskin_scene: 1,
    svg_text: svg,
    handles: [{ position: [20, 20] }, { position: [70, 20] }],
    weights: { family: 'bbw' },
  };
  const file = join(out.path, 'two-discs-scene.json');
  writeFileSync(file, JSON.stringify(scene));
  await page.setInputFiles('#open-file', file);
  await page.waitForFunction(() => window.splineskinEditor.info?.name.endsWith('two-discs-scene.json'), null, { timeout: WAIT });
  await waitRig();
  assert.equal(await page.isHidden('#margin-label'), false, 'shown for the smooth weights');
  assert.equal(await page.inputValue('#margin'), '1', 'the default margin, in %');
  const meshSays = async (pattern) => {
    await page.check('#show-mesh');
    await page.waitForFunction((p) => new RegExp(p).test(document.getElementById('message').textContent), pattern, { timeout: WAIT });
    await page.uncheck('#show-mesh');
  };
  await meshSays('over the art \\(2 parts\\)');
  // Out of range: refused with a message, the scene unchanged.
  await page.fill('#margin', '150');
  await page.dispatchEvent('#margin', 'change');
  await page.waitForFunction(() => /margin 150 %: expected a number from 0 to 100/.test(document.getElementById('error').textContent), null, { timeout: WAIT });
  assert.equal((await page.evaluate(() => window.splineskinEditor.scene.margin)) ?? null, null);
  assert.equal(await page.inputValue('#margin'), '1', 'the field shows the margin in force again');
  await page.fill('#margin', '10');
  await page.dispatchEvent('#margin', 'change');
  await waitRig();
  assert.equal(await page.evaluate(() => window.splineskinEditor.scene.margin), 0.1);
  await meshSays('over the art \\(1 part\\)');
  // The scene file carries it, and undo brings the default back.
  const saved = await page.evaluate(async () => {
    const { info, scene } = window.splineskinEditor;
    const answer = await fetch(`/api/documents/${encodeURIComponent(info.id)}/scene`, {
      method: 'POST',
      headers: { 'content-type': 'application/json', 'x-splineskin': '1' },
      body: JSON.stringify(scene),
    });
    return answer.text();
  });
  assert.equal(JSON.parse(saved).domain?.margin, 0.1, saved.slice(0, 300));
  await page.click('#undo');
  await waitRig();
  assert.equal(await page.inputValue('#margin'), '1');
  await meshSays('over the art \\(2 parts\\)');
  // Families without a mesh hide the field.
  await page.selectOption('#family', 'shepard');
  await waitRig();
  assert.equal(await page.isHidden('#margin-label'), true);
});

check('the exact weights replace their coarse stand-in without a jump: blended in from the stand-in\'s deformation under the pose shown', async () => {
  // The bundled fish opens posed; with smooth weights the stand-in comes first, then the exact rig.
  const scene = JSON.parse(readFileSync(join(REPO_ASSETS, 'demo-scene.json'), 'utf8'));
  scene.svg_text = readFileSync(join(REPO_ASSETS, scene.svg), 'utf8');
  delete scene.svg;
  scene.weights = { family: 'bbw' };
  const file = join(out.path, 'blend-scene.json');
  writeFileSync(file, JSON.stringify(scene));
  // The points shown as data-rig changes, read in the observer (before the next frame).
  await page.evaluate(() => {
    window.shownAt = {};
    new MutationObserver(() => {
      const state = document.body.dataset.rig;
      if (state === 'preview' || state === 'ready') window.shownAt[state] ??= Float64Array.from(window.splineskinEditor.points);
    }).observe(document.body, { attributes: true, attributeFilter: ['data-rig'] });
  });
  await page.setInputFiles('#open-file', file);
  await page.waitForFunction(() => window.splineskinEditor.info?.name.endsWith('blend-scene.json'), null, { timeout: WAIT });
  await waitRig();
  await page.waitForFunction(() => !window.splineskinEditor.rig.blendingUntil, null, { timeout: WAIT });
  const { preview, ready, final } = await page.evaluate(() => ({
    preview: [...(window.shownAt.preview ?? [])],
    ready: [...window.shownAt.ready],
    final: [...window.splineskinEditor.points],
  }));
  assert.ok(preview.length > 0, 'the stand-in was shown');
  const distance = (a, b) => Math.max(...a.map((x, k) => Math.abs(x - b[k])));
  const jump = distance(final, preview);
  assert.ok(jump > 1e-3, `the exact deformation differs from the stand-in's (${jump})`);
  assert.ok(distance(ready, preview) < 0.25 * jump, `when the exact rig arrived the drawing was still near the stand-in's: ${distance(ready, preview)} of ${jump}`);
});

check('a click a few pixels off a thin stroke adds the pin on the stroke; farther off, the status says where pins go', async () => {
  // One hairline across the drawing: 0.5 units wide, about 1 px on screen.
  const file = join(out.path, 'hairline.svg');
  writeFileSync(file, '<svg xmlns="http://www.w3.org/2000/svg" width="400" height="400" viewBox="0 0 400 400"><path d="M50 200 C150 198 250 202 350 200" stroke="#333" stroke-width="0.5" fill="none"/></svg>');
  await page.setInputFiles('#open-file', file);
  await page.waitForFunction(() => window.splineskinEditor.info?.name.endsWith('hairline.svg'), null, { timeout: WAIT });
  const on = await client([200, 200]);
  const near = [on[0], on[1] + 4];
  const handles = async () => (await scene()).handles;
  assert.equal(await page.evaluate(([x, y]) => window.splineskinEditor.view.artAt(x, y), near), false, '4 px off, nothing is painted');
  await page.mouse.click(...near);
  const added = await handles();
  assert.equal(added.length, 1, 'the click added a pin');
  const u = await unitsPerPixel();
  assert.ok(Math.abs(added[0][1] - 200) < 1.5 * u, `the pin is on the stroke: y = ${added[0][1]}`);
  await waitRig();
  await page.keyboard.press('Escape'); // nothing selected: a click off the art has nothing to deselect
  await page.mouse.click(on[0], on[1] + 40);
  assert.equal((await handles()).length, 1, '40 px off, no pin');
  assert.match(await page.textContent('#message'), /pins go on the art/);
});

check('Auto pins places pins over the art, the user\'s own kept, one undo step', async () => {
  // Two discs apart: the rule pins both.
  const file = join(out.path, 'two-discs.svg');
  writeFileSync(file, '<svg xmlns="http://www.w3.org/2000/svg" width="400" height="200" viewBox="0 0 200 100"><circle cx="50" cy="50" r="30" fill="#4a8"/><circle cx="150" cy="50" r="30" fill="#a48"/></svg>');
  await page.setInputFiles('#open-file', file);
  await page.waitForFunction(() => window.splineskinEditor.info?.name.endsWith('two-discs.svg'), null, { timeout: WAIT });
  await page.mouse.click(...(await client([45, 55])));
  await waitRig();
  const mine = (await scene()).handles[0];
  // The status line's messages as they come (the rig's own follows at once).
  await page.evaluate(() => {
    const line = document.getElementById('message');
    window.messagesSeen = [];
    new MutationObserver(() => window.messagesSeen.push(line.textContent)).observe(line, { childList: true, characterData: true, subtree: true });
  });
  await page.click('#auto-pins');
  await page.waitForFunction(() => window.splineskinEditor.scene.handles.length > 1, null, { timeout: WAIT });
  await waitRig();
  const { handles, pose } = await scene();
  assert.deepEqual(handles[0], mine, 'the user\'s pin is kept first');
  assert.equal(pose.length, handles.length);
  const inDisc = (p, cx) => Math.hypot(p[0] - cx, p[1] - 50) < 30;
  assert.ok(handles.every((p) => inDisc(p, 50) || inDisc(p, 150)), `every pin on the art: ${JSON.stringify(handles)}`);
  assert.ok(handles.slice(1).some((p) => inDisc(p, 150)), 'the other disc is pinned');
  const seen = await page.evaluate(() => window.messagesSeen);
  assert.ok(seen.some((m) => /\d+ pins? placed over the art/.test(m)), `the status said so: ${JSON.stringify(seen)}`);
  await page.screenshot({ path: join(out.path, 'auto-pins.png') });
  await page.keyboard.press('Control+z');
  await waitRig();
  assert.deepEqual((await scene()).handles, [mine], 'one Ctrl+Z takes them away');
});
