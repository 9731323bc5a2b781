// The JavaScript API (splineskin.js) in a page: open a drawing, pin it, drag a pin. Also run by
// browser-tests/js-api.test.mjs in chromium (and its calls under Node).
import { load } from './splineskin.js';

const splineskin = await load();
const svgText = await (await fetch('demo.svg')).text();
const drawing = splineskin.open(svgText, 'demo.svg');
const pins = [[440, 215], [150, 210], [300, 150]];
const rig = drawing.rig({ pins, weights: 'bbw' }); // smooth weights: the one slow step
const points = new Float64Array(2 * drawing.nPoints);
const pose = pins.map(() => [1, 0, 0, 1, 0, 0]);

const art = document.getElementById('art');
art.innerHTML = drawing.document; // every element a <path data-splineskin-element="k">
const elements = [...art.querySelectorAll('[data-splineskin-element]')];

function show(dy) {
  pose[0][5] = dy; // the head pin moves up or down
  rig.update(pose, points); // points = O · vec(T): no allocation, no module call
  const d = drawing.elementPathData(points);
  for (const e of elements) e.setAttribute('d', d[Number(e.dataset.splineskinElement)]);
  document.body.dataset.shown = String(dy);
}

document.getElementById('amount').addEventListener('input', (e) => show(Number(e.target.value)));
show(0);
// For the test: the deformed document, as an export writes it.
window.splineskinExample = { drawing, rig, points, pose, show, exported: () => drawing.svg(points, { rig, pose }) };
