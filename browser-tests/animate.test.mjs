// `splineskin animate` in a real browser: the animated SVG (SMIL <animate> of each path's `d`)
// is opened in chromium, its timeline paused and sought to each frame's time, and what the
// browser then shows is compared with the static frame the same command writes for that time:
// the path data the browser computes, each path's bounding box, and a screenshot (which also
// shows the label's text and the gradients, animated by animateTransform, following the art).

import assert from 'node:assert/strict';
import { readFileSync, readdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { launchBrowser, outputFolder, REPO, runSplineskin, serveFolder } from './harness.mjs';
import { compareImages, decodePng, encodePng, inkFraction } from './png.mjs';

const ASSETS = join(REPO, 'crates', 'splineskin', 'assets');

// The bundled scene has poses but no animation; ours keyframes them from the rest pose, ending
// on the last one so that the first and last frames differ. Its SVG is the bundled file.
const KEYFRAMES = [
  { time: 0, pose: [{}, {}, {}, {}, {}] },
  { time: 0.6, pose: 'swish' },
  { time: 1.2, pose: 'nose-up' },
  { time: 1.8, pose: 'flap' },
];
// The same timing options for both outputs: 5 fps over 1.7 s, so frames at 0, 0.2, …, 1.6 and
// a last one at 1.7 (a shorter last interval, as when the duration is not a whole number of
// frames).
const FPS = 5;
const DURATION = 1.7;
const TIMING = ['--fps', String(FPS), '--duration', String(DURATION)];
const EXPECTED_TIMES = [0, 0.2, 0.4, 0.6, 0.8, 1, 1.2, 1.4, 1.6, 1.7];

// What "the same picture" means. The browser parses path data to single precision (about 3e-5
// at these coordinates) and its computed `d` has 6 significant digits (5e-4 at 100–600), so
// 0.01 drawing units is far above rounding and far below any motion between frames.
const GEOMETRY_TOLERANCE = 0.01;
// Mean absolute difference per channel, 0–255: anti-aliasing may differ along a few edges
// (measured: at most 0.002). The fish's label and gradients left at rest while the art moves
// (the animated SVG before it carried them) gave 0.24–0.35.
const PIXEL_TOLERANCE = 0.05;
// Between two frames that are meant to differ, the geometry must move by at least this much.
const CLEARLY_MOVED = 2;

const VIEWPORT = { width: 600, height: 400 }; // the drawing's width and height

const out = outputFolder('animate');
let browser;
let server;
let page; // the animated SVG
let framePage; // the static frames
let frameFiles;

/** A test whose failure keeps the outputs folder. */
const check = (...args) => out.check(...args);

before(async () => {
  try {
    const scene = JSON.parse(readFileSync(join(ASSETS, 'demo-scene.json'), 'utf8'));
    scene.svg = join(ASSETS, scene.svg);
    scene.animation = { fps: 30, keyframes: KEYFRAMES };
    writeFileSync(join(out.path, 'scene.json'), JSON.stringify(scene, null, 2));
    await runSplineskin(['animate', 'scene.json', '-o', 'animated.svg', ...TIMING], { cwd: out.path });
    await runSplineskin(['animate', 'scene.json', '-o', 'frames', ...TIMING], { cwd: out.path });
    frameFiles = readdirSync(join(out.path, 'frames')).filter((f) => f.endsWith('.svg')).sort();
    server = await serveFolder(out.path);
    browser = await launchBrowser({ viewport: VIEWPORT });
    page = await browser.context.newPage();
    framePage = await browser.context.newPage();
    await page.goto(server.url('animated.svg'));
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

/** Pauses the animated document's timeline at `t` seconds and waits for it to be drawn. */
async function seek(t) {
  const now = await page.evaluate(async (t) => {
    const svg = document.documentElement;
    svg.pauseAnimations();
    svg.setCurrentTime(t);
    await new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)));
    return svg.getCurrentTime();
  }, t);
  // The timeline keeps time to about a microsecond (2.1 s reads back as 2.099999 s).
  assert.ok(Math.abs(now - t) < 1e-5, `sought ${t} s, the document is at ${now} s`);
}

/**
 * Every <path> of the document shown in `p`, in document order: its id, the browser's bounding
 * box [x, y, width, height], the commands of its computed path data (animated value included)
 * and their numbers.
 */
async function geometry(p) {
  const paths = await p.evaluate(() =>
    [...document.querySelectorAll('path')].map((path) => {
      const box = path.getBBox();
      return { id: path.id, box: [box.x, box.y, box.width, box.height], d: getComputedStyle(path).d };
    }),
  );
  const number = /[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?/gi;
  return paths.map(({ id, box, d }, i) => {
    const numbers = (d.match(number) ?? []).map(Number);
    // Not `none`: otherwise comparisons of the path data would compare nothing.
    assert.ok(numbers.length >= 8, `path ${i} (${id}): computed path data ${d.slice(0, 60)}`);
    return { id, box, commands: d.replace(number, '#').replace(/[\s,]+/g, ''), numbers };
  });
}

/**
 * The largest coordinate difference between two documents' paths (the same paths, in the same
 * order, with the same commands: otherwise an assertion fails): `box` over bounding boxes, `d`
 * over path-data numbers, and which path and value it is.
 */
function difference(a, b) {
  assert.equal(a.length, b.length, 'the same number of paths');
  let box = { value: 0 };
  let d = { value: 0 };
  a.forEach((pa, i) => {
    const pb = b[i];
    const name = pa.id ? `#${pa.id}` : `path ${i}`;
    assert.equal(pa.id, pb.id, `path ${i}: the same id`);
    assert.equal(pa.commands, pb.commands, `${name}: the same commands`);
    pa.box.forEach((v, k) => {
      const diff = Math.abs(v - pb.box[k]);
      if (diff > box.value) box = { value: diff, where: `${name} box[${k}]: ${v} vs ${pb.box[k]}` };
    });
    pa.numbers.forEach((v, k) => {
      const diff = Math.abs(v - pb.numbers[k]);
      if (diff > d.value) d = { value: diff, where: `${name} number ${k}: ${v} vs ${pb.numbers[k]}` };
    });
  });
  return { box, d };
}

async function screenshot(p, name) {
  const bytes = await p.screenshot({ path: join(out.path, name) });
  return decodePng(bytes);
}

async function showFrame(f) {
  await framePage.goto(server.url(join('frames', frameFiles[f])));
}

/** The animated document at `t` against static frame `f`: geometry and pixel differences. */
async function compareAt(t, f, label) {
  await seek(t);
  await showFrame(f);
  const geo = difference(await geometry(page), await geometry(framePage));
  const shown = await screenshot(page, `${label}-animated-at-${t}s.png`);
  const expected = await screenshot(framePage, `${label}-frame-${f}.png`);
  const pixels = compareImages(shown, expected);
  return { geo, pixels, shown, expected };
}

function report(t, label, { geo, pixels }) {
  t.diagnostic(
    `${label}: box ${geo.box.value.toExponential(2)}, d ${geo.d.value.toExponential(2)} units; ` +
      `pixels mean ${pixels.mean.toFixed(4)}, max ${pixels.max}, changed ${(pixels.changed * 100).toFixed(3)} %`,
  );
}

check('the command writes one animated path per frame path and one frame per time', async () => {
  assert.deepEqual(frameFiles, EXPECTED_TIMES.map((_, f) => `frame-${String(f).padStart(4, '0')}.svg`));
  const text = readFileSync(join(out.path, 'animated.svg'), 'utf8');
  const animates = [...text.matchAll(/<animate ([^>]*)\/>/g)].map((m) => m[1]);
  const paths = await geometry(page);
  assert.ok(paths.length >= 10, `the fish has many paths (${paths.length})`);
  assert.equal(animates.length, paths.length, 'one <animate> per path');
  for (const attrs of animates) {
    const attr = (name) => attrs.match(new RegExp(`\\b${name}="([^"]*)"`))?.[1];
    assert.equal(attr('attributeName'), 'd');
    assert.equal(attr('dur'), `${DURATION}s`);
    const times = attr('keyTimes').split(';').map((k) => Number(k) * DURATION);
    assert.equal(times.length, EXPECTED_TIMES.length);
    times.forEach((time, f) => assert.ok(Math.abs(time - EXPECTED_TIMES[f]) < 1e-9, `frame ${f} at ${time} s`));
    assert.equal(attr('values').split(';').length, EXPECTED_TIMES.length);
  }
});

check('at each frame time the browser shows that frame', async (t) => {
  const started = Date.now();
  let worst = { box: 0, d: 0, mean: 0 };
  // The last frame is what the loop approaches (at DURATION itself it starts again, below).
  const times = EXPECTED_TIMES.map((time, f) => (f + 1 === EXPECTED_TIMES.length ? time - 1e-5 : time));
  for (const [f, time] of times.entries()) {
    const result = await compareAt(time, f, 'same');
    const { geo, pixels, shown } = result;
    report(t, `frame ${f} at ${time} s`, result);
    assert.ok(inkFraction(shown) > 0.2, `frame ${f}: the drawing is rendered (${inkFraction(shown)} of the pixels)`);
    assert.ok(geo.box.value <= GEOMETRY_TOLERANCE, `frame ${f}: bounding boxes differ: ${geo.box.where}`);
    assert.ok(geo.d.value <= GEOMETRY_TOLERANCE, `frame ${f}: path data differs: ${geo.d.where}`);
    if (pixels.mean > PIXEL_TOLERANCE) {
      writeFileSync(join(out.path, `same-diff-${f}.png`), encodePng(pixels.diff));
    }
    assert.ok(pixels.mean <= PIXEL_TOLERANCE, `frame ${f}: screenshots differ by ${pixels.mean} on average`);
    worst = {
      box: Math.max(worst.box, geo.box.value),
      d: Math.max(worst.d, geo.d.value),
      mean: Math.max(worst.mean, pixels.mean),
    };
  }
  t.diagnostic(
    `worst: box ${worst.box.toExponential(2)}, d ${worst.d.toExponential(2)} units, ` +
      `pixels mean ${worst.mean.toFixed(4)}; ${Date.now() - started} ms for ${times.length} frames`,
  );
});

check('the comparison fails for the wrong frame: the animation moves', async (t) => {
  // Each frame against the animated document at the next frame's time.
  for (let f = 0; f + 2 < EXPECTED_TIMES.length; f++) {
    const result = await compareAt(EXPECTED_TIMES[f + 1], f, 'wrong');
    report(t, `frame ${f} at frame ${f + 1}'s time`, result);
    assert.ok(result.geo.box.value > CLEARLY_MOVED, `frames ${f} and ${f + 1}: boxes move by ${result.geo.box.value}`);
    assert.ok(result.geo.d.value > CLEARLY_MOVED, `frames ${f} and ${f + 1}: points move by ${result.geo.d.value}`);
    assert.ok(result.pixels.mean > 4 * PIXEL_TOLERANCE, `frames ${f} and ${f + 1}: pixels differ by ${result.pixels.mean}`);
  }
});

check('between frames the browser interpolates every point linearly', async (t) => {
  const f = 3;
  const [t0, t1] = [EXPECTED_TIMES[f], EXPECTED_TIMES[f + 1]];
  await showFrame(f);
  const a = await geometry(framePage);
  await showFrame(f + 1);
  const b = await geometry(framePage);
  await seek(t0 + 0.25 * (t1 - t0));
  const shown = await geometry(page);
  let worst = 0;
  shown.forEach((path, i) => {
    path.numbers.forEach((v, k) => {
      worst = Math.max(worst, Math.abs(v - (0.75 * a[i].numbers[k] + 0.25 * b[i].numbers[k])));
    });
  });
  t.diagnostic(`a quarter of the way from frame ${f} to ${f + 1}: largest difference from the blend ${worst}`);
  assert.ok(worst <= GEOMETRY_TOLERANCE, `not the linear blend of frames ${f} and ${f + 1}: ${worst}`);
  assert.ok(difference(shown, a).d.value > CLEARLY_MOVED / 4, 'and it is not frame f itself');
});

check('the animation loops: at the duration it starts again', async (t) => {
  for (const f of [0, 2]) {
    const result = await compareAt(DURATION + EXPECTED_TIMES[f], f, 'loop');
    report(t, `frame ${f} one loop later`, result);
    assert.ok(result.geo.d.value <= GEOMETRY_TOLERANCE, `frame ${f} one loop later: ${result.geo.d.where}`);
    assert.ok(result.pixels.mean <= PIXEL_TOLERANCE);
  }
});

check('unpaused, the animation plays in real time', async (t) => {
  // A page behind another tab keeps its clock running but is not drawn, so its animated values
  // stay where they were; this page must be in front while it plays.
  await page.bringToFront();
  await seek(0);
  const start = await geometry(page);
  const played = await page.evaluate(async () => {
    const svg = document.documentElement;
    const begin = performance.now();
    svg.unpauseAnimations();
    await new Promise((done) => setTimeout(done, 400));
    svg.pauseAnimations();
    const wall = (performance.now() - begin) / 1000;
    await new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)));
    return { wall, at: svg.getCurrentTime() };
  });
  // Paused, the drawing settles on the clock's time within a frame or two; on a loaded machine
  // it may take longer: read until two reads a frame apart agree (at most 2 s).
  let shown = await geometry(page);
  for (let k = 0; k < 60; k++) {
    await page.evaluate(() => new Promise((done) => setTimeout(done, 33)));
    const again = await geometry(page);
    const same = difference(shown, again).d.value === 0;
    shown = again;
    if (same) break;
  }
  const moved = difference(start, shown).d.value;
  // What was on screen when the clock stopped is the animation at the clock's time.
  await seek(played.at);
  const lag = difference(shown, await geometry(page)).d.value;
  t.diagnostic(
    `after ${played.wall.toFixed(3)} s of wall time the timeline is at ${played.at} s; ` +
      `points moved ${moved}; differ from the animation at that time by ${lag}`,
  );
  assert.ok(played.at > 0.1 && played.at <= played.wall + 0.05, `timeline at ${played.at} s after ${played.wall} s`);
  assert.ok(moved > CLEARLY_MOVED, `the drawing moved by ${moved}`);
  assert.ok(lag <= GEOMETRY_TOLERANCE, `the drawing lags the clock by ${lag}`);
});
