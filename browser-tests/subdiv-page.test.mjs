// The Catmull–Clark page of `splineskin serve` (/subdiv/index.html) as a person uses it in
// chromium (WebGL2 through its software rasteriser): open the bundled tube through the file
// picker and see its limit surface shaded; drag to orbit, wheel to zoom, show the cage; a broken
// OBJ is refused with a message naming the file and line. Screenshots are kept on failure (or
// with BROWSER_TESTS_OUT).

import assert from 'node:assert/strict';
import { copyFileSync, existsSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { launchBrowser, outputFolder, REPO, runSplineskin, startEditor } from './harness.mjs';
import { compareImages, decodePng, inkFraction } from './png.mjs';

const TUBE = join(REPO, 'crates', 'splineskin', 'assets', 'subdiv', 'tube.obj');
/** OpenSubdiv's regression shapes (the external data, ../shared/data). */
const SHAPES = join(REPO, '..', 'shared', 'data', 'subdiv', 'shapes');
const NO_SHAPES = !existsSync(SHAPES) && `${SHAPES} missing (the external data)`;
if (NO_SHAPES && process.env.CI) throw new Error(`${SHAPES} is missing; CI has the external data`);
const WAIT = 60_000;

const out = outputFolder('subdiv-page');
const check = (...args) => out.check(...args);
let browser;
let server;
let page;
const pageErrors = [];

before(async () => {
  browser = await launchBrowser({ viewport: { width: 960, height: 640 } });
  server = await startEditor();
  page = await browser.context.newPage();
  page.on('pageerror', (e) => pageErrors.push(e.message));
  await page.goto(`${server.url}subdiv/index.html`);
});

after(async () => {
  await browser?.close();
  await server?.close();
  out.finish();
});

/** A screenshot of the canvas, saved as `name`.png and decoded. */
async function shot(name) {
  const png = await page.locator('#view').screenshot();
  writeFileSync(join(out.path, `${name}.png`), png);
  return decodePng(png);
}

const status = () => page.locator('#status').textContent();

check('the tube opens through the picker and its limit surface is drawn shaded', async () => {
  await page.setInputFiles('#open', TUBE);
  await page.waitForFunction(() => document.getElementById('status').textContent.includes('triangles'), null, { timeout: WAIT });
  const said = await status();
  console.log(said);
  assert.match(said, /^tube\.obj: 72 vertices, 66 faces, 8 creases/);
  const image = await shot('tube');
  const ink = inkFraction(image);
  assert.ok(ink > 0.05 && ink < 0.8, `the surface covers ${ink} of the canvas`);
  assert.deepEqual(pageErrors, []);
});

check('dragging orbits, the wheel zooms, the cage shows on demand', async () => {
  const before = await shot('before');
  const box = await page.locator('#view').boundingBox();
  const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
  await page.mouse.move(cx, cy);
  await page.mouse.down();
  await page.mouse.move(cx + 120, cy + 40, { steps: 6 });
  await page.mouse.up();
  const turned = await shot('orbited');
  assert.ok(compareImages(before, turned).mean > 1, 'the view turned');
  await page.mouse.move(cx, cy);
  await page.mouse.wheel(0, -600);
  await page.waitForTimeout(100);
  const nearer = await shot('zoomed');
  assert.ok(inkFraction(nearer) > inkFraction(turned) * 1.2, 'zooming in makes the surface larger');
  await page.check('#show-cage');
  const caged = await shot('cage');
  const difference = compareImages(nearer, caged);
  assert.ok(difference.changed > 0.005, `the cage's lines show (${difference.changed} of the pixels changed)`);
  await page.uncheck('#show-cage');
  assert.ok(compareImages(nearer, await shot('no-cage')).mean < 0.01, 'and go again');
  assert.deepEqual(pageErrors, []);
});

check('a broken OBJ is refused with a message naming the file and line', async () => {
  await page.setInputFiles('#open', { name: 'broken.obj', mimeType: 'text/plain', buffer: Buffer.from('v 0 0 0\nf 1 2 3\n') });
  await page.waitForFunction(() => document.getElementById('status').classList.contains('error'), null, { timeout: WAIT });
  const said = await status();
  assert.match(said, /broken\.obj:2/);
  assert.deepEqual(pageErrors, []);
});

/** Clicks the canvas where the world point `p` is drawn. */
async function clickAt(p) {
  const box = await page.locator('#view').boundingBox();
  const [x, y] = await page.evaluate((q) => window.subdivProject(q), p);
  await page.mouse.click(box.x + x, box.y + y);
}

check('clicking adds handles, the rig arrives, dragging a handle bends the surface near it only', async () => {
  await page.setInputFiles('#open', TUBE);
  await page.waitForFunction(() => document.getElementById('status').textContent.includes('Click the surface'), null, { timeout: WAIT });
  await clickAt([0.8, 0, 0]);
  await page.waitForFunction(() => window.subdivPageState().rigReady, null, { timeout: WAIT });
  await clickAt([7.2, 0, 0]);
  await page.waitForFunction(() => window.subdivPageState().rigReady && window.subdivPageState().handles.length === 2, null, { timeout: WAIT });
  const rest = await page.evaluate(() => window.subdivPageState());
  assert.equal(rest.selected, 1);
  const before = await shot('two-handles');
  // Drag the second handle 80 pixels up.
  const box = await page.locator('#view').boundingBox();
  const at = rest.handles[1].rest;
  const [x, y] = await page.evaluate((q) => window.subdivProject(q), at);
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x, box.y + y - 80, { steps: 8 });
  await page.mouse.up();
  const moved = await page.evaluate(() => window.subdivPageState());
  const offset = Math.hypot(...moved.handles[1].offset);
  assert.ok(offset > 0.5, `the handle moved by ${offset}`);
  assert.deepEqual(moved.handles[0].offset, [0, 0, 0]);
  // The cage's vertices near the moved handle follow it, those near the other stay.
  const shift = (v) => Math.hypot(...[0, 1, 2].map((k) => moved.fitted[3 * v + k] - rest.fitted[3 * v + k]));
  const near = (end) => [...Array(72).keys()].filter((v) => Math.abs(rest.fitted[3 * v] - end) < 0.6);
  const farMove = Math.max(...near(8).map(shift));
  const stillMove = Math.max(...near(0).map(shift));
  console.log(`the moved end's cage moved ${farMove.toFixed(3)}, the other end's ${stillMove.toFixed(3)}; frame ${moved.frameMs.toFixed(1)} ms`);
  assert.ok(farMove > 0.5 * offset && stillMove < 0.25 * farMove, `${farMove} vs ${stillMove}`);
  const after = await shot('dragged');
  assert.ok(compareImages(before, after).mean > 0.5, 'the surface changed on screen');
  // Paint the selected handle's weights: red where it pulls.
  await page.check('#paint');
  const painted = await shot('painted');
  const red = countPixels(painted, ([r, g, b]) => r > 150 && g < 90 && b < 90);
  assert.ok(red > 500, `${red} red pixels`);
  // Another family: the rig is recomputed with it.
  await page.selectOption('#family', 'bbw');
  await page.waitForFunction(() => document.getElementById('status').textContent.includes('bbw weights: weights and rig in'), null, { timeout: WAIT });
  const bbw = await shot('bbw');
  assert.ok(countPixels(bbw, ([r, g, b]) => r > 150 && g < 90 && b < 90) > 500, 'painted with the new weights');
  // The canvas kept its size whatever the status said.
  assert.equal(bbw.width, painted.width);
  assert.equal((await page.locator('#view').boundingBox()).width, 960);
  assert.deepEqual(pageErrors, []);
});

