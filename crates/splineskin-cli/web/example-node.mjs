// The JavaScript API (splineskin.js) under Node: pin a drawing, move a pin, write the result.
//   node example-node.mjs drawing.svg out.svg X,Y [X,Y …] -- DX,DY
// pins at X,Y (the drawing's units), smooth weights; the first pin moved by DX,DY.
// Run by browser-tests/js-api.test.mjs against `splineskin deform`.
import { readFileSync, writeFileSync } from 'node:fs';
import { load } from './splineskin.js';

const [input, output, ...rest] = process.argv.slice(2);
const split = rest.indexOf('--');
const pins = rest.slice(0, split).map((p) => p.split(',').map(Number));
const [dx, dy] = rest[split + 1].split(',').map(Number);

const splineskin = await load(readFileSync(new URL('splineskin.wasm', import.meta.url)));
const drawing = splineskin.open(readFileSync(input, 'utf8'), input);
const rig = drawing.rig({ pins, weights: 'bbw' });
const pose = pins.map(() => [1, 0, 0, 1, 0, 0]);
pose[0] = [1, 0, 0, 1, dx, dy];
const points = rig.update(pose, new Float64Array(2 * drawing.nPoints));
writeFileSync(output, drawing.svg(points, { rig, pose }));
console.log(`${output}: ${drawing.nCurves} curves, ${pins.length} pins`);
