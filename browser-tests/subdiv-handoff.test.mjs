// `splineskin subdiv animate -o anim.glb` checked by Khronos' own glTF Validator (npm
// `gltf-validator`): no errors; and every frame the file plays (the base mesh plus that frame's
// morph target) is the limit surface `subdiv deform --frame N --limit-mesh` writes for the same
// frame and tessellation level, to the rounding of the 32-bit floats glTF stores.

import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after } from 'node:test';

import validator from 'gltf-validator';

import { outputFolder, REPO, runSplineskin } from './harness.mjs';

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