check('ours is closer to the skinned surface than naive, the distance coloured', async () => {
  // The page keeps the two handles and the pose of the test before.
  await page.check('#distance');
  const ours = (await page.evaluate(() => window.subdivPageState())).error;
  await shot('distance-ours');
  await page.selectOption('#method', 'naive');
  const naive = (await page.evaluate(() => window.subdivPageState())).error;
  await shot('distance-naive');
  console.log(`to the skinned surface: ours max ${ours.max.toFixed(4)} RMS ${ours.rms.toFixed(4)}; naive max ${naive.max.toFixed(4)} RMS ${naive.rms.toFixed(4)}`);
  assert.ok(ours.max > 0 && ours.max < naive.max && ours.rms < naive.rms, JSON.stringify({ ours, naive }));
  await page.selectOption('#method', 'ours');
  await page.uncheck('#distance');
  assert.deepEqual(pageErrors, []);
});

check('turning a handle turns the cage about it, rigidly', async () => {
  await page.click('#rest');
  await page.selectOption('#mode', 'turn');
  const rest = await page.evaluate(() => window.subdivPageState());
  const box = await page.locator('#view').boundingBox();
  const [x, y] = await page.evaluate((q) => window.subdivProject(q), rest.handles[1].rest);
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x + 60, box.y + y, { steps: 6 });
  await page.mouse.up();
  const turned = await page.evaluate(() => window.subdivPageState());
  const r = turned.handles[1].rotation;
  // A rotation: orthonormal rows, determinant 1, and not the identity (60 px: 0.6 rad).
  const det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) + r[2] * (r[3] * r[7] - r[4] * r[6]);
  assert.ok(Math.abs(det - 1) < 1e-9, `det ${det}`);
  const trace = r[0] + r[4] + r[8];
  const angle = Math.acos((trace - 1) / 2);
  assert.ok(Math.abs(angle - 0.6) < 1e-6, `turned ${angle} rad`);
  assert.deepEqual(turned.handles[1].offset, [0, 0, 0], 'turning does not move the handle');
  const moved = Math.max(...rest.fitted.map((v, i) => Math.abs(v - turned.fitted[i])));
  assert.ok(moved > 0.3, `the cage turned (${moved})`);
  await shot('turned');
  await page.selectOption('#mode', 'move');
  assert.deepEqual(pageErrors, []);
});

