// The JavaScript API (crates/splineskin-cli/web/splineskin.js, types in splineskin.d.ts) on the
// WebAssembly module: under Node, a drawing opened, pinned with smooth weights and posed gives
// the document the native `splineskin deform` writes for the same pins and pose, to 1e-9 of the
// diagonal; the identity pose gives the rest drawing; bad input throws a message naming the
// file. In chromium, the ~30-line example page (example.html, from the static build) runs and
// its slider's pose equals the native deformation too.
//
// The module: SPLINESKIN_WASM, else target/wasm/wasm32-unknown-unknown/release/splineskin_wasm.wasm
// (tools/build-wasm). Without it these tests skip, saying so, unless CI is set.

import assert from 'node:assert/strict';
import { existsSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after } from 'node:test';

import { launchBrowser, outputFolder, pathDifference, REPO, runSplineskin, serveFolder } from './harness.mjs';

const WASM = process.env.SPLINESKIN_WASM || join(REPO, 'target', 'wasm', 'wasm32-unknown-unknown', 'release', 'splineskin_wasm.wasm');
const WASM_THREADS = process.env.SPLINESKIN_WASM_THREADS || join(REPO, 'target', 'wasm-threads', 'wasm32-unknown-unknown', 'release', 'splineskin_wasm.wasm');
const WEB = join(REPO, 'crates', 'splineskin-cli', 'web');
const DEMO_SVG = join(REPO, 'crates', 'splineskin', 'assets', 'demo.svg');
const SAME = 1e-9;
// The example's pins (example.js).
const PINS = [[440, 215], [150, 210], [300, 150]];

const MISSING = !existsSync(WASM) && !process.env.CI && `${WASM} is missing (build it: tools/build-wasm)`;
if (!existsSync(WASM) && process.env.CI) throw new Error(`${WASM} is missing; CI builds it in .ci/run`);

const NO_THREADS = !existsSync(WASM_THREADS) && !process.env.CI && `${WASM_THREADS} is missing (build it: tools/build-wasm)`;
if (!existsSync(WASM_THREADS) && process.env.CI) throw new Error(`${WASM_THREADS} is missing; CI builds it in .ci/run`);

const out = outputFolder('js-api');
const check = (...args) => out.check(...args);
after(() => out.finish());

/** `splineskin deform` of demo.svg with the example's pins, smooth weights and `pose` flags. */
async function native(name, poseArgs) {
  const file = join(out.path, `${name}-native.svg`);
  await runSplineskin(['deform', DEMO_SVG, ...PINS.flatMap(([x, y]) => ['--pin', `${x},${y}`]), '--weights', 'bbw', ...poseArgs, '-o', file]);
  return readFileSync(file, 'utf8');
}

/** The map turning by `degrees` (clockwise on screen) about `p`, then moving by `by`. */
function turnAbout([px, py], degrees, [dx, dy] = [0, 0]) {
  const t = (degrees * Math.PI) / 180;
  const [c, s] = [Math.cos(t), Math.sin(t)];
  return [c, s, -s, c, px - (c * px - s * py) + dx, py - (s * px + c * py) + dy];
}

check('under Node: open, rig with smooth weights, update into a Float64Array, export: the native deformation', { skip: MISSING }, async () => {
  const { load, SplineskinError } = await import(join(WEB, 'splineskin.js'));
  const started = performance.now();
  const splineskin = await load(readFileSync(WASM));
  const loaded = performance.now();
  const drawing = splineskin.open(readFileSync(DEMO_SVG, 'utf8'), 'demo.svg');
  const rig = drawing.rig({ pins: PINS, weights: 'bbw' });
  const rigged = performance.now();
  const points = new Float64Array(2 * drawing.nPoints);

  // Identity: the rest drawing.
  const identity = PINS.map(() => [1, 0, 0, 1, 0, 0]);
  assert.equal(rig.update(identity, points), points, 'update writes into the caller\'s array');
  const size = Math.hypot(drawing.viewBox[2], drawing.viewBox[3]);
  const rest = Math.max(...points.map((v, k) => Math.abs(v - drawing.rest[k])));
  assert.ok(rest <= 1e-12 * size, `identity pose: ${rest} from the rest drawing`);

  // Pin 0 moved, pin 1 turned about itself: the native command's document.
  const pose = [[1, 0, 0, 1, 12, -30], turnAbout(PINS[1], 20), [1, 0, 0, 1, 0, 0]];
  const t0 = performance.now();
  const frames = 200;
  for (let k = 0; k < frames; k++) rig.update(pose, points);
  const perFrame = (performance.now() - t0) / frames;
  const exported = drawing.svg(points, { rig, pose });
  writeFileSync(join(out.path, 'node-api.svg'), exported);
  const { paths, relative } = pathDifference(exported, await native('node', ['--move', '0:12,-30', '--rotate', '1:20']), 'node');
  console.log(`js-api: Node: load ${(loaded - started).toFixed(0)} ms, open + bbw rig ${(rigged - loaded).toFixed(0)} ms, update ${(perFrame * 1000).toFixed(1)} µs a frame (${drawing.nPoints} points); ${paths} paths, ${relative.toExponential(2)} of the diagonal from native`);
  assert.ok(relative <= SAME, `${relative} of the diagonal`);
  // The module's own solve gives the same points (no flexible junctions).
  const solved = rig.solve(pose);
  const gap = Math.max(...solved.map((v, k) => Math.abs(v - points[k])));
  assert.ok(gap <= 1e-12 * size, `solve against update: ${gap}`);

  // Bad input: a message naming the file, and the module goes on.
  assert.throws(() => splineskin.open('<svg xmlns="http://www.w3.org/2000/svg"><path d="M 0 0 L"/>', 'broken.svg'), (e) => e instanceof SplineskinError && /broken\.svg/.test(e.message));
  assert.throws(() => rig.update([[1, 0, 0, 1, 0, 0]], points), /pose of 3 maps/);
  assert.throws(() => drawing.rig({ pins: [[Number.NaN, 0]] }), SplineskinError);
  assert.equal(splineskin.open(readFileSync(DEMO_SVG, 'utf8'), 'again.svg').nPoints, drawing.nPoints);
});

