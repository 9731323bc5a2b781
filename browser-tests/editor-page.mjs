// What the editor's browser tests do to its page, shared by them: open a file through the
// picker, read the page's state and the drawing's path data, find a drawing point on screen,
// drag with the mouse.

import { launchBrowser, startEditor } from './harness.mjs';

/** Longest wait for the editor (precomputation, uploads), ms. */
export const WAIT = 60_000;

/**
 * The editor served (`splineskin serve` with `args`: the bundled fish without), a browser of
 * `viewport` and a page of it, booted, its rig ready when `rig`: { page, close() }. The page's
 * errors are printed.
 */
export async function servedEditor({ viewport, args = [], rig = false } = {}) {
  const browser = await launchBrowser({ viewport });
  const server = await startEditor(args);
  const page = await browser.context.newPage();
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto(server.url);
  await page.waitForSelector('body[data-booted]', { timeout: WAIT });
  if (rig) await page.waitForSelector('body[data-rig="ready"]', { timeout: WAIT });
  return {
    page,
    server,
    browser,
    async close() {
      await browser.close();
      await server.close();
    },
  };
}

/** Opens `file` (a path, or { name, mimeType, buffer }) through the page's file picker and waits until it is shown. */
export async function openThroughPicker(p, file) {
  const name = typeof file === 'string' ? file.split('/').pop() : file.name;
  await p.setInputFiles('#open-file', file);
  await p.waitForFunction((n) => document.title.startsWith(n), name, { timeout: WAIT });
  // The page lays itself out again for the new drawing (its notices, the view's fit) in the
  // frames that follow: positions on screen are read after two.
  await p.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(() => ok()))));
}

/** The page's document description and scene. */
export function editorState(p) {
  return p.evaluate(() => {
    const e = window.splineskinEditor;
    return { info: e.info, scene: e.scene, rig: document.body.dataset.rig };
  });
}

/** The `d` of every marked element, by marker index. */
export function pathData(p) {
  return p.evaluate(() => {
    const d = [];
    for (const e of document.getElementById('canvas').shadowRoot.querySelectorAll('[data-splineskin-element]')) {
      d[Number(e.getAttribute('data-splineskin-element'))] = e.getAttribute('d');
    }
    return d;
  });
}

/** Client (CSS pixel) coordinates of drawing point [x, y]. */
export function clientPoint(p, [x, y]) {
  return p.evaluate(([x, y]) => window.splineskinEditor.view.toClient([x, y]), [x, y]);
}

/** The median of `values`. */
export function median(values) {
  const s = [...values].sort((a, b) => a - b);
  const m = s.length >> 1;
  return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
}

/** Drags with the mouse from drawing point `from` by `delta` (drawing units) in `steps` moves. */
export async function drag(p, from, delta, steps) {
  const [x0, y0] = await clientPoint(p, from);
  const [x1, y1] = await clientPoint(p, [from[0] + delta[0], from[1] + delta[1]]);
  await p.mouse.move(x0, y0);
  await p.mouse.down();
  for (let k = 1; k <= steps; k++) {
    await p.mouse.move(x0 + ((x1 - x0) * k) / steps, y0 + ((y1 - y0) * k) / steps);
    // One frame per move, as a user's drag gives.
    await p.evaluate(() => new Promise((ok) => requestAnimationFrame(() => ok())));
  }
  await p.mouse.up();
}
