// The keyboard as an Illustrator user has it: arrows nudge the selected pins (one screen pixel,
// ten with Shift) even while the Weights menu has the focus, which keeps its family; letters
// and Space never change a setting from a focused menu (Space pans); a menu chosen with the
// mouse gives the keyboard back.

import assert from 'node:assert/strict';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { outputFolder } from './harness.mjs';
import { WAIT, clientPoint, servedEditor } from './editor-page.mjs';

const VIEWPORT = { width: 1280, height: 800 };

const out = outputFolder('editor-keyboard');
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

/** The scene, the selection, the family and the view's frame and scale. */
const state = () =>
  page.evaluate(() => {
    const e = window.splineskinEditor;
    return {
      pose: structuredClone(e.scene.pose),
      selection: [...e.selection],
      family: e.scene.weights.family,
      menu: document.getElementById('family').value,
      frame: e.view.toUser(0, 0),
      unitsPerPixel: e.view.unitsPerPixel(),
    };
  });

/** Handle i's posed position (drawing units). */
async function posed(i) {
  const { pose } = await state();
  const handles = await page.evaluate(() => window.splineskinEditor.scene.handles);
  const [T, [x, y]] = [pose[i], handles[i]];
  return [T[0] * x + T[2] * y + T[4], T[1] * x + T[3] * y + T[5]];
}

check('arrows nudge the selected pin while the Weights menu has the focus, and the family stays', async () => {
  await page.mouse.click(...(await clientPoint(page, await posed(1))));
  const start = await state();
  assert.deepEqual(start.selection, [1], 'the clicked pin is selected');
  await page.focus('#family');
  assert.equal(await page.evaluate(() => document.activeElement.id), 'family');
  await page.keyboard.press('ArrowRight');
  await page.keyboard.press('Shift+ArrowDown');
  await page.keyboard.press('r'); // the first letter of "Rigid (ARAP)"
  await page.keyboard.press('End');
  const moved = await state();
  assert.equal(moved.family, start.family, 'the family is unchanged');
  assert.equal(moved.menu, start.menu, 'the menu shows the same entry');
  const u = start.unitsPerPixel;
  const [dx, dy] = [moved.pose[1][4] - start.pose[1][4], moved.pose[1][5] - start.pose[1][5]];
  assert.ok(Math.abs(dx - u) < 1e-9 * u && Math.abs(dy - 10 * u) < 1e-9 * u, `nudged by (${dx / u}, ${dy / u}) px, expected (1, 10)`);
  for (const i of [0, 2, 3, 4]) assert.deepEqual(moved.pose[i], start.pose[i], `pin ${i} stays`);
  // Each nudge is one undo step.
  await page.keyboard.press('Control+Z');
  await page.keyboard.press('Control+Z');
  assert.deepEqual((await state()).pose, start.pose, 'undone');
  await page.screenshot({ path: join(out.path, 'nudged.png') });
});

check('Space-drag pans with the menu focused; it neither opens the menu nor box-selects', async () => {
  await page.focus('#family');
  const before = await state();
  const [x, y] = [640, 600];
  await page.keyboard.down(' ');
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.mouse.move(x + 60, y - 40, { steps: 5 });
  await page.mouse.up();
  await page.keyboard.up(' ');
  const after = await state();
  assert.deepEqual(after.selection, before.selection, 'the selection is unchanged');
  assert.equal(after.family, before.family);
  const panned = [(after.frame[0] - before.frame[0]) / before.unitsPerPixel, (after.frame[1] - before.frame[1]) / before.unitsPerPixel];
  assert.ok(Math.abs(panned[0] + 60) < 1 && Math.abs(panned[1] - 40) < 1, `the view panned by ${panned} px`);
});

check('a family chosen with the mouse gives the keyboard back', async () => {
  // The menu is a native popup; a pointer press on it, then the change, as a click-and-pick does.
  await page.click('#family');
  await page.keyboard.press('Escape');
  await page.selectOption('#family', 'harmonic');
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  assert.notEqual(await page.evaluate(() => document.activeElement.id), 'family', 'the menu let go of the focus');
  await page.selectOption('#family', 'shepard');
  await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
});
