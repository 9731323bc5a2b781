// `splineskin subdiv animate -o anim.glb` checked by Khronos' own glTF Validator (npm
// `gltf-validator`): no errors; and every frame the file plays (the base mesh plus that frame's
// morph target) is the limit surface `subdiv deform --frame N --limit-mesh` writes for the same
// frame and tessellation level, to the rounding of the 32-bit floats glTF stores. Then three.js
// (npm `three`, its GLTFLoader and AnimationMixer) plays the file in chromium: the morphed
// vertices at a frame's time are that frame's surface, and screenshots of three frames are kept.

import assert from 'node:assert/strict';
import { cpSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after } from 'node:test';

import validator from 'gltf-validator';

import { launchBrowser, outputFolder, REPO, runSplineskin, serveFolder } from './harness.mjs';
import { compareImages, decodePng, inkFraction } from './png.mjs';

const TUBE = join(REPO, 'crates', 'splineskin', 'assets', 'subdiv', 'tube-scene.json');
const LEVEL = '2';
const FRAMES = 97; // 24 fps over 4 s, both ends included

const out = outputFolder('subdiv-handoff');
after(() => out.finish());

/** The JSON and binary chunks of a GLB file. */
function readGlb(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  assert.equal(view.getUint32(0, true), 0x46546c67, 'magic "glTF"');
  assert.equal(view.getUint32(8, true), bytes.byteLength, 'length in the header');
  const jsonLength = view.getUint32(12, true);
  const json = JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + jsonLength)));
  const binStart = 20 + jsonLength + 8;
  const bin = bytes.subarray(binStart, binStart + view.getUint32(20 + jsonLength, true));
  return { json, bin };
}

/** An accessor's floats. */
function floats({ json, bin }, index) {
  const accessor = json.accessors[index];
  const view = json.bufferViews[accessor.bufferView];
  const start = bin.byteOffset + (view.byteOffset ?? 0) + (accessor.byteOffset ?? 0);
  const width = { SCALAR: 1, VEC3: 3 }[accessor.type];
  return new Float32Array(bin.buffer.slice(start, start + 4 * width * accessor.count));
}

function objVertices(text) {
  return text
    .split('\n')
    .filter((line) => line.startsWith('v '))
    .flatMap((line) => line.split(/\s+/).slice(1, 4).map(Number));
}

