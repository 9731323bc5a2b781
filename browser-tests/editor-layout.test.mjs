// The editor's canvas holds still: messages of any length, the notice, the notes, the progress
// bar, the weight legend and the weights' option field come and go while the drawing, its pins
// and the canvas stay where they are to the pixel (a click aimed at a pin must land on it).

import assert from 'node:assert/strict';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { outputFolder } from './harness.mjs';
import { WAIT, servedEditor } from './editor-page.mjs';

const VIEWPORT = { width: 1280, height: 800 };
/** A text far longer than any row of the status bar. */
const LONG = 'a long message that goes on and on about what the editor is doing, '.repeat(12);

const out = outputFolder('editor-layout');
const check = (...args) => out.check(...args);
let session;
let page;

before(async () => {
  session = await servedEditor({ viewport: VIEWPORT, rig: true });
  page = session.page;
});

after(async () => {
  await session?.close();
  out.finish();
});

/** Where the canvas, its drawing and every pin marker are on screen (CSS pixels). */
function canvasGeometry() {
  return page.evaluate(() => {
    const root = document.getElementById('canvas');
    const boxes = [root, root.shadowRoot.querySelector('svg'), ...root.shadowRoot.querySelectorAll('.ss-handle')];
    return boxes.map((e) => {
      const r = e.getBoundingClientRect();
      return [r.left, r.top, r.width, r.height];
    });
  });
}

/** The largest move of any box of `now` from `then`, pixels. */
function largestMove(then, now) {
  assert.equal(now.length, then.length, 'the same boxes');
  return Math.max(...then.flatMap((box, i) => box.map((v, k) => Math.abs(v - now[i][k]))));
}

/** Waits two frames (the page lays itself out again in the frame after a change). */
const frames = () => page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(() => ok()))));

check('no part of the canvas moves while messages, notes, the notice and the progress bar come and go', async () => {
  const rest = await canvasGeometry();
  assert.ok(rest.length > 3, 'the canvas, its drawing and pins');
  const moves = [];
  const after = async (what) => {
    await frames();
    moves.push([what, largestMove(rest, await canvasGeometry())]);
  };
  // What the page's modules show, each at a length no row can hold, then taken away.
  const show = (name, ...args) =>
    page.evaluate(
      async ([name, args]) => {
        const messages = await import('./messages.js');
        messages[name](...args);
      },
      [name, args],
    );
  await show('say', LONG);
  await after('a long message');
  await show('showNotice', LONG);
  await after('a long notice');
  await show('showNote', 'fold-note', `7517 folds: ${LONG}`);
  await show('showNote', 'viewbox-note', `3 paths leave the viewBox: ${LONG}`);
  await after('long notes');
  await show('progress', `training the operator: ${LONG}`, 0.4);
  await after('the progress bar with a long label');
  await page.screenshot({ path: join(out.path, 'long-texts.png') });
  assert.ok(await page.isVisible('#status-more'), 'cut texts offer "more…"');
  await page.click('#status-more');
  await frames();
  assert.ok((await page.textContent('#status-details')).includes(LONG.trim()), 'the details view holds the message in full');
  await page.screenshot({ path: join(out.path, 'details.png') });
  await page.click('#status-details');
  await show('progress', null);
  await show('showNote', 'fold-note', '');
  await show('showNote', 'viewbox-note', '');
  await show('showNotice', '');
  await show('say', 'ready');
  await after('all taken away');
  // What the page does by itself: the weight field's legend, another family's precomputation
  // (its progress bar), the operators' samples field in place of the margin.
  await page.check('#show-weights');
  await after('the weight legend shown');
  await page.uncheck('#show-weights');
  await page.selectOption('#family', 'harmonic');
  await page.waitForSelector('#progress:not([hidden])', { timeout: WAIT });
  await after('the weights computing');
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  await after('the weights computed');
  await page.selectOption('#family', 'defop-arap');
  await after('an operator family (samples field, training progress)');
  await page.selectOption('#family', 'shepard');
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  await after('back to the first family');
  for (const [what, px] of moves) console.log(`layout: ${what}: the canvas moved ${px.toFixed(2)} px`);
  for (const [what, px] of moves) assert.ok(px < 0.5, `${what}: the canvas moved ${px} px`);
});