/** Chooses `format` in the export menu and saves the download into the outputs as `name`. */
async function exported(format, name) {
  const [download] = await Promise.all([page.waitForEvent('download'), page.selectOption('#export', format)]);
  const path = join(out.path, name);
  await download.saveAs(path);
  return path;
}

const objVertices = (text) => text.split('\n').filter((l) => l.startsWith('v ')).flatMap((l) => l.split(/\s+/).slice(1, 4).map(Number));

check('the pose exported from the page is the library\'s deform of the saved scene', async () => {
  // The pose of the test before: handle 2 turned. Move handle 1 too.
  const box = await page.locator('#view').boundingBox();
  const state = await page.evaluate(() => window.subdivPageState());
  const [x, y] = await page.evaluate((q) => window.subdivProject(q), state.handles[0].rest);
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x - 30, box.y + y + 40, { steps: 5 });
  await page.mouse.up();
  const posed = await page.evaluate(() => window.subdivPageState());
  copyFileSync(TUBE, join(out.path, 'tube.obj'));
  const scene = await exported('scene', 'tube.json');
  const obj = await exported('obj', 'page.obj');
  const usda = await exported('usda', 'page.usda');
  await runSplineskin(['subdiv', 'deform', scene, '-o', join(out.path, 'cli.obj')]);
  const cli = readFileSync(join(out.path, 'cli.obj'), 'utf8');
  assert.equal(readFileSync(obj, 'utf8'), cli, 'the exported cage is the command line\'s, byte for byte');
  const want = objVertices(cli);
  const diagonal = 8.48528137423857;
  const pageError = Math.max(...want.map((v, i) => Math.abs(v - posed.fitted[i])));
  console.log(`the page's own fitted cage against subdiv deform: ${(pageError / diagonal).toExponential(2)} of the diagonal`);
  assert.ok(pageError <= 1e-9 * diagonal, `${pageError}`);
  // USD's points (its default value, the one frame) are the cage in f32.
  const text = readFileSync(usda, 'utf8');
  const points = /point3f\[\] points = \[(.*)\]\n/.exec(text)[1].match(/-?[\d.]+(?:e-?\d+)?/g).map(Number);
  assert.equal(points.length, want.length);
  const largest = Math.max(...want.map(Math.abs));
  const usdError = Math.max(...want.map((v, i) => Math.abs(v - points[i])));
  assert.ok(usdError <= 2 ** -23 * largest, `${usdError}`);
  assert.ok(text.includes('subdivisionScheme = "catmullClark"'));
  assert.deepEqual(pageErrors, []);
});

