// The Catmull–Clark page of `splineskin serve` (/subdiv/index.html) as a person uses it in
// chromium (WebGL2 through its software rasteriser): open the bundled tube through the file
// picker and see its limit surface shaded; drag to orbit, wheel to zoom, show the cage; a broken
// OBJ is refused with a message naming the file and line. Screenshots are kept on failure (or
// with BROWSER_TESTS_OUT).

import assert from 'node:assert/strict';
import { copyFileSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { launchBrowser, outputFolder, REPO, runSplineskin, startEditor } from './harness.mjs';
import { compareImages, decodePng, inkFraction } from './png.mjs';

const TUBE = join(REPO, 'crates', 'splineskin', 'assets', 'subdiv', 'tube.obj');
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

check('keys play on the page and export as the animation `subdiv animate` writes', async () => {
  await page.click('#rest');
  await page.fill('#key-time', '0');
  await page.click('#add-key');
  const box = await page.locator('#view').boundingBox();
  const state = await page.evaluate(() => window.subdivPageState());
  const [x, y] = await page.evaluate((q) => window.subdivProject(q), state.handles[1].rest);
  await page.mouse.move(box.x + x, box.y + y);
  await page.mouse.down();
  await page.mouse.move(box.x + x, box.y + y - 60, { steps: 5 });
  await page.mouse.up();
  await page.click('#add-key');
  const keyed = await page.evaluate(() => window.subdivPageState());
  assert.deepEqual(keyed.keys, [0, 1]);
  await page.click('#rest');
  await page.click('#play');
  await page.waitForFunction(() => document.getElementById('status').textContent.startsWith('played'), null, { timeout: WAIT });
  const played = await page.evaluate(() => window.subdivPageState());
  console.log(await status());
  // Played to the end: the last key's pose.
  played.handles[1].offset.forEach((v, k) => assert.ok(Math.abs(v - keyed.handles[1].offset[k]) < 1e-12));
  const scene = await exported('scene', 'animated.json');
  const usda = await exported('usda', 'animated.usda');
  assert.ok(JSON.parse(readFileSync(scene, 'utf8')).animation.keyframes.length === 2);
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

/** Pixels of `image` for which `test([r, g, b])` holds. */
function countPixels({ width, height, data }, test) {
  let n = 0;
  for (let i = 0; i < width * height; i++) {
    if (test([data[4 * i], data[4 * i + 1], data[4 * i + 2]])) n++;
  }
  return n;
}
