// The editor's timeline as an animator uses it, on the bundled fish drawing opened bare (no pins,
// no animation): three pins clicked onto the art, three keyframes set by keying and dragging
// pins at three times, an eased segment, playback paused between keyframes, keyframes moved,
// duplicated and deleted with undo; then the saved scene through `splineskin animate`: the
// drawing the editor shows at a time between keyframes equals the command's frame at that time
// to 1e-9 of the drawing's diagonal. And the session comes back after a reload.

import assert from 'node:assert/strict';
import { readFileSync, readdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { REPO, launchBrowser, outputFolder, runSplineskin, startEditor, pathNumbersById } from './harness.mjs';

const VIEWPORT = { width: 1280, height: 800 };
const WAIT = 60_000;
const DEMO_SVG = join(REPO, 'crates', 'splineskin', 'assets', 'demo.svg');
/** The editor's drawing against the command's frame, relative to the diagonal. */
const SAME = 1e-9;

const out = outputFolder('editor-timeline');
const check = (...args) => out.check(...args);
let browser;
let server;
let page;

before(async () => {
  browser = await launchBrowser({ viewport: VIEWPORT });
  server = await startEditor([DEMO_SVG]);
  page = await browser.context.newPage();
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto(server.url);
  await page.waitForSelector('body[data-booted]', { timeout: WAIT });
});

after(async () => {
  await browser?.close();
  await server?.close();
  out.finish();
});

const editorState = () =>
  page.evaluate(() => {
    const e = window.splineskinEditor;
    return { scene: structuredClone(e.scene), time: e.time, selectedKey: e.selectedKey, selection: [...e.selection] };
  });

/** Client coordinates of drawing point p. */
const client = (p) =>
  page.evaluate(([x, y]) => {
    return window.splineskinEditor.view.toClient([x, y]);
  }, p);

async function posed(i) {
  const { scene } = await editorState();
  const [T, [x, y]] = [scene.pose[i], scene.handles[i]];
  return [T[0] * x + T[2] * y + T[4], T[1] * x + T[3] * y + T[5]];
}

async function mouseDrag(from, to, { steps = 8, modifier } = {}) {
  if (modifier) await page.keyboard.down(modifier);
  await page.mouse.move(...from);
  await page.mouse.down();
  for (let k = 1; k <= steps; k++) {
    await page.mouse.move(from[0] + ((to[0] - from[0]) * k) / steps, from[1] + ((to[1] - from[1]) * k) / steps);
  }
  await page.mouse.up();
  if (modifier) await page.keyboard.up(modifier);
}

async function waitRig() {
  await page.waitForFunction(() => ['ready', 'error'].includes(document.body.dataset.rig), null, { timeout: WAIT });
  const error = await page.evaluate(() => (document.body.dataset.rig === 'error' ? document.getElementById('error').textContent : null));
  assert.equal(error, null);
}

/** Resolves once the page has drawn its next animation frame (the drawing follows the time). */
const drawn = () => page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok))));

/** Clicks the ruler at time t (it snaps to the frame) and waits for the drawing. */
async function clickRuler(t) {
  const x = await page.evaluate((t) => window.splineskinEditor.ruler.clientX(t), t);
  const box = await page.locator('#ruler').boundingBox();
  await page.mouse.click(x, box.y + box.height - 4);
  await drawn();
}

/**
 * The numbers of every element's path data with an id, at full precision, as the page's
 * drawing has them (chain points mapped into the element's own coordinates).
 */
const shownNumbers = () =>
  page.evaluate(() => {
    const e = window.splineskinEditor;
    const { view, info, points } = e;
    const result = {};
    info.elements.forEach((el, k) => {
      const node = view.elements[k];
      if (!node?.id) return;
      const T = view.localMaps[k];
      const numbers = [];
      for (let p = el.first_path; p < el.end_path; p++) {
        const path = info.paths[p];
        const o = view.offsets[p];
        for (let i = 0; i < path.n_points; i++) {
          const q = path.closed && i === path.n_points - 1 ? o : o + i;
          const [x, y] = [points[2 * q], points[2 * q + 1]];
          numbers.push(...(T ? [T[0] * x + T[2] * y + T[4], T[1] * x + T[3] * y + T[5]] : [x, y]));
        }
      }
      result[node.id] = numbers;
    });
    return result;
  });


let savedScene = null;

