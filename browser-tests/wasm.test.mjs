// The library compiled to WebAssembly (crates/splineskin-wasm), run by Node: a scene deformed
// in WebAssembly gives the path data the native `splineskin deform` writes for it, to 1e-9 of
// the drawing's diagonal — the bundled fish (Shepard weights) and a real emoji rigged with
// bounded biharmonic weights (domain, BBW, fit, all in WebAssembly, one thread).
//
// The module: SPLINESKIN_WASM, else target/wasm/wasm32-unknown-unknown/release/splineskin_wasm.wasm
// (`.ci/run` builds it; docs/webassembly.md says how). Without it these tests skip, saying so,
// unless CI is set.

import assert from 'node:assert/strict';
import { existsSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after } from 'node:test';

import { REPO, outputFolder, runSplineskin, startEditor, pathNumbersById } from './harness.mjs';
import { loadEditor } from '../crates/splineskin-cli/web/wasm-editor.js';

const WASM = process.env.SPLINESKIN_WASM || join(REPO, 'target', 'wasm', 'wasm32-unknown-unknown', 'release', 'splineskin_wasm.wasm');
const ASSETS = join(REPO, 'crates', 'splineskin', 'assets');
const EMOJI = join(REPO, 'test-art', 'node_modules', 'openmoji', 'color', 'svg', '1F41F.svg');
/** WebAssembly against native, relative to the drawing's diagonal. */
const SAME = 1e-9;

const MISSING = !existsSync(WASM) && !process.env.CI && `${WASM} is missing (build it: docs/webassembly.md)`;
if (!existsSync(WASM) && process.env.CI) throw new Error(`${WASM} is missing; CI builds it in .ci/run`);

const out = outputFolder('wasm');
const check = (...args) => out.check(...args);
after(() => out.finish());

/** The module's exports, instantiated once. */
let instance = null;
async function wasm() {
  if (!instance) {
    // The module's host imports (its clock, progress) as the page's loader gives them.
    instance = (await loadEditor(readFileSync(WASM))).exports;
  }
  return instance;
}

/** Calls `fn(len, pose)` of the module on scene text `json`; the SVG text or the error thrown. */
async function deformSvg(json, pose) {
  const m = await wasm();
  const bytes = new TextEncoder().encode(json);
  const at = m.splineskin_input(bytes.length);
  new Uint8Array(m.memory.buffer, at, bytes.length).set(bytes);
  const n = Number(m.splineskin_deform_scene_svg(bytes.length, pose));
  const read = (address, length) => new TextDecoder().decode(new Uint8Array(m.memory.buffer, address, length));
  if (n < 0) throw new Error(read(m.splineskin_message(), m.splineskin_message_len()));
  return read(m.splineskin_text(), n);
}


/** The scene file `file` with its drawing inline (`svg` → `svg_text`), as JSON text. */
function inlineScene(file, folder) {
  const scene = JSON.parse(readFileSync(file, 'utf8'));
  if (scene.svg) {
    scene.svg_text = readFileSync(join(folder, scene.svg), 'utf8');
    delete scene.svg;
  }
  return JSON.stringify(scene);
}

/** Compares WebAssembly's deformation of scene `json` at pose `pose` with the native command's. */
async function compareWithNative(name, json, pose, { minPaths }) {
  const started = performance.now();
  const svg = await deformSvg(json, pose);
  const seconds = (performance.now() - started) / 1000;
  const scene = join(out.path, `${name}-scene.json`);
  writeFileSync(scene, json);
  const native = join(out.path, `${name}-native.svg`);
  await runSplineskin(['deform', scene, '--pose', String(pose), '-o', native]);
  writeFileSync(join(out.path, `${name}-wasm.svg`), svg);
  const [a, b] = [pathNumbersById(svg), pathNumbersById(readFileSync(native, 'utf8'))];
  const ids = Object.keys(a).filter((id) => id in b);
  assert.ok(ids.length >= minPaths, `${name}: ${ids.length} paths compared`);
  let [lo, hi] = [[Infinity, Infinity], [-Infinity, -Infinity]];
  let worst = 0;
  for (const id of ids) {
    assert.equal(a[id].length, b[id].length, `${name} #${id}: as many numbers`);
    a[id].forEach((v, k) => {
      worst = Math.max(worst, Math.abs(v - b[id][k]));
      lo[k % 2] = Math.min(lo[k % 2], v);
      hi[k % 2] = Math.max(hi[k % 2], v);
    });
  }
  const diagonal = Math.hypot(hi[0] - lo[0], hi[1] - lo[1]);
  console.log(`wasm: ${name}: ${ids.length} paths in ${seconds.toFixed(2)} s (setup and deformation in WebAssembly); largest difference from native ${(worst / diagonal).toExponential(2)} of the diagonal`);
  assert.ok(worst <= SAME * diagonal, `${name}: ${worst} > ${SAME} of the diagonal ${diagonal}`);
}