out.check('the glb validates with no errors and plays the limit surface of every frame', async () => {
  const glbPath = join(out.path, 'tube.glb');
  await runSplineskin(['subdiv', 'animate', TUBE, '-o', glbPath, '--level', LEVEL]);
  const bytes = new Uint8Array(readFileSync(glbPath));
  const report = await validator.validateBytes(bytes);
  const { numErrors, numWarnings } = report.issues;
  const messages = report.issues.messages.map((m) => `${m.severity} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  console.log(`gltf-validator: ${numErrors} errors, ${numWarnings} warnings, ${report.issues.numInfos} infos`);
  assert.equal(numErrors, 0, messages.join('\n'));

  const glb = readGlb(bytes);
  const primitive = glb.json.meshes[0].primitives[0];
  assert.equal(primitive.targets.length, FRAMES - 1, 'one morph target per frame after the first');
  const sampler = glb.json.animations[0].samplers[0];
  const times = floats(glb, sampler.input);
  assert.equal(times.length, FRAMES);
  assert.ok(Math.abs(times[FRAMES - 1] - 4) < 1e-6, `ends at 4 s, not ${times[FRAMES - 1]}`);
  const base = floats(glb, primitive.attributes.POSITION);
  let worst = 0;
  for (const frame of [0, 12, 30, 72, FRAMES - 1]) {
    const meshPath = join(out.path, `frame${frame}-mesh.obj`);
    await runSplineskin(['subdiv', 'deform', TUBE, '--frame', String(frame), '-o', join(out.path, `frame${frame}.obj`),
      '--limit-mesh', meshPath, '--level', LEVEL]);
    const want = objVertices(readFileSync(meshPath, 'utf8'));
    assert.equal(want.length, base.length, `frame ${frame}: vertex count`);
    const delta = frame === 0 ? null : floats(glb, primitive.targets[frame - 1].POSITION);
    const largest = want.reduce((m, v) => Math.max(m, Math.abs(v)), 0);
    for (let i = 0; i < want.length; i++) {
      const got = Math.fround(base[i] + (delta ? delta[i] : 0));
      const error = Math.abs(got - want[i]);
      worst = Math.max(worst, error / largest);
      // The base and the difference are each rounded to f32, and so is their sum.
      assert.ok(error <= 4 * 2 ** -24 * largest, `frame ${frame}, coordinate ${i}: ${got} vs ${want[i]}`);
    }
  }
  console.log(`glTF frames against subdiv deform --limit-mesh: ${worst.toExponential(2)} of the largest coordinate`);
  // A control: frame 30 (the bend) is not frame 0.
  const moved = floats(glb, primitive.targets[29].POSITION).reduce((m, v) => Math.max(m, Math.abs(v)), 0);
  assert.ok(moved > 0.5, `frame 30 moves the surface by ${moved}`);
});

/** A page that loads `tube.glb` with three.js and shows it at any time of its animation. */
const PLAYER = `<!doctype html>
<html><head><style>html, body { margin: 0; background: #fff; }</style>
<script type="importmap">{"imports": {"three": "./three/build/three.module.js"}}</script>
</head><body>
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from './three/examples/jsm/loaders/GLTFLoader.js';
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setSize(640, 400);
renderer.setClearColor(0xffffff);
document.body.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.add(new THREE.HemisphereLight(0xffffff, 0x445566, 2.0));
const sun = new THREE.DirectionalLight(0xffffff, 2.0);
sun.position.set(3, 5, 8);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(35, 640 / 400, 0.1, 100);
camera.position.set(4, 3, 14);
camera.lookAt(4, 0, 0);
const gltf = await new GLTFLoader().loadAsync('tube.glb');
scene.add(gltf.scene);
let mesh;
gltf.scene.traverse((o) => { if (o.isMesh) mesh = o; });
mesh.material = new THREE.MeshStandardMaterial({ color: 0x4477cc, roughness: 0.6 });
const mixer = new THREE.AnimationMixer(gltf.scene);
mixer.clipAction(gltf.animations[0]).play();
// The mesh at time t: every vertex with the morph targets applied, and a render.
window.showAt = (t) => {
  mixer.setTime(t);
  renderer.render(scene, camera);
  const out = [];
  const v = new THREE.Vector3();
  const n = mesh.geometry.attributes.position.count;
  for (let i = 0; i < n; i++) {
    mesh.getVertexPosition(i, v);
    out.push(v.x, v.y, v.z);
  }
  return out;
};
window.loaded = true;
</script></body></html>`;

out.check('three.js plays the glb: the morphed surface at a frame time is that frame', async () => {
  const dir = join(out.path, 'player');
  mkdirSync(dir, { recursive: true });
  const three = join(REPO, 'browser-tests', 'node_modules', 'three');
  cpSync(join(three, 'build'), join(dir, 'three', 'build'), { recursive: true });
  cpSync(join(three, 'examples', 'jsm', 'loaders', 'GLTFLoader.js'), join(dir, 'three', 'examples', 'jsm', 'loaders', 'GLTFLoader.js'));
  cpSync(join(three, 'examples', 'jsm', 'utils'), join(dir, 'three', 'examples', 'jsm', 'utils'), { recursive: true });
  writeFileSync(join(dir, 'index.html'), PLAYER);
  await runSplineskin(['subdiv', 'animate', TUBE, '-o', join(dir, 'tube.glb'), '--level', LEVEL]);
  const server = await serveFolder(dir);
  const browser = await launchBrowser({ viewport: { width: 640, height: 400 } });
  try {
    const page = await browser.context.newPage();
    const problems = [];
    page.on('pageerror', (e) => problems.push(String(e)));
    await page.goto(server.url('index.html'));
    await page.waitForFunction(() => window.loaded === true, null, { timeout: 30000 });
    const shots = {};
    for (const frame of [0, 24, 72]) {
      const played = await page.evaluate((t) => window.showAt(t), frame / 24);
      const meshPath = join(out.path, `three-frame${frame}-mesh.obj`);
      await runSplineskin(['subdiv', 'deform', TUBE, '--frame', String(frame), '-o', join(out.path, `three-frame${frame}.obj`),
        '--limit-mesh', meshPath, '--level', LEVEL]);
      const want = objVertices(readFileSync(meshPath, 'utf8'));
      assert.equal(played.length, want.length, `frame ${frame}: vertex count`);
      const largest = want.reduce((m, v) => Math.max(m, Math.abs(v)), 0);
      const worst = played.reduce((m, v, i) => Math.max(m, Math.abs(v - want[i])), 0);
      // three.js adds the morph target in f32 on the CPU; a few ulps of the largest coordinate.
      assert.ok(worst <= 1e-5 * largest, `frame ${frame}: three.js is ${worst} from our surface`);
      const png = await page.screenshot();
      writeFileSync(join(out.path, `three-frame${frame}.png`), png);
      shots[frame] = decodePng(png);
      assert.ok(inkFraction(shots[frame]) > 0.02, `frame ${frame}: the tube is drawn`);
    }
    assert.deepEqual(problems, []);
    // A control: the bend (frame 24) and the twist (frame 72) look different from the rest pose.
    assert.ok(compareImages(shots[0], shots[24]).mean > 1, 'the bend shows');
    assert.ok(compareImages(shots[0], shots[72]).mean > 0.2, 'the twist shows');
  } finally {
    await browser.close();
    await server.close();
  }
});