check('three pins on the art, three keyframes by keying and dragging, an eased segment', async () => {
  // A quick family for the test: the timeline is the same with any.
  await page.selectOption('#family', 'shepard');
  for (const p of [[440, 200], [300, 230], [120, 205]]) {
    await page.mouse.click(...(await client(p)));
  }
  await waitRig();
  let state = await editorState();
  assert.equal(state.scene.handles.length, 3, 'three pins');
  assert.equal(state.scene.animation ?? null, null, 'no keyframes yet');

  // Keyframe 0: the rest pose at 0 s.
  await page.click('#key-pose');
  state = await editorState();
  assert.equal(state.scene.animation.keyframes.length, 1);
  assert.equal(state.scene.animation.keyframes[0].time, 0);

  // Keyframe 1 at 1 s: dragging pins keys them there (the nose up, the tail turned).
  await clickRuler(1);
  assert.equal((await editorState()).time, 1, 'the ruler snaps to frames');
  await mouseDrag(await client(await posed(0)), (await client(await posed(0))).map((v, k) => v + [30, -40][k]));
  await page.mouse.click(...(await client(await posed(2))));
  assert.ok(await page.isEnabled('#key-pins'), 'a selected pin can be keyed alone');
  await mouseDrag(await client(await posed(2)), (await client(await posed(2))).map((v, k) => v + [70, 10][k]), { modifier: 'Shift' });
  state = await editorState();
  assert.deepEqual(state.scene.animation.keyframes.map((k) => k.time), [0, 1], 'dragging keyed the pins at 1 s');
  const turned = state.scene.animation.keyframes[1].pose[2];
  assert.ok(Math.abs(Math.atan2(turned[1], turned[0])) > 0.3, 'the tail pin is turned in keyframe 1');

  // Keyframe 2 at 2 s: the middle pin moves down.
  await clickRuler(2);
  await mouseDrag(await client(await posed(1)), (await client(await posed(1))).map((v, k) => v + [0, 50][k]));
  state = await editorState();
  assert.deepEqual(state.scene.animation.keyframes.map((k) => k.time), [0, 1, 2]);

  // The first segment eases in and out: select keyframe 0 on the ruler, pick the easing.
  await clickRuler(0);
  await page.evaluate(() => window.splineskinEditor.selectedKey);
  const diamond = page.locator('#ruler .key').first();
  await diamond.click();
  assert.equal((await editorState()).selectedKey, 0);
  await page.selectOption('#easing', 'ease-in-out');
  state = await editorState();
  assert.equal(state.scene.animation.keyframes[0].easing, 'ease-in-out');
  assert.equal(state.scene.animation.keyframes[1].easing, 'linear');
  await page.screenshot({ path: join(out.path, 'timeline-keyed.png') });
});

check('onion skin outlines the keyframes before and after the shown time', async () => {
  await clickRuler(1.5);
  await page.check('#onion');
  const d = await page.evaluate(() =>
    [...document.getElementById('canvas').shadowRoot.querySelectorAll('.ss-onion')].map((p) => p.getAttribute('d') ?? ''),
  );
  assert.equal(d.length, 2);
  assert.ok(d[0].length > 100 && d[1].length > 100, 'both outlines drawn');
  assert.notEqual(d[0], d[1], 'two different poses');
  await page.screenshot({ path: join(out.path, 'timeline-onion.png') });
  await page.uncheck('#onion');
});

check('keyframes move, duplicate and delete on the ruler, and undo steps back through them', async () => {
  let state = await editorState();
  const keysBefore = structuredClone(state.scene.animation.keyframes);
  // Drag keyframe 1 from 1 s to 1.2 s.
  const box = await page.locator('#ruler').boundingBox();
  const y = box.y + 9;
  const x1 = await page.evaluate(() => window.splineskinEditor.ruler.clientX(1));
  const x12 = await page.evaluate(() => window.splineskinEditor.ruler.clientX(1.2));
  await mouseDrag([x1, y], [x12, y]);
  state = await editorState();
  assert.deepEqual(state.scene.animation.keyframes.map((k) => k.time), [0, 1.2, 2], 'moved to 1.2 s');
  // It cannot pass its neighbour.
  const x3 = await page.evaluate(() => window.splineskinEditor.ruler.clientX(2.5));
  await mouseDrag([x12, y], [x3, y]);
  state = await editorState();
  const times = state.scene.animation.keyframes.map((k) => k.time);
  assert.ok(times[1] < times[2] && times[2] === 2, `still in order: ${times}`);
  await page.keyboard.press('Control+z');
  await page.keyboard.press('Control+z');
  state = await editorState();
  assert.deepEqual(state.scene.animation.keyframes, keysBefore, 'undo: the keyframes as they were');

  // Duplicate keyframe 1 to 2.5 s, then delete the copy; undo brings it back, redo removes it.
  await page.locator('#ruler .key').nth(1).click();
  await clickRuler(2.5);
  await page.evaluate(() => (window.splineskinEditor.selectedKey = 1));
  await page.click('#duplicate-key');
  state = await editorState();
  assert.deepEqual(state.scene.animation.keyframes.map((k) => k.time), [0, 1, 2, 2.5]);
  assert.deepEqual(state.scene.animation.keyframes[3].pose, state.scene.animation.keyframes[1].pose, 'the copy has the pose');
  await page.click('#delete-key');
  state = await editorState();
  assert.deepEqual(state.scene.animation.keyframes, keysBefore, 'deleted');
  await page.click('#undo');
  assert.equal((await editorState()).scene.animation.keyframes.length, 4, 'undo: back');
  await page.click('#redo');
  assert.deepEqual((await editorState()).scene.animation.keyframes, keysBefore, 'redo: gone again');
});