/**
 * Clicks the timeline's ruler at time `t` (s) when it shows `span` seconds (../timeline.js: 8
 * pixels inset at each end).
 */
async function rulerClick(t, span) {
  const b = await page.locator('#ruler').boundingBox();
  await page.mouse.click(b.x + 8 + (t / span) * (b.width - 16), b.y + b.height / 2);
}

check('keys play on the page and export as the animation `subdiv animate` writes', async () => {
  await page.click('#rest');
  await rulerClick(0, 2);
  assert.equal((await page.evaluate(() => window.subdivPageState())).time, 0);
  await page.click('#add-key');
  const box = await page.locator('#view').boundingBox();
  const state = await page.evaluate(() => window.subdivPageState());
  const [x, y] = await page.evaluate((q) => window.subdivProject(q), state.handles[1].rest);
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x, box.y + y - 60, { steps: 5 });
  await page.mouse.up();
  // The ruler shows 2 s with one key at 0: a click at its middle is 1 s.
  const posedNow = await page.evaluate(() => window.subdivPageState());
  await rulerClick(1, 2);
  const sought = await page.evaluate(() => window.subdivPageState());
  assert.equal(sought.time, 1);
  assert.deepEqual(sought.handles[1].offset, [0, 0, 0], 'one key holds the pose at rest everywhere');
  // The drag again (going to a time took the keys' pose), then keyed there.
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x, box.y + y - 60, { steps: 5 });
  await page.mouse.up();
  await page.click('#add-key');
  const keyed = await page.evaluate(() => window.subdivPageState());
  assert.deepEqual(keyed.keys, [0, 1]);
  keyed.handles[1].offset.forEach((v, k) => assert.ok(Math.abs(v - posedNow.handles[1].offset[k]) < 1e-9));
  // Ease in and out from the first key: at a quarter of the way the handle has come
  // e(¼) = ¼² (3 − ½) = 0.15625 of it, not ¼.
  await rulerClick(0, 2);
  await page.selectOption('#easing', 'ease-in-out');
  await rulerClick(0.25, 2); // the keys end at 1 s: the ruler still shows 2 s
  const eased = await page.evaluate(() => window.subdivPageState());
  assert.equal(eased.time, 0.25);
  assert.deepEqual(eased.easings, ['ease-in-out', 'linear']);
  eased.handles[1].offset.forEach((v, k) => assert.ok(Math.abs(v - 0.15625 * keyed.handles[1].offset[k]) < 1e-9, `${v} vs ${keyed.handles[1].offset[k]}`));
  await page.click('#rest');
  await page.click('#play');
  await page.waitForFunction(() => document.getElementById('status').textContent.startsWith('played'), null, { timeout: WAIT });
  const played = await page.evaluate(() => window.subdivPageState());
  console.log(await status());
  // Played to the end: the last key's pose.
  played.handles[1].offset.forEach((v, k) => assert.ok(Math.abs(v - keyed.handles[1].offset[k]) < 1e-12));
  const scene = await exported('scene', 'animated.json');
  const usda = await exported('usda', 'animated.usda');
  const keyframes = JSON.parse(readFileSync(scene, 'utf8')).animation.keyframes;
  assert.equal(keyframes.length, 2);
  assert.equal(keyframes[0].easing, 'ease-in-out', 'the easing is in the scene, for the command line');
  await runSplineskin(['subdiv', 'animate', scene, '-o', join(out.path, 'cli-animated.usda')]);
  assert.equal(readFileSync(usda, 'utf8'), readFileSync(join(out.path, 'cli-animated.usda'), 'utf8'),
    'the page\'s animated USD is the command line\'s, byte for byte');
  assert.match(readFileSync(usda, 'utf8'), /endTimeCode = 24\n/);
  await shot('keyed');
  writeFileSync(join(out.path, 'page.png'), await page.screenshot());
  assert.deepEqual(pageErrors, []);
});

