// `splineskin animate -o anim.json` (Lottie) played by lottie-web in chromium.
//
// For each drawing (the bundled fish, the bundled octopus, a real flag with gradients from the
// flag-icons package, a real emoji with gradients: Noto's tropical fish) the same animation is written twice: as Lottie, and as a folder of SVG
// frames at the same frame rate. The Lottie file is validated against the Lottie community's
// JSON schema; then lottie-web plays it, paused at every frame time (most of them between the
// Lottie keyframes, which the export thins out), and the path data lottie-web draws for each
// element is compared with that element's path data in the SVG frame of that time, and a
// screenshot of lottie-web's frame with chromium's rendering of the SVG frame.

import assert from 'node:assert/strict';
import { copyFileSync, existsSync, mkdirSync, readFileSync, readdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import Ajv2020 from 'ajv/dist/2020.js';

import { launchBrowser, outputFolder, REPO, runSplineskin, serveFolder } from './harness.mjs';
import { compareImages, decodePng, encodePng, inkFraction } from './png.mjs';

const ASSETS = join(REPO, 'crates', 'splineskin', 'assets');
const MODULES = join(REPO, 'browser-tests', 'node_modules');
const SCHEMA = join(MODULES, '@lottie-animation-community', 'lottie-specs', 'src', 'data', 'lottie.schema.json');
const PLAYER = join(MODULES, 'lottie-web', 'build', 'player', 'lottie_svg.min.js');
const FLAG = join(REPO, 'test-art', 'node_modules', 'flag-icons', 'flags', '4x3', 'gs.svg');
// A flag whose art is clipped (a clip path cropping its stripes): Lottie masks it.
const CLIPPED_FLAG = join(REPO, 'test-art', 'node_modules', 'flag-icons', 'flags', '4x3', 'cu.svg');
// Google's Noto emoji, as the Iconify package carries them (an icon's body, 128 × 128 units).
const NOTO = join(REPO, 'test-art', 'node_modules', '@iconify-json', 'noto', 'icons.json');

// What lottie-web's path data adds to the export's tolerance (which its report states, in the
// drawing's units): it writes coordinates with 3 decimals.
const PRINT_ROUNDING = 5e-4;
// Mean absolute difference per channel (0–255) between lottie-web's frame and chromium's
// rendering of the SVG frame. Between keyframes the shapes may be off by the tolerance (0.6–0.8
// px here), which moves every edge's anti-aliasing: measured up to 0.02 on the octopus, 0.63 on
// the fish (also its bounding-box gradients, which SVG refits to the deformed box and Lottie
// carries with the element's map) and 1.65 on the flag (2 000 curves of edges). The control
// below checks that a wrong frame (the rest pose) exceeds it.
const PIXEL_TOLERANCE = 2;

const FPS = 10;

const out = outputFolder('lottie');
let browser;
let server;
let ajv;

/** A test whose failure keeps the outputs folder. */
const check = (...args) => out.check(...args);

before(async () => {
  try {
    ajv = new Ajv2020({ allErrors: true, strict: false }).compile(JSON.parse(readFileSync(SCHEMA, 'utf8')));
    copyFileSync(PLAYER, join(out.path, 'lottie_svg.min.js'));
    server = await serveFolder(out.path);
    browser = await launchBrowser({ viewport: { width: 800, height: 600 } });
  } catch (error) {
    out.failed();
    throw error;
  }
});

after(async () => {
  await browser?.close();
  await server?.close();
  out.finish();
});

/**
 * Writes `name/anim.json` and `name/frames/` for `args` (the `animate` arguments before `-o`)
 * at FPS; returns the Lottie document, the command's report and the frame files.
 */
async function exportBoth(name, args) {
  const dir = join(out.path, name);
  mkdirSync(dir, { recursive: true });
  // Text as outlines in both, so that the label is in the Lottie file too.
  const timing = ['--fps', String(FPS), '--text-outlines'];
  const report = await runSplineskin(['animate', ...args, '-o', join(dir, 'anim.json'), ...timing], { cwd: out.path });
  await runSplineskin(['animate', ...args, '-o', join(dir, 'frames'), ...timing], { cwd: out.path });
  const lottie = JSON.parse(readFileSync(join(dir, 'anim.json'), 'utf8'));
  const frames = readdirSync(join(dir, 'frames')).filter((f) => f.endsWith('.svg')).sort();
  writeFileSync(
    join(dir, 'player.html'),
    `<!doctype html><html><body style="margin:0;background:#fff">
<div id="anim" style="width:${lottie.w}px;height:${lottie.h}px"></div>
<script src="../lottie_svg.min.js"></script>
<script>
  window.anim = lottie.loadAnimation({ container: document.getElementById('anim'), renderer: 'svg',
    loop: false, autoplay: false, path: 'anim.json' });
  window.anim.addEventListener('DOMLoaded', () => { window.loaded = true; });
</script></body></html>`,
  );
  return { dir, report, lottie, frames };
}

/**
 * A copy of the SVG file `from` in the outputs folder with an id on every geometry element that
 * has none (`t-0`, `t-1`, …), so that lottie-web's groups (named by the export after the
 * elements' ids) can be matched with the SVG frames' elements.
 */
function withIds(from, name) {
  let n = 0;
  const text = readFileSync(from, 'utf8').replace(
    /<(path|rect|circle|ellipse|line|polyline|polygon)\b(?![^>]*\sid=)/g,
    (tag) => `${tag} id="t-${n++}"`,
  );
  const to = join(out.path, `${name}.svg`);
  writeFileSync(to, text);
  return to;
}

/**
 * The numbers of the path data of every element with an id matching `selector` (the first
 * path under it, or itself), as points in the pixels of the root <svg>'s viewport: each pair
 * mapped by the element's screen CTM, less the root's position on the page (lottie-web's
 * groups carry no transforms and its coordinates are the composition's pixels; our frames keep
 * the source's transforms and viewBox).
 */
async function pathPoints(page, selector) {
  return page.evaluate((selector) => {
    const root = document.querySelector('svg');
    const origin = root.getBoundingClientRect();
    const result = {};
    for (const el of document.querySelectorAll(selector)) {
      const path = el.tagName === 'path' ? el : el.querySelector('path');
      const d = path?.getAttribute('d');
      if (!el.id || !d) continue;
      const m = path.getScreenCTM();
      // Subpath by subpath (lottie-web joins a group's shapes in its own order), each
      // subpath's coordinates mapped to the root's viewport.
      const subpaths = d
        .split(/(?=[Mm])/)
        .map((sub) => {
          const numbers = (sub.match(/[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?/gi) ?? []).map(Number);
          const points = [];
          for (let k = 0; k + 1 < numbers.length; k += 2) {
            const p = new DOMPoint(numbers[k], numbers[k + 1]).matrixTransform(m);
            points.push(p.x - origin.left, p.y - origin.top);
          }
          return points;
        })
        .filter((points) => points.length > 0);
      result[el.id] = subpaths;
    }
    return result;
  }, selector);
}

/**
 * The diagonal of the drawing's bounding box, from the SVG frame's geometry, in pixels of the
 * root's viewport (as pathPoints gives coordinates).
 */
/** CSS pixels per user unit of the frame shown on `page`. */
async function pixelsPerUnit(page) {
  return page.evaluate(() => {
    const m = document.documentElement.getScreenCTM();
    return Math.sqrt(Math.abs(m.a * m.d - m.b * m.c));
  });
}

async function screenshot(page, file) {
  return decodePng(await page.screenshot({ path: file }));
}

/**
 * The coordinates of the subpaths of `played` and `truth` (one element's), flattened, each
 * truth subpath paired with the unused played one of the same length whose first point is
 * nearest (lottie-web draws a group's shapes in an order of its own).
 */
function pairSubpaths(played, truth, what) {
  assert.equal(played.length, truth.length, `${what}: ${played.length} vs ${truth.length} subpaths`);
  const unused = new Set(played.keys());
  const a = [];
  const b = [];
  for (const t of truth) {
    let best = -1;
    let bestDistance = Infinity;
    for (const k of unused) {
      const p = played[k];
      const distance = Math.hypot(p[0] - t[0], p[1] - t[1]);
      if (p.length === t.length && distance < bestDistance) {
        best = k;
        bestDistance = distance;
      }
    }
    assert.ok(best >= 0, `${what}: no drawn subpath of ${t.length / 2} points for the one at (${t[0]}, ${t[1]})`);
    unused.delete(best);
    a.push(...played[best]);
    b.push(...t);
  }
  return [a, b];
}

/** Plays `name`'s Lottie file in lottie-web at every frame time and compares (file doc). */
async function playAndCompare(t, name, args, { minElements }) {
  const { dir, report, lottie, frames } = await exportBoth(name, args);
  t.diagnostic(`${name}: ${report.trim().split('\n').filter((l) => l.includes('keyframes')).join(' ')}`);
  // The export's own tolerance, in the drawing's units, as its report gives it.
  const units = Number(/of the diagonal \(([\d.e+-]+) units\)/.exec(report)?.[1]);
  assert.ok(units > 0, `${name}: the report states the tolerance in units: ${report}`);
  // Valid against the specification's schema.
  const valid = ajv(lottie);
  assert.ok(valid, `${name}: ${JSON.stringify(ajv.errors?.slice(0, 5))}`);
  assert.equal(frames.length, lottie.op + 1, `${name}: one SVG frame per Lottie frame`);
  const player = await browser.context.newPage();
  const framePage = await browser.context.newPage();
  await player.setViewportSize({ width: lottie.w, height: lottie.h });
  await framePage.setViewportSize({ width: lottie.w, height: lottie.h });
  await player.goto(server.url(`${name}/player.html`));
  await player.waitForFunction(() => window.loaded === true);
  let worst = { d: 0, mean: 0 };
  for (const [f, file] of frames.entries()) {
    // The last frame is the end of the timeline (Lottie's `op`, excluded): just before it.
    const at = f + 1 === frames.length ? f - 1e-3 : f;
    await player.evaluate(async (f) => {
      window.anim.goToAndStop(f, true);
      await new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)));
    }, at);
    await framePage.goto(server.url(`${name}/frames/${file}`));
    const tolerance = units * (await pixelsPerUnit(framePage)) + PRINT_ROUNDING;
    const played = await pathPoints(player, '#anim g[id]');
    const truth = await pathPoints(framePage, 'path[id], rect[id], circle[id], ellipse[id], line[id], polyline[id], polygon[id]');
    const ids = Object.keys(played).filter((id) => id in truth);
    assert.ok(ids.length >= minElements, `${name}, frame ${f}: ${ids.length} elements matched (${Object.keys(played).length} drawn)`);
    for (const id of ids) {
      const [a, b] = pairSubpaths(played[id], truth[id], `${name}, frame ${f}, #${id}`);
      a.forEach((v, k) => {
        const diff = Math.abs(v - b[k]);
        if (diff > worst.d) worst = { ...worst, d: diff, where: `frame ${f}, #${id}, number ${k}: ${v} vs ${b[k]}` };
        assert.ok(diff <= tolerance, `${name}, frame ${f}, #${id}, number ${k}: lottie-web ${v}, deformation ${b[k]} (tolerance ${tolerance})`);
      });
    }
    if (f % 3 === 0 || f + 1 === frames.length) {
      const shown = await screenshot(player, join(dir, `lottie-${f}.png`));
      const expected = await screenshot(framePage, join(dir, `svg-${f}.png`));
      assert.ok(inkFraction(shown) > 0.05, `${name}, frame ${f}: lottie-web drew the art`);
      const pixels = compareImages(shown, expected);
      worst.mean = Math.max(worst.mean, pixels.mean);
      if (pixels.mean > PIXEL_TOLERANCE) {
        writeFileSync(join(dir, `diff-${f}.png`), encodePng(pixels.diff));
      }
      assert.ok(pixels.mean <= PIXEL_TOLERANCE, `${name}, frame ${f}: mean pixel difference ${pixels.mean}`);
    }
  }
  // Control: lottie-web's frame at the largest motion against the SVG frame at rest.
  const middle = Math.floor(frames.length / 2);
  await player.evaluate(async (f) => {
    window.anim.goToAndStop(f, true);
    await new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)));
  }, middle);
  await framePage.goto(server.url(`${name}/frames/${frames[0]}`));
  const control = compareImages(await screenshot(player, join(dir, 'control-lottie.png')), await screenshot(framePage, join(dir, 'control-rest.png')));
  assert.ok(control.mean > PIXEL_TOLERANCE, `${name}: frame ${middle} against the rest pose differs by only ${control.mean}`);
  t.diagnostic(`${name}: ${frames.length} frames; control (frame ${middle} against rest) ${control.mean.toFixed(2)}; largest path-data difference ${worst.d.toExponential(2)} (${worst.where}); largest mean pixel difference ${worst.mean.toFixed(3)}`);
  await player.close();
  await framePage.close();
}

