// Big drawings in the editor: a made drawing of 100 000 curves and flag-icons' Serbia (52 187
// curves), three pins, a pin dragged. A drag's frames apply only the dragged pin's columns of
// the rig's operator and write the path data the frame's time allows, the most moved first
// (the notice says so); mid-drag the points equal the whole product, and after the release
// every element's path data is written from the exact points. The median frame time is
// printed (the page's own figure), never asserted.

import assert from 'node:assert/strict';
import { existsSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { REPO, outputFolder } from './harness.mjs';
import { WAIT, clientPoint, median, openThroughPicker, servedEditor } from './editor-page.mjs';

const VIEWPORT = { width: 1280, height: 800 };
const SERBIA = join(REPO, 'test-art', 'node_modules', 'flag-icons', 'flags', '4x3', 'rs.svg');
/** Rings of the made drawing, and cubic curves per ring: 100 000 curves. */
const RINGS = [40, 25];
const CURVES_PER_RING = 100;
/** Mid-drag points against the whole product, relative to the drawing's diagonal. */
const SAME = 1e-9;
/** Moves of the drag. */
const MOVES = 30;

const out = outputFolder('editor-big');
const check = (...args) => out.check(...args);
let session;
let page;

before(async () => {
  session = await servedEditor({ viewport: VIEWPORT });
  page = session.page;
});

after(async () => {
  await session?.close();
  out.finish();
});

/** A grid of wavy rings, each a closed path of CURVES_PER_RING cubics, in a 1000 × 625 frame. */
function madeDrawing() {
  const [nx, ny] = RINGS;
  const paths = [];
  for (let j = 0; j < ny; j++) {
    for (let i = 0; i < nx; i++) {
      const [cx, cy, r] = [12.5 + 25 * i, 12.5 + 25 * j, 10];
      const at = (k) => {
        const a = (2 * Math.PI * k) / (3 * CURVES_PER_RING);
        const rr = r * (1 + 0.08 * Math.sin(7 * a));
        return `${(cx + rr * Math.cos(a)).toFixed(3)} ${(cy + rr * Math.sin(a)).toFixed(3)}`;
      };
      let d = `M${at(0)}`;
      for (let c = 0; c < CURVES_PER_RING; c++) d += ` C${at(3 * c + 1)} ${at(3 * c + 2)} ${at(3 * c + 3)}`;
      paths.push(`<path d="${d}Z" fill="hsl(${(i * 9 + j * 14) % 360} 60% 60%)"/>`);
    }
  }
  const file = join(out.path, 'rings.svg');
  writeFileSync(file, `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 1000 625">${paths.join('')}</svg>`);
  return file;
}

/** Opens `file`, pins it at three places (fractions of its viewBox) and waits for its rig. */
async function pinned(file) {
  await openThroughPicker(page, file);
  await page.selectOption('#family', 'shepard');
  const vb = await page.evaluate(() => window.splineskinEditor.info.view_box);
  const at = ([fx, fy]) => [vb[0] + fx * vb[2], vb[1] + fy * vb[3]];
  for (const p of [[0.2, 0.25], [0.5, 0.5], [0.8, 0.75]]) {
    const [x, y] = await clientPoint(page, at(p));
    await page.keyboard.down('Alt');
    await page.mouse.click(x, y);
    await page.keyboard.up('Alt');
  }
  await page.waitForSelector('body[data-rig="ready"]', { timeout: 10 * WAIT });
  return { middle: at([0.5, 0.5]), diagonal: Math.hypot(vb[2], vb[3]) };
}

/**
 * Drags the middle pin by (60, 20) px, one frame per move; mid-drag, the largest difference
 * between the page's points and the whole product (relative to `diagonal`). Returns it with
 * the frames' times.
 */
async function dragMiddle(middle, diagonal) {
  await page.evaluate(() => {
    const e = window.splineskinEditor;
    e.frameTimes.length = 0;
    e.productTimes.length = 0;
  });
  const [x0, y0] = await clientPoint(page, middle);
  await page.mouse.move(x0, y0);
  await page.mouse.down();
  for (let k = 1; k <= MOVES; k++) {
    await page.mouse.move(x0 + (60 * k) / MOVES, y0 + (20 * k) / MOVES);
    await page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => ok())));
  }
  await page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(() => ok()))));
  const apart = await page.evaluate((diagonal) => {
    const e = window.splineskinEditor;
    const exact = new Float64Array(e.points.length);
    e.rig.deform(e.scene.pose, exact);
    let worst = 0;
    for (let i = 0; i < exact.length; i++) worst = Math.max(worst, Math.abs(exact[i] - e.points[i]));
    return worst / diagonal;
  }, diagonal);
  await page.mouse.up();
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  const times = await page.evaluate(() => ({ frame: [...window.splineskinEditor.frameTimes], product: [...window.splineskinEditor.productTimes] }));
  return { apart, ...times };
}

/** Whether every element's path data was written from the page's current points. */
const allWritten = () =>
  page.evaluate(() => {
    const { view, points } = window.splineskinEditor;
    return view.written.every((v, i) => v === points[i]);
  });

check('a 100 000-curve drawing follows a drag: partial frames, the exact points, everything written on release', async () => {
  const { middle, diagonal } = await pinned(madeDrawing());
  assert.equal(await page.evaluate(() => window.splineskinEditor.info.n_curves), RINGS[0] * RINGS[1] * CURVES_PER_RING);
  const { apart, frame, product } = await dragMiddle(middle, diagonal);
  console.log(
    `big: 100 000 curves, Shepard, 3 pins: median frame ${median(frame).toFixed(1)} ms (product ${median(product).toFixed(1)} ms) over ${frame.length} frames; mid-drag points ${apart.toExponential(1)} of the diagonal from the whole product`,
  );
  assert.ok(apart <= SAME, `mid-drag points ${apart} of the diagonal from the whole product`);
  assert.match(await page.textContent('#notice'), /is big \(100000 curves\).*exact when you let go/);
  assert.ok(await allWritten(), 'after the release every element is written from the exact points');
  await page.screenshot({ path: join(out.path, 'rings.png') });
});

check('flag-icons\' Serbia (52 187 curves) follows a drag', { skip: !existsSync(SERBIA) && `${SERBIA} missing (npm ci in test-art)` }, async () => {
  const { middle, diagonal } = await pinned(SERBIA);
  const { apart, frame, product } = await dragMiddle(middle, diagonal);
  console.log(
    `big: Serbia, ${await page.evaluate(() => window.splineskinEditor.info.n_curves)} curves, Shepard, 3 pins: median frame ${median(frame).toFixed(1)} ms (product ${median(product).toFixed(1)} ms) over ${frame.length} frames`,
  );
  assert.ok(apart <= SAME, `mid-drag points ${apart} of the diagonal from the whole product`);
  assert.ok(await allWritten(), 'after the release every element is written from the exact points');
  await page.screenshot({ path: join(out.path, 'serbia.png') });
});