check('the bundled fish deformed in WebAssembly is the native deformation', { skip: MISSING }, async () => {
  await compareWithNative('fish', inlineScene(join(ASSETS, 'demo-scene.json'), ASSETS), 1, { minPaths: 10 });
});

check('a real emoji rigged with bounded biharmonic weights, deformed in WebAssembly, is the native deformation', { skip: MISSING || (!existsSync(EMOJI) && `${EMOJI} missing (npm ci in test-art)`) }, async () => {
  // Ids on every shape (the comparison pairs paths by id), then a rig by the command.
  let n = 0;
  const text = readFileSync(EMOJI, 'utf8').replace(/<(path|rect|circle|ellipse|line|polyline|polygon)\b(?![^>]*\sid=)/g, (tag) => `${tag} id="t-${n++}"`);
  const svg = join(out.path, 'emoji.svg');
  writeFileSync(svg, text);
  const rigged = join(out.path, 'emoji-rig.json');
  await runSplineskin(['rig', svg, '--pins', '4', '--rotate', '1:25', '--move', '2:6,-4', '-o', rigged]);
  const json = inlineScene(rigged, out.path);
  assert.match(json, /"family":\s*"bbw"/, 'bounded biharmonic weights');
  await compareWithNative('emoji', json, 0, { minPaths: 3 });
});

check('bad input comes back as a message naming the scene, and the module goes on', { skip: MISSING }, async () => {
  await assert.rejects(deformSvg('{"splineskin_scene": 1', 0), /scene\.json/);
  await assert.rejects(deformSvg(inlineScene(join(ASSETS, 'demo-scene.json'), ASSETS), 9), /pose 9 does not exist/);
  const svg = await deformSvg(inlineScene(join(ASSETS, 'demo-scene.json'), ASSETS), 0);
  assert.match(svg, /^<svg/);
});

check('the editor\'s routes answered in WebAssembly are the server\'s: the same operator, the same messages', { skip: MISSING }, async () => {
  const editor = await loadEditor(readFileSync(WASM));
  const server = await startEditor([]);
  try {
    const svg = readFileSync(join(ASSETS, 'demo.svg'));
    const both = async (method, path, body, headers = {}) => {
      const all = { 'x-splineskin': '1', ...headers };
      const local = editor.request(method, path, { body, headers: all });
      const remote = await fetch(`${server.url}${path.slice(1)}`, { method, headers: all, body });
      return [local, { status: remote.status, headers: remote.headers, body: new Uint8Array(await remote.arrayBuffer()) }];
    };
    const [openedHere, openedThere] = await both('POST', '/api/open', svg, { 'x-file-name': 'demo.svg' });
    const [here, there] = [openedHere, openedThere].map((r) => JSON.parse(new TextDecoder().decode(r.body)));
    assert.deepEqual({ ...here, id: 0 }, { ...there, id: 0 }, 'the same description of the opened drawing');
    const scene = (id) => JSON.stringify({
      document: id,
      scene: { handles: [[440, 215], [150, 210]], pose: [[1, 0, 0, 1, 0, 0], [1, 0, 0, 1, 0, 0]], weights: { family: 'bbw' }, junctions: [], flexible: false },
    });
    const local = editor.request('POST', '/api/rig', { body: scene(here.id), headers: { 'x-splineskin': '1' } });
    const remote = await fetch(`${server.url}api/rig`, { method: 'POST', headers: { 'x-splineskin': '1', 'content-type': 'application/json' }, body: scene(there.id) });
    assert.equal(local.status, 200);
    assert.equal(remote.status, 200);
    const a = new Float64Array(local.body.buffer.slice(local.body.byteOffset, local.body.byteOffset + local.body.byteLength));
    const b = new Float64Array(await remote.arrayBuffer());
    assert.equal(a.length, b.length, 'operators of one size');
    const scale = Math.max(...b.map(Math.abs));
    const worst = Math.max(...a.map((v, k) => Math.abs(v - b[k])));
    console.log(`wasm: editor route /api/rig (bbw, fish): operator of ${a.length} numbers, largest difference from the server's ${(worst / scale).toExponential(2)} of its largest entry`);
    assert.ok(worst <= 1e-9 * scale, `${worst} against ${scale}`);
    assert.ok(local.headers['x-splineskin-rig'], 'the rig\'s id');
    // A bad request: the same status and message.
    const [badHere, badThere] = await both('POST', '/api/rig', JSON.stringify({ document: 'd999', scene: {} }), { 'content-type': 'application/json' });
    assert.equal(badHere.status, badThere.status);
    assert.deepEqual(JSON.parse(new TextDecoder().decode(badHere.body)), JSON.parse(new TextDecoder().decode(badThere.body)));
  } finally {
    await server.close();
  }
});