check('the schema check rejects a broken document (control)', async () => {
  const { lottie } = await exportBoth('control', [join(ASSETS, 'demo-scene.json'), '--duration', '0.5']);
  assert.ok(ajv(lottie));
  const broken = structuredClone(lottie);
  delete broken.layers[0].shapes[0].it[0].ks;
  assert.ok(!ajv(broken), 'a path shape without its "ks" is invalid');
});

check('the fish plays in lottie-web as the deformation', async (t) => {
  const scene = JSON.parse(readFileSync(join(ASSETS, 'demo-scene.json'), 'utf8'));
  scene.svg = withIds(join(ASSETS, scene.svg), 'fish');
  scene.animation = {
    fps: 30,
    keyframes: [
      { time: 0, pose: [{}, {}, {}, {}, {}] },
      { time: 0.6, pose: 'swish' },
      { time: 1.2, pose: 'nose-up' },
      { time: 1.8, pose: 'flap' },
    ],
  };
  writeFileSync(join(out.path, 'fish-scene.json'), JSON.stringify(scene));
  await playAndCompare(t, 'fish', ['fish-scene.json'], { minElements: 10 });
});

check('dashed strokes (two dash pairs, an offset) play in lottie-web as the deformation', async (t) => {
  // lottie-web drew nothing of a layer whose stroke dashes shared a name ("dash" twice).
  const svg = join(out.path, 'dashes.svg');
  writeFileSync(svg, `<svg xmlns="http://www.w3.org/2000/svg" width="300" height="300" viewBox="0 0 100 100">
  <path id="curve" d="M10 25 C35 0 65 50 90 25" stroke="#222" stroke-width="5" fill="none" stroke-dasharray="10 5 3 5" stroke-dashoffset="6"/>
  <circle id="ring" cx="50" cy="68" r="24" stroke="#c33" stroke-width="6" fill="#fd8" stroke-dasharray="12 6" stroke-dashoffset="3"/>
</svg>`);
  await playAndCompare(t, 'dashes', [svg, '--pin', '25,50', '--pin', '75,50', '--pin', '50,15', '--move', '1:6,-5', '--rotate', '1:15', '--duration', '1'], { minElements: 2 });
});

