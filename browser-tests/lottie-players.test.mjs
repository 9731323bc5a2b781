// Our Lottie in the players beyond lottie-web (lottie.test.mjs) that run here: Skia's Skottie
// (npm canvaskit-wasm, its full build, on a CPU surface under Node) plays the `.json`, and the
// dotLottie player (npm @lottiefiles/dotlottie-web: ThorVG in WebAssembly, in chromium) opens
// the `.lottie` archive. Each frame drawn is compared with our own rendering of the same frame
// (`splineskin animate -o DIR/ --png`): the mean difference per channel (of 255) over the
// picture flattened on white, with a control, the same player's frame against a frame of ours
// posed otherwise, which must differ far more. Three animations: the bundled fish (gradients),
// and our scenes on two real emoji nobody here drew, Noto's flamingo (gradients) and OpenMoji's
// turtle (test-art's npm packages). rlottie and ThorVG's own build are played by the Python
// tests (python/tests/test_lottie_players.py).

import assert from 'node:assert/strict';
import { copyFileSync, existsSync, readFileSync, readdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import CanvasKitInit from 'canvaskit-wasm/bin/full/canvaskit.js';

import { launchBrowser, outputFolder, REPO, runSplineskin, serveFolder } from './harness.mjs';
import { decodePng } from './png.mjs';

const MODULES = join(REPO, 'browser-tests', 'node_modules');
const ART = join(REPO, 'test-art', 'node_modules');
const NOTO = join(ART, '@iconify-json', 'noto', 'icons.json');
const TURTLE = join(ART, 'openmoji', 'color', 'svg', '1F422.svg');
const NO_ART = !(existsSync(NOTO) && existsSync(TURTLE)) && `${ART}: the art packages are missing (npm ci in test-art)`;
if (NO_ART && process.env.CI) throw new Error(NO_ART);

/**
 * Mean difference per channel (of 255) within which a player's frame is ours (measured over
 * every frame: Skottie at most 1.03, the dotLottie player 1.40, both on the fish).
 */
const SAME = 2.5;
/** How much more a frame of ours posed otherwise must differ. */
const CONTROL_RATIO = 3;

const out = outputFolder('lottie-players');
const check = (...args) => out.check(...args);
/** Per animation: { json, lottie, frames: [file…] } in the outputs. */
const made = {};
let browser;
let site;

/** The input and pose arguments of each animation (the art written into the outputs). */
function animations() {
  const list = { fish: [join(REPO, 'crates', 'splineskin', 'assets', 'demo-scene.json')] };
  if (NO_ART) return list;
  const noto = JSON.parse(readFileSync(NOTO, 'utf8'));
  const flamingo = join(out.path, 'flamingo.svg');
  writeFileSync(flamingo, `<svg xmlns="http://www.w3.org/2000/svg" width="256" height="256" viewBox="0 0 ${noto.width} ${noto.height}">${noto.icons.flamingo.body}</svg>`);
  list.flamingo = [flamingo, '--pins', '4', '--rotate', '2:30'];
  list.turtle = [TURTLE, '--pins', '4', '--move', '1:8,-6'];
  return list;
}

before(async () => {
  for (const [name, args] of Object.entries(animations())) {
    const json = join(out.path, `${name}.json`);
    const lottie = join(out.path, `${name}.lottie`);
    const frames = join(out.path, `${name}-frames`);
    await runSplineskin(['animate', ...args, '-o', json]);
    await runSplineskin(['animate', ...args, '-o', lottie]);
    await runSplineskin(['animate', ...args, '-o', `${frames}/`, '--png']);
    // The archive names its animation after the input's file name.
    const id = args[0].split('/').pop().replace(/\.[^.]*$/, '');
    made[name] = { id, json, lottie, frames: readdirSync(frames).filter((f) => f.endsWith('.png')).sort().map((f) => join(frames, f)) };
  }
  const player = join(MODULES, '@lottiefiles', 'dotlottie-web', 'dist');
  copyFileSync(join(player, 'index.js'), join(out.path, 'dotlottie-web.js'));
  copyFileSync(join(player, 'dotlottie-player.wasm'), join(out.path, 'dotlottie-player.wasm'));
  site = await serveFolder(out.path);
  browser = await launchBrowser({ viewport: { width: 1300, height: 1300 } });
});

after(async () => {
  await browser?.close();
  await site?.close();
  out.finish();
});

/** RGB of an RGBA picture flattened on white (floats, 3 per pixel). */
function flattened({ width, height, data }) {
  const rgb = new Float32Array(3 * width * height);
  for (let i = 0; i < width * height; i++) {
    const a = data[4 * i + 3] / 255;
    for (let c = 0; c < 3; c++) rgb[3 * i + c] = data[4 * i + c] * a + 255 * (1 - a);
  }
  return rgb;
}

/** Mean absolute difference per channel of two flattened pictures of the same size. */
function meanDifference(a, b) {
  assert.equal(a.length, b.length, 'pictures of the same size');
  let sum = 0;
  for (let i = 0; i < a.length; i++) sum += Math.abs(a[i] - b[i]);
  return sum / a.length;
}

/**
 * Compares `played(f, width, height)` (a flattened picture) with our frame of `name` at every
 * frame; at the rest, the pose and five sixths of the way also against a control, the frame
 * farthest from it in pose. Returns the report.
 */
async function compareFrames(name, player, played) {
  const frames = made[name].frames;
  const n = frames.length;
  const ours = (f) => decodePng(readFileSync(frames[f]));
  const controlled = [0, Math.floor(n / 2), Math.floor((5 * n) / 6)];
  const report = [];
  let worst = 0;
  for (let f = 0; f < n; f++) {
    const expected = ours(f);
    const got = await played(f, expected.width, expected.height);
    const same = meanDifference(got, flattened(expected));
    worst = Math.max(worst, same);
    assert.ok(same <= SAME, `${name}, ${player}, frame ${f}: ${same.toFixed(2)}/255 from ours`);
    if (controlled.includes(f)) {
      const control = meanDifference(got, flattened(ours(f === 0 ? Math.floor(n / 2) : 0)));
      report.push(`frame ${f}: ${same.toFixed(2)} (control ${control.toFixed(2)})`);
      assert.ok(control >= CONTROL_RATIO * same, `${name}, ${player}, frame ${f}: the control differs by only ${control.toFixed(2)}`);
    }
  }
  return `${name} in ${player}: ${n} frames, largest ${worst.toFixed(2)}; ${report.join('; ')}`;
}

check('Skottie (canvaskit-wasm) plays our Lottie as we draw it', async () => {
  const kit = await CanvasKitInit({ locateFile: (file) => join(MODULES, 'canvaskit-wasm', 'bin', 'full', file) });
  for (const name of Object.keys(made)) {
    const animation = kit.MakeAnimation(readFileSync(made[name].json, 'utf8'));
    assert.ok(animation, `${name}: Skottie reads the file`);
    assert.equal(Math.round(animation.duration() * animation.fps()) + 1, made[name].frames.length, `${name}: one frame of ours per Lottie frame`);
    let surface = null;
    const report = await compareFrames(name, 'Skottie', (f, width, height) => {
      surface ??= kit.MakeSurface(width, height);
      const canvas = surface.getCanvas();
      canvas.clear(kit.WHITE);
      animation.seekFrame(f);
      animation.render(canvas, kit.LTRBRect(0, 0, width, height));
      surface.flush();
      const pixels = surface.makeImageSnapshot().readPixels(0, 0, {
        width, height, colorType: kit.ColorType.RGBA_8888, alphaType: kit.AlphaType.Unpremul, colorSpace: kit.ColorSpace.SRGB,
      });
      return flattened({ width, height, data: pixels });
    });
    console.log(report);
    surface?.delete();
    animation.delete();
  }
});

check('the dotLottie player opens our .lottie and plays it as we draw it', async () => {
  for (const name of Object.keys(made)) {
    const { width, height } = decodePng(readFileSync(made[name].frames[0]));
    const html = join(out.path, `${name}-player.html`);
    writeFileSync(html, `<!doctype html><html><body style="margin:0">
<canvas id="c" width="${width}" height="${height}" style="width:${width}px;height:${height}px"></canvas>
<script type="module">
import { DotLottie } from './dotlottie-web.js';
DotLottie.setWasmUrl(new URL('./dotlottie-player.wasm', import.meta.url).href);
const player = new DotLottie({ canvas: document.getElementById('c'), src: './${name}.lottie', autoplay: false,
  renderConfig: { devicePixelRatio: 1, autoResize: false } });
player.addEventListener('load', () => { window.player = player; });
player.addEventListener('loadError', (e) => { window.failed = String(e.error ?? 'load error'); });
</script></body></html>`);
    const page = await browser.context.newPage();
    try {
      await page.goto(site.url(`${name}-player.html`));
      await page.waitForFunction(() => window.player || window.failed, null, { timeout: 60_000 });
      const opened = await page.evaluate(() => ({ failed: window.failed, total: window.player?.totalFrames, manifest: window.player?.manifest }));
      assert.equal(opened.failed, undefined, `${name}: ${opened.failed}`);
      assert.equal(opened.manifest.animations[0].id, made[name].id, 'the archive\'s manifest names the animation');
      assert.equal(opened.total + 1, made[name].frames.length, `${name}: one frame of ours per Lottie frame`);
      const report = await compareFrames(name, 'the dotLottie player', async (f) => {
        const png = await page.evaluate(async (f) => {
          window.player.setFrame(f);
          await new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok)));
          return document.getElementById('c').toDataURL('image/png');
        }, f);
        return flattened(decodePng(Buffer.from(png.split(',')[1], 'base64')));
      });
      console.log(report);
      await page.screenshot({ path: join(out.path, `${name}-dotlottie.png`) });
    } finally {
      await page.close();
    }
  }
});