check('undo and redo take back and restore a handle and a move', async () => {
  await page.click('#rest');
  const before = await page.evaluate(() => window.subdivPageState());
  await clickAt([4, 0, 0]);
  await page.waitForFunction((n) => window.subdivPageState().handles.length === n && window.subdivPageState().rigReady, before.handles.length + 1, { timeout: WAIT });
  await page.click('#undo');
  await page.waitForFunction((n) => window.subdivPageState().handles.length === n && window.subdivPageState().rigReady, before.handles.length, { timeout: WAIT });
  assert.deepEqual((await page.evaluate(() => window.subdivPageState())).keys, before.keys, 'the keys are kept');
  await page.keyboard.press('Control+Shift+Z');
  await page.waitForFunction((n) => window.subdivPageState().handles.length === n && window.subdivPageState().rigReady, before.handles.length + 1, { timeout: WAIT });
  // A move undone: the handle back where it was.
  const box = await page.locator('#view').boundingBox();
  const state = await page.evaluate(() => window.subdivPageState());
  const h = state.handles[0];
  const [x, y] = await page.evaluate((q) => window.subdivProject(q), h.rest.map((r, k) => r + h.offset[k]));
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x + 40, box.y + y, { steps: 4 });
  await page.mouse.up();
  assert.notDeepEqual((await page.evaluate(() => window.subdivPageState())).handles[0].offset, h.offset);
  await page.keyboard.press('Control+Z');
  assert.deepEqual((await page.evaluate(() => window.subdivPageState())).handles[0].offset, h.offset);
  assert.deepEqual(pageErrors, []);
});

/**
 * A point of the selected handle's gizmo ring about axis `k` (world) far on screen from the other
 * parts, and one `turn` radians further along it: [from, to] in canvas pixels.
 */
function ringPoints(k, turn) {
  return page.evaluate(({ k, turn }) => {
    const s = window.subdivPageState();
    const h = s.handles[s.selected];
    const centre = h.rest.map((r, i) => r + h.offset[i]);
    const r = 0.8 * s.gizmoSize;
    const on = (axis, t) => {
      const p = [...centre];
      p[(axis + 1) % 3] += r * Math.cos(t);
      p[(axis + 2) % 3] += r * Math.sin(t);
      return window.subdivProject(p);
    };
    const others = [];
    for (let a = 0; a < 3; a++) {
      if (a !== k) for (let t = 0; t < 64; t++) others.push(on(a, (2 * Math.PI * t) / 64));
      const tip = [...centre];
      tip[a] += s.gizmoSize;
      others.push(window.subdivProject(centre), window.subdivProject(tip));
    }
    let best = null;
    for (let t = 0; t < 64; t++) {
      const angle = (2 * Math.PI * t) / 64;
      const p = on(k, angle);
      const clear = Math.min(...others.map((o) => Math.hypot(o[0] - p[0], o[1] - p[1])));
      if (!best || clear > best.clear) best = { angle, clear };
    }
    return [on(k, best.angle), on(k, best.angle + turn)];
  }, { k, turn });
}