/** The largest difference between the numbers of two JSON values of one shape (throws if the shapes differ). */
function jsonDifference(a, b, at = '') {
  if (typeof a === 'number' && typeof b === 'number') return Math.abs(a - b);
  if (typeof a !== typeof b || Array.isArray(a) !== Array.isArray(b) || (a === null) !== (b === null)) throw new Error(`${at}: ${JSON.stringify(a)?.slice(0, 40)} against ${JSON.stringify(b)?.slice(0, 40)}`);
  if (a === null || typeof a !== 'object') {
    if (a !== b) throw new Error(`${at}: ${a} against ${b}`);
    return 0;
  }
  const keys = new Set([...Object.keys(a), ...Object.keys(b)]);
  let worst = 0;
  for (const k of keys) worst = Math.max(worst, jsonDifference(a[k], b[k], `${at}.${k}`));
  return worst;
}

check('trained operators and Lottie export run in WebAssembly too: the server\'s operator and animation', { skip: MISSING }, async () => {
  const stages = [];
  const editor = await loadEditor(readFileSync(WASM), { onProgress: (job, stage) => stages.push(`${job}:${stage.stage}`) });
  const server = await startEditor([]);
  try {
    const headers = { 'x-splineskin': '1', 'content-type': 'application/json' };
    const local = (path, body, extra = {}) => editor.request('POST', path, { body: JSON.stringify(body), headers: { ...headers, ...extra } });
    const remote = async (path, body) => {
      const r = await fetch(`${server.url}${path.slice(1)}`, { method: 'POST', headers, body: JSON.stringify(body) });
      return { status: r.status, headers: Object.fromEntries(r.headers), body: new Uint8Array(await r.arrayBuffer()) };
    };
    const here = JSON.parse(new TextDecoder().decode(editor.request('GET', '/api/initial').body));
    const there = await (await fetch(`${server.url}api/initial`)).json();
    const scene = { ...here.scene, flexible: false, weights: { family: 'defop-arap', samples: 12 } };
    const [a, b] = [local('/api/defop', { document: here.id, scene }, { 'x-splineskin-job': 'train-1' }), await remote('/api/defop', { document: there.id, scene })];
    assert.equal(a.status, 200, new TextDecoder().decode(a.body));
    assert.equal(b.status, 200);
    const [ga, gb] = [a, b].map((r) => new Float64Array(r.body.buffer.slice(r.body.byteOffset, r.body.byteOffset + r.body.byteLength)));
    const scale = Math.max(...gb.map(Math.abs));
    const worst = Math.max(...ga.map((v, k) => Math.abs(v - gb[k])));
    console.log(`wasm: editor route /api/defop (ARAP, 12 samples, fish): ${ga.length} numbers, largest difference from the server's ${(worst / scale).toExponential(2)} of its largest entry; stages reported: ${[...new Set(stages)].join(', ')}`);
    assert.equal(ga.length, gb.length);
    assert.ok(worst <= 1e-9 * scale, `${worst} against ${scale}`);
    assert.ok(stages.includes('train-1:training'), 'the training stage reported to the host');

    const animated = {
      ...here.scene,
      animation: { fps: 10, keyframes: [{ time: 0, pose: here.scene.pose }, { time: 1, pose: here.scene.pose.map(([p, q, r, s, e, f]) => [p, q, r, s, e + 20, f]) }] },
    };
    const [la, lb] = [local(`/api/documents/${here.id}/lottie`, animated), await remote(`/api/documents/${there.id}/lottie`, animated)];
    assert.equal(la.status, 200, new TextDecoder().decode(la.body));
    const [ja, jb] = [la, lb].map((r) => JSON.parse(new TextDecoder().decode(r.body)));
    const difference = jsonDifference(ja, jb);
    console.log(`wasm: editor route /lottie: ${la.body.length} bytes, largest difference of any number from the server's ${difference.toExponential(2)}`);
    assert.ok(difference <= 1e-9 * Math.max(here.view_box[2], here.view_box[3]), `${difference}`);
    // The same report, warnings included (the fish's label is text, which Lottie leaves out).
    const [ra, rb] = [la.headers['x-splineskin-lottie'], lb.headers['x-splineskin-lottie']].map((h) => JSON.parse(h));
    assert.deepEqual(ra.warnings, rb.warnings);
    assert.ok(ra.warnings.some((w) => /^text label: not written/.test(w)), ra.warnings.join('; '));
  } finally {
    await server.close();
  }
});