check('under Node with the threaded module on two threads: the operator of one thread, bit for bit (timed, printed)', { skip: MISSING || NO_THREADS }, async () => {
  const { load } = await import(join(WEB, 'splineskin.js'));
  const pins = [[100, 100], [300, 200], [500, 300], [200, 350], [400, 120]];
  const operators = [];
  for (const threads of [1, 2]) {
    const splineskin = await load(readFileSync(WASM_THREADS), { threads });
    assert.equal(splineskin.threads, threads, 'the pool started');
    const drawing = splineskin.open(readFileSync(DEMO_SVG, 'utf8'), 'demo.svg');
    const seconds = [];
    let rig;
    for (let k = 0; k < 3; k++) {
      const t0 = performance.now();
      rig = drawing.rig({ pins, weights: 'bbw' });
      seconds.push((performance.now() - t0) / 1000);
    }
    operators.push(rig.operator);
    console.log(`js-api: Node, threaded module on ${threads} thread(s): the fish's bbw rig with 5 pins ${seconds.map((s) => s.toFixed(2)).join(', ')} s`);
  }
  assert.equal(operators[0].length, operators[1].length);
  // Checked failing with the second operator's first entry changed.
  assert.ok(operators[0].every((v, k) => Object.is(v, operators[1][k])), 'the same operator on two threads');
});

check('in chromium: the example page (example.html of the static build) runs, and its pose is the native deformation', { skip: MISSING }, async () => {
  const folder = join(out.path, 'site');
  await runSplineskin(['serve', '--static-out', folder, '--wasm', WASM]);
  const site = await serveFolder(folder);
  const browser = await launchBrowser({ viewport: { width: 900, height: 600 } });
  try {
    const page = await browser.context.newPage();
    const errors = [];
    page.on('pageerror', (e) => errors.push(e.message));
    await page.goto(site.url('example.html'));
    await page.waitForSelector('body[data-shown="0"]', { timeout: 60_000 });
    const before = await page.evaluate(() => document.querySelector('[data-splineskin-element]').getAttribute('d'));
    await page.evaluate(() => {
      const slider = document.getElementById('amount');
      slider.value = '40';
      slider.dispatchEvent(new Event('input'));
    });
    await page.waitForSelector('body[data-shown="40"]');
    const after = await page.evaluate(() => document.querySelector('[data-splineskin-element]').getAttribute('d'));
    assert.notEqual(after, before, 'the slider moved the drawing');
    const exported = await page.evaluate(() => window.splineskinExample.exported());
    const { relative } = pathDifference(exported, await native('chromium', ['--move', '0:0,40']), 'chromium');
    console.log(`js-api: chromium example: ${relative.toExponential(2)} of the diagonal from native`);
    assert.ok(relative <= SAME, `${relative} of the diagonal`);
    await page.screenshot({ path: join(out.path, 'example.png') });
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
    await site.close();
  }
});

check('the Node example (example-node.mjs of the static build), inside a CommonJS npm project, writes the native deformation', { skip: MISSING }, async () => {
  // The static build inside a project whose package.json says CommonJS, as `npm init -y`
  // writes it: the build's own package.json keeps its scripts ES modules.
  const project = join(out.path, 'cjs-project');
  mkdirSync(project, { recursive: true });
  writeFileSync(join(project, 'package.json'), JSON.stringify({ name: 'cjs-project', version: '1.0.0', type: 'commonjs' }));
  const folder = join(project, 'node-site');
  await runSplineskin(['serve', '--static-out', folder, '--wasm', WASM]);
  const { execFileSync } = await import('node:child_process');
  const file = join(out.path, 'node-example.svg');
  const printed = execFileSync(process.execPath, [join(folder, 'example-node.mjs'), DEMO_SVG, file, ...PINS.map(([x, y]) => `${x},${y}`), '--', '-20,35'], { encoding: 'utf8' });
  assert.match(printed, /pins/);
  const { relative } = pathDifference(readFileSync(file, 'utf8'), await native('node-example', ['--move', '0:-20,35']), 'node example');
  console.log(`js-api: Node example: ${relative.toExponential(2)} of the diagonal from native`);
  assert.ok(relative <= SAME, `${relative} of the diagonal`);
});

check('the TypeScript declarations type-check a caller, and refuse its mistakes (tsc --strict on js-api-types.ts)', {}, async () => {
  const { execFileSync } = await import('node:child_process');
  const tsc = join(REPO, 'browser-tests', 'node_modules', '.bin', 'tsc');
  const args = ['--noEmit', '--strict', '--target', 'es2022', '--module', 'es2022', '--moduleResolution', 'bundler', '--lib', 'es2022,dom', join(REPO, 'browser-tests', 'js-api-types.ts')];
  try {
    execFileSync(tsc, args, { encoding: 'utf8' });
  } catch (e) {
    assert.fail(`tsc: ${e.stdout}${e.stderr}`);
  }
});