check('played and paused between keyframes, the drawing equals `splineskin animate`\'s frame at that time', async () => {
  await clickRuler(0);
  await page.click('#play');
  assert.equal(await page.evaluate(() => document.body.dataset.playing), '1', 'playing');
  await page.waitForTimeout(700);
  await page.click('#play');
  let state = await editorState();
  assert.equal(await page.evaluate(() => document.body.dataset.playing ?? null), null, 'paused');
  // Between keyframes 0 and 1 (the eased segment), or step there frame by frame.
  while (state.time === 0 || state.time === 1 || state.time >= 2) {
    await page.keyboard.press(state.time >= 2 ? ',' : '.');
    await drawn();
    state = await editorState();
  }
  const fps = state.scene.animation.fps;
  const frame = Math.round(state.time * fps);
  assert.equal(frame / fps, state.time, 'paused on a frame');
  const times = [state.time];
  const shown = [await shownNumbers()];
  // And a time in the second segment, by scrubbing.
  await clickRuler(1.5);
  times.push((await editorState()).time);
  shown.push(await shownNumbers());
  await page.screenshot({ path: join(out.path, 'timeline-paused.png') });

  // The saved scene, played by the command.
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#save-scene')]);
  const scenePath = join(out.path, 'timeline-scene.json');
  await download.saveAs(scenePath);
  savedScene = JSON.parse(readFileSync(scenePath, 'utf8'));
  assert.equal(savedScene.animation.keyframes.length, 3, 'the timeline is in the scene file');
  assert.equal(savedScene.animation.keyframes[0].easing, 'ease-in-out');
  const frames = join(out.path, 'frames');
  await runSplineskin(['animate', scenePath, '-o', frames]);
  const files = readdirSync(frames).filter((f) => f.endsWith('.svg')).sort();
  assert.equal(files.length, Math.ceil(2 * fps) + 1, 'frames 0 … 2 s');
  const [, , w, h] = await page.evaluate(() => window.splineskinEditor.info.view_box);
  const diagonal = Math.hypot(w, h);
  times.forEach((t, n) => {
    const f = Math.round(t * fps);
    const truth = pathNumbersById(readFileSync(join(frames, files[f]), 'utf8'));
    let compared = 0;
    let worst = 0;
    for (const [id, numbers] of Object.entries(shown[n])) {
      const want = truth[id];
      if (!want) continue;
      assert.equal(numbers.length, want.length, `${id}: as many numbers`);
      numbers.forEach((v, k) => (worst = Math.max(worst, Math.abs(v - want[k]))));
      compared++;
    }
    assert.ok(compared >= 5, `${compared} paths compared at frame ${f}`);
    console.log(`timeline: t = ${t.toFixed(4)} s (frame ${f}): ${compared} paths, largest difference ${(worst / diagonal).toExponential(2)} of the diagonal`);
    assert.ok(worst <= SAME * diagonal, `frame ${f}: ${worst} > ${SAME} of the diagonal`);
  });
});

check('Export Lottie downloads what `splineskin animate -o anim.json` writes of the saved scene', async () => {
  assert.ok(savedScene, 'the scene was saved by the test before');
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-lottie')]);
  const fromEditor = join(out.path, 'editor.json');
  await download.saveAs(fromEditor);
  const report = await page.evaluate(() => window.splineskinEditor.lottieReport);
  const cli = join(out.path, 'cli.json');
  const stderr = await runSplineskin(['animate', join(out.path, 'timeline-scene.json'), '-o', cli]);
  const [a, b] = [fromEditor, cli].map((f) => JSON.parse(readFileSync(f, 'utf8')));
  // The animation's name is the file's (the drawing's in the editor, the scene's on the command line).
  for (const x of [a, b]) {
    delete x.nm;
    delete x.layers[0].nm;
  }
  assert.deepEqual(a, b, 'the same animation');
  assert.ok(report.keyframes > 0 && report.keyframes <= report.every_frame_keyframes);
  assert.ok(stderr.includes(`${report.keyframes} path keyframes of ${report.every_frame_keyframes}`), stderr);
  console.log(`timeline: Lottie from the editor: ${report.summary}`);
  assert.match(await page.textContent('#message'), /exported demo\.json/);
});