check('three handles clicked and a bone drawn by Alt-drag, the bone turned with the gizmo: the page, the USD and subdiv deform agree', async () => {
  await page.setInputFiles('#open', TUBE);
  await page.waitForFunction(() => document.getElementById('status').textContent.includes('Click the surface'), null, { timeout: WAIT });
  await clickAt([0.8, 0, 0]);
  await page.waitForFunction(() => window.subdivPageState().rigReady, null, { timeout: WAIT });
  await clickAt([4, 0, 0]);
  await page.waitForFunction(() => window.subdivPageState().rigReady && window.subdivPageState().handles.length === 2, null, { timeout: WAIT });
  await clickAt([2.4, 0, 0]);
  await page.waitForFunction(() => window.subdivPageState().rigReady && window.subdivPageState().handles.length === 3, null, { timeout: WAIT });
  // The bone: Alt-drag from one point of the surface to another.
  const box = await page.locator('#view').boundingBox();
  const [a, b] = await page.evaluate(() => [window.subdivProject([5.6, 0, 0]), window.subdivProject([7.6, 0, 0])]);
  await page.keyboard.down('Alt');
  await page.mouse.move(box.x + a[0], box.y + a[1]);
  await page.mouse.down();
  await page.mouse.move(box.x + b[0], box.y + b[1], { steps: 6 });
  await page.mouse.up();
  await page.keyboard.up('Alt');
  await page.waitForFunction(() => window.subdivPageState().rigReady && window.subdivPageState().handles.length === 4, null, { timeout: WAIT });
  const rigged = await page.evaluate(() => window.subdivPageState());
  assert.deepEqual(rigged.handles.map((h) => h.kind), ['point', 'point', 'point', 'bone']);
  assert.equal(rigged.selected, 3, 'the new bone is selected');
  const bone = rigged.handles[3];
  assert.ok(Math.hypot(...bone.rest.map((v, k) => v - bone.end[k])) > 1, `a bone from ${bone.rest} to ${bone.end}`);
  assert.match(await status(), /3 handles and 1 bone, \w+ weights: weights and rig in/);
  await shot('bone');
  // Turn the bone about z with the gizmo's blue ring: 50° swept on screen.
  const [from, to] = await ringPoints(2, (50 * Math.PI) / 180);
  await page.mouse.move(box.x + from[0], box.y + from[1]);
  await page.mouse.down();
  await page.mouse.move(box.x + to[0], box.y + to[1], { steps: 10 });
  await page.mouse.up();
  const turned = await page.evaluate(() => window.subdivPageState());
  const r = turned.handles[3].rotation;
  const angle = Math.atan2(r[3], r[0]);
  console.log(`the gizmo's ring turned the bone ${(angle * 180 / Math.PI).toFixed(1)}° about z; frame ${turned.frameMs.toFixed(2)} ms`);
  assert.ok(Math.abs(r[8] - 1) < 1e-12 && Math.abs(r[2]) < 1e-12 && Math.abs(r[5]) < 1e-12, `about z: ${r}`);
  assert.ok(Math.abs(angle) > (10 * Math.PI) / 180 && Math.abs(angle) < (90 * Math.PI) / 180, `${angle} rad`);
  assert.deepEqual(turned.handles[3].offset, [0, 0, 0], 'turning does not move the pivot');
  // Move the first handle up along y with the gizmo's green arrow.
  await clickAt(turned.handles[0].rest);
  const arrow = await page.evaluate(() => {
    const s = window.subdivPageState();
    const h = s.handles[0].rest;
    return [window.subdivProject([h[0], h[1] + 0.6 * s.gizmoSize, h[2]]), window.subdivProject([h[0], h[1] + s.gizmoSize, h[2]])];
  });
  await page.mouse.move(box.x + arrow[0][0], box.y + arrow[0][1]);
  await page.mouse.down();
  await page.mouse.move(box.x + arrow[1][0], box.y + arrow[1][1], { steps: 5 });
  await page.mouse.up();
  const posed = await page.evaluate(() => window.subdivPageState());
  const [dx, dy, dz] = posed.handles[0].offset;
  assert.ok(dx === 0 && dz === 0 && dy > 0.1, `moved along y only: ${posed.handles[0].offset}`);
  await shot('bone-turned');
  writeFileSync(join(out.path, 'bone-page.png'), await page.screenshot());
  // The library's deform of the saved scene, and the exported USD, against the page's cage.
  copyFileSync(TUBE, join(out.path, 'tube.obj'));
  const scene = await exported('scene', 'bone.json');
  assert.deepEqual(JSON.parse(readFileSync(scene, 'utf8')).bones, [{ ends: [bone.rest, bone.end] }]);
  const usda = await exported('usda', 'bone.usda');
  await runSplineskin(['subdiv', 'deform', scene, '-o', join(out.path, 'bone-cli.obj')]);
  const want = objVertices(readFileSync(join(out.path, 'bone-cli.obj'), 'utf8'));
  const diagonal = 8.48528137423857;
  const pageError = Math.max(...want.map((v, i) => Math.abs(v - posed.fitted[i])));
  console.log(`bone scene: the page's fitted cage against subdiv deform ${(pageError / diagonal).toExponential(2)} of the diagonal`);
  assert.ok(pageError <= 1e-9 * diagonal, `${pageError}`);
  const points = /point3f\[\] points = \[(.*)\]\n/.exec(readFileSync(usda, 'utf8'))[1].match(/-?[\d.]+(?:e-?\d+)?/g).map(Number);
  const largest = Math.max(...want.map(Math.abs));
  const usdError = Math.max(...want.map((v, i) => Math.abs(v - points[i])));
  console.log(`bone scene: USD points against subdiv deform ${(usdError / diagonal).toExponential(2)} of the diagonal (f32)`);
  assert.ok(usdError <= 2 ** -23 * largest, `${usdError}`);
  assert.deepEqual(pageErrors, []);
});