check('the octopus plays in lottie-web as the deformation', async (t) => {
  const scene = JSON.parse(readFileSync(join(ASSETS, 'octopus-scene.json'), 'utf8'));
  scene.svg = withIds(join(ASSETS, scene.svg), 'octopus');
  writeFileSync(join(out.path, 'octopus-scene.json'), JSON.stringify(scene));
  await playAndCompare(t, 'octopus', ['octopus-scene.json', '--duration', '2'], { minElements: 30 });
});

check('a real flag with gradients plays in lottie-web as the deformation', { skip: existsSync(FLAG) ? false : `${FLAG} missing (npm ci in test-art)` }, async (t) => {
  const flag = withIds(FLAG, 'flag');
  await playAndCompare(t, 'flag', [flag, '--pins', '4', '--rotate', '1:20', '--move', '2:30,-20'], { minElements: 30 });
});

check('a real emoji with gradients (Noto\'s tropical fish) plays in lottie-web as the deformation', { skip: existsSync(NOTO) ? false : `${NOTO} missing (npm ci in test-art)` }, async (t) => {
  const noto = JSON.parse(readFileSync(NOTO, 'utf8'));
  const icon = noto.icons['tropical-fish'];
  assert.ok(icon, 'the package has the tropical fish');
  const [w, h] = [icon.width ?? noto.width ?? 128, icon.height ?? noto.height ?? 128];
  assert.ok((icon.body.match(/<(linear|radial)Gradient/g) ?? []).length >= 2, 'it has gradients');
  // The icon as an SVG document, drawn at 4 pixels per unit.
  const file = join(out.path, 'tropical-fish-source.svg');
  writeFileSync(file, `<svg xmlns="http://www.w3.org/2000/svg" width="${4 * w}" height="${4 * h}" viewBox="0 0 ${w} ${h}">${icon.body}</svg>`);
  const emoji = withIds(file, 'emoji');
  await playAndCompare(t, 'emoji', [emoji, '--pins', '4', '--rotate', '1:20', '--move', '2:8,-6'], { minElements: 10 });
});

check('a real flag with a clip path (Cuba\'s) plays in lottie-web with the clip as a layer mask', { skip: existsSync(CLIPPED_FLAG) ? false : `${CLIPPED_FLAG} missing (npm ci in test-art)` }, async (t) => {
  const flag = withIds(CLIPPED_FLAG, 'clipped');
  await playAndCompare(t, 'clipped', [flag, '--pins', '4', '--rotate', '1:25', '--move', '2:40,-30'], { minElements: 4 });
  const lottie = JSON.parse(readFileSync(join(out.path, 'clipped', 'anim.json'), 'utf8'));
  const masked = lottie.layers.filter((l) => l.hasMask);
  assert.equal(masked.length, 1, 'the clipped group is a masked layer');
  assert.equal(masked[0].masksProperties.length, 1, 'masked by the clip path\'s one shape');
});