check('Export animation writes the animated SVG, GIF and APNG that `splineskin animate` writes of the saved scene', async () => {
  const scenePath = join(out.path, 'timeline-scene.json');
  for (const [format, ending] of [['svg', 'svg'], ['gif', 'gif'], ['apng', 'png']]) {
    await page.selectOption('#animation-format', format);
    const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-animation')]);
    const fromPage = readFileSync(await download.path());
    const cli = join(out.path, `cli.${ending}`);
    await runSplineskin(['animate', scenePath, '-o', cli]);
    const fromCli = readFileSync(cli);
    console.log(`timeline: Export animation ${format}: ${fromPage.length} bytes (the command's: ${fromCli.length})`);
    assert.ok(fromPage.equals(fromCli), `${format}: the page's file equals the command's`);
    assert.match(await page.textContent('#message'), new RegExp(`exported demo\\.${ending}`));
  }
});

check('a reload brings the session back: pins, keyframes, the shown time', async () => {
  const state = await editorState();
  await page.waitForFunction(() => document.body.dataset.autosaved, null, { timeout: WAIT });
  await page.waitForTimeout(400);
  await page.reload();
  await page.waitForSelector('body[data-booted]', { timeout: WAIT });
  await waitRig();
  const back = await editorState();
  assert.equal(await page.evaluate(() => document.body.dataset.recovered), '1');
  assert.deepEqual(back.scene.handles, state.scene.handles);
  assert.deepEqual(back.scene.animation, state.scene.animation);
  assert.deepEqual(back.scene.pose, state.scene.pose);
  assert.equal(back.time, state.time);
  await page.screenshot({ path: join(out.path, 'timeline-reloaded.png') });
  writeFileSync(join(out.path, 'notice.txt'), await page.locator('#notice').textContent());
});

check('the ruler fits the animation: a click at its end keys there, the wheel zooms about the pointer', async () => {
  const box = await page.locator('#ruler').boundingBox();
  assert.ok(box.width > 0.6 * VIEWPORT.width, `the ruler is ${box.width} px wide`);
  const keyTimes = async () => (await editorState()).scene.animation.keyframes.map((k) => k.time);
  const before = await keyTimes();
  // The last second shown, at the ruler's right end (a click on its border's last pixel).
  const end = await page.evaluate(() => {
    const r = window.splineskinEditor.ruler;
    return r.window.start + r.window.span;
  });
  await page.mouse.click(box.x + box.width - 1, box.y + box.height / 2);
  await drawn();
  const fpsNow = await page.evaluate(() => Number(document.getElementById('fps').value));
  const t = (await editorState()).time;
  assert.ok(Math.abs(t - end) <= 0.5 / fpsNow, `the click went to ${t} s, the ruler's end is ${end} s`);
  await page.click('#key-pose');
  const after = await keyTimes();
  assert.deepEqual(after, [...before, t], 'a new keyframe at the end, the others kept');
  // The ruler grew to show room after it: the new diamond is not at its edge.
  const x = await page.evaluate((t) => window.splineskinEditor.ruler.clientX(t), t);
  assert.ok(x < box.x + box.width - 40, `the new key is drawn at ${x}, inside the ruler ending at ${box.x + box.width}`);
  // The wheel zooms in about the pointer: the time under it stays put.
  const at = box.x + box.width / 3;
  const under = () => page.evaluate((at) => {
    const r = window.splineskinEditor.ruler;
    const { left, width } = r.scale();
    return r.window.start + ((at - left) / width) * r.window.span;
  }, at);
  const t0 = await under();
  const span0 = await page.evaluate(() => window.splineskinEditor.ruler.window.span);
  await page.mouse.move(at, box.y + box.height / 2);
  await page.mouse.wheel(0, -300);
  await drawn();
  const span1 = await page.evaluate(() => window.splineskinEditor.ruler.window.span);
  assert.ok(span1 < 0.7 * span0, `zoomed in: ${span0} s → ${span1} s`);
  const t1 = await under();
  assert.ok(Math.abs(t1 - t0) < 1e-9 * span0 + 0.01 * span1, `the time under the pointer stays: ${t0} s → ${t1} s`);
  await page.screenshot({ path: join(out.path, 'timeline-zoomed.png') });
  await page.mouse.dblclick(at, box.y + box.height / 2);
  await drawn();
  assert.equal(await page.evaluate(() => window.splineskinEditor.ruler.window.zoomed), false, 'a double-click fits it again');
});