check('the session is autosaved and comes back after a reload', async () => {
  const before = await page.evaluate(() => window.subdivPageState());
  await page.waitForFunction(() => document.body.dataset.autosaved, null, { timeout: WAIT });
  // Let the last edit's save land (saves wait 150 ms for the next edit).
  await page.waitForTimeout(400);
  await page.reload();
  await page.waitForSelector('body[data-restored]', { timeout: WAIT });
  await page.waitForFunction(() => window.subdivPageState().rigReady, null, { timeout: WAIT });
  const after = await page.evaluate(() => window.subdivPageState());
  assert.deepEqual(after.handles, before.handles);
  assert.deepEqual(after.keys, before.keys);
  assert.equal(after.family, before.family);
  const off = Math.max(...after.fitted.map((v, i) => Math.abs(v - before.fitted[i])));
  assert.ok(off < 1e-12, `the restored cage is the same to ${off}`);
  console.log(await status());
  assert.match(await status(), /tube\.obj: the session autosaved .* is back \(3 handles and 1 bone, 0 keys\)/);
  assert.deepEqual(pageErrors, []);
});

check('regression shapes refined once: four handles clicked, a drag, the frame time printed', { skip: NO_SHAPES }, async () => {
  await page.selectOption('#family', 'shepard');
  for (const shape of ['catmark_car', 'catmark_bishop', 'catmark_rook']) {
    const refined = join(out.path, `${shape}-refined.obj`);
    await runSplineskin(['subdiv', 'refine', join(SHAPES, `${shape}.obj`), '--levels', '1', '-o', refined]);
    await page.setInputFiles('#open', refined);
    await page.waitForFunction(() => document.getElementById('status').textContent.includes('Click the surface'), null, { timeout: WAIT });
    const opened = await status();
    // Four handles: clicks over the middle of the view until four land on the surface.
    const box = await page.locator('#view').boundingBox();
    for (let k = 0; k < 40; k++) {
      const n = (await page.evaluate(() => window.subdivPageState())).handles.length;
      if (n === 4) break;
      const [fx, fy] = [0.3 + 0.4 * ((k * 0.37) % 1), 0.35 + 0.3 * ((k * 0.61) % 1)];
      await page.mouse.click(box.x + fx * box.width, box.y + fy * box.height);
    }
    await page.waitForFunction(() => window.subdivPageState().rigReady && window.subdivPageState().handles.length === 4, null, { timeout: WAIT });
    const rigged = await page.evaluate(() => window.subdivPageState());
    const h = rigged.handles[0].rest;
    const [x, y] = await page.evaluate((q) => window.subdivProject(q), h);
    await page.mouse.move(box.x + x, box.y + y);
    await page.mouse.down();
    const times = [];
    for (let step = 1; step <= 30; step++) {
      await page.mouse.move(box.x + x + 2 * step, box.y + y - 3 * step);
      times.push((await page.evaluate(() => window.subdivPageState())).frameMs);
    }
    await page.mouse.up();
    const moved = await page.evaluate(() => window.subdivPageState());
    assert.ok(Math.hypot(...moved.handles[0].offset) > 0, `${shape}: the handle moved`);
    times.sort((a, b) => a - b);
    const vertices = /(\d+) vertices/.exec(opened)[1];
    const triangles = /(\d+) triangles/.exec(opened)[1];
    console.log(`${shape} refined once: ${vertices} cage vertices, ${triangles} triangles (${opened.match(/level \d+/)[0]}); 4 handles; drag frame (cage product, surface, normals) median ${times[15].toFixed(1)} ms, slowest ${times[29].toFixed(1)} ms (60 fps: 16.7 ms)`);
    await shot(`${shape}-refined`);
  }
  assert.deepEqual(pageErrors, []);
});

/** Pixels of `image` for which `test([r, g, b])` holds. */
function countPixels({ width, height, data }, test) {
  let n = 0;
  for (let i = 0; i < width * height; i++) {
    if (test([data[4 * i], data[4 * i + 1], data[4 * i + 2]])) n++;
  }
  return n;
}
