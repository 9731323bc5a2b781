// The Catmull–Clark page of `splineskin serve` (/subdiv/index.html) as a person uses it in
// chromium (WebGL2 through its software rasteriser): open the bundled tube through the file
// picker and see its limit surface shaded; drag to orbit, wheel to zoom, show the cage; a broken
// OBJ is refused with a message naming the file and line. Screenshots are kept on failure (or
// with BROWSER_TESTS_OUT).

import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { launchBrowser, outputFolder, REPO, startEditor } from './harness.mjs';
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
