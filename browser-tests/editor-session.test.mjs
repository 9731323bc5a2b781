// The editor's autosave as a user meets it: a drawing of 3 MB (most of it metadata, as
// Illustrator writes) opened through the picker, pinned and dragged, comes back after a reload
// with its pins and pose; and when the browser refuses to store, the page says so instead of
// losing the session silently.

import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { launchBrowser, outputFolder, startEditor } from './harness.mjs';
import { WAIT, clientPoint, drag, editorState, openThroughPicker } from './editor-page.mjs';

const VIEWPORT = { width: 1280, height: 800 };
/** Characters of metadata in the large drawing: with its art, over 3 MB. */
const METADATA_CHARS = 3_100_000;

const out = outputFolder('editor-session');
const check = (...args) => out.check(...args);
let browser;
let server;

before(async () => {
  browser = await launchBrowser({ viewport: VIEWPORT });
  server = await startEditor([]);
});

after(async () => {
  await browser?.close();
  await server?.close();
  out.finish();
});

/** A new page of the editor, booted (`initScript` runs before the page's own scripts). */
async function freshPage({ initScript } = {}) {
  const page = await browser.context.newPage();
  if (initScript) await page.addInitScript(initScript);
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto(server.url);
  await page.waitForSelector('body[data-booted]', { timeout: WAIT });
  return page;
}

/** A drawing of two shapes carrying `METADATA_CHARS` characters of metadata. */
function largeDrawing() {
  const words = 'lorem ipsum dolor sit amet consectetur adipiscing elit ';
  const metadata = words.repeat(Math.ceil(METADATA_CHARS / words.length));
  const svg =
    '<svg xmlns="http://www.w3.org/2000/svg" width="400" height="200" viewBox="0 0 400 200">' +
    `<metadata><x:description xmlns:x="urn:example">${metadata}</x:description></metadata>` +
    '<path id="body" d="M20 100 C60 20 140 20 180 100 C220 180 300 180 380 100 L380 160 L20 160 Z" fill="#e86"/>' +
    '<rect id="block" x="150" y="40" width="100" height="40" fill="#68c"/></svg>';
  const file = join(out.path, 'large.svg');
  writeFileSync(file, svg);
  return { file, bytes: svg.length };
}

/** Alt-clicks a pin at drawing point `p` and waits for the rig. */
async function pinAt(page, p) {
  const [x, y] = await clientPoint(page, p);
  await page.keyboard.down('Alt');
  await page.mouse.click(x, y);
  await page.keyboard.up('Alt');
  await page.waitForFunction(() => ['ready', 'error'].includes(document.body.dataset.rig), null, { timeout: WAIT });
}

check('a 3 MB drawing\'s session (pins and a drag) comes back after a reload', async () => {
  const { file, bytes } = largeDrawing();
  assert.ok(bytes > 3_000_000, `${bytes} bytes`);
  const page = await freshPage();
  await openThroughPicker(page, file);
  for (const p of [[40, 130], [200, 100], [360, 130]]) await pinAt(page, p);
  await drag(page, [360, 130], [0, -60], 6);
  await page.waitForFunction(() => window.splineskinEditor.scene.pose[2][5] < -30, null, { timeout: WAIT });
  const before = await editorState(page);
  assert.equal(before.scene.handles.length, 3);
  // The save after the drag (a burst is saved 150 ms after its last change).
  await page.waitForTimeout(300);
  await page.waitForFunction(() => document.body.dataset.autosaved && !document.body.dataset.autosaveFailed, null, { timeout: WAIT });
  await page.reload();
  await page.waitForSelector('body[data-booted]', { timeout: WAIT });
  assert.equal(await page.evaluate(() => document.body.dataset.recovered), '1', 'the session is restored');
  const back = await editorState(page);
  assert.ok(back.info.name.endsWith('large.svg'), `the large drawing is open again, not ${back.info.name}`);
  assert.deepEqual(back.scene.handles, before.scene.handles);
  assert.deepEqual(back.scene.pose, before.scene.pose);
  assert.match(await page.textContent('#notice'), /restored your session/);
  await page.screenshot({ path: join(out.path, 'large-restored.png') });
  await page.close();
});

check('when the browser refuses to store, the page says the session is not kept', async () => {
  // A browser whose storage refuses every database (as a full disk or a locked-down profile does).
  const page = await freshPage({
    initScript: () => {
      IDBFactory.prototype.open = function () {
        throw new DOMException('storage refused for the test', 'QuotaExceededError');
      };
    },
  });
  await pinAt(page, [150, 100]);
  await page.waitForFunction(() => document.body.dataset.autosaveFailed, null, { timeout: WAIT });
  const notice = page.locator('#notice');
  assert.ok(await notice.isVisible(), 'the notice is shown');
  assert.match(await notice.textContent(), /autosave failed \(storage refused for the test\).*Save scene/);
  await page.screenshot({ path: join(out.path, 'autosave-failed.png') });
  await page.close();
});
