// Trained deformation operators in the editor (weights menu: "ARAP / Symmetric ARAP (trained
// operator)"): the training's progress appears, the rest configuration gives the drawing back,
// a dragged handle gives the library's deformation (POST /api/defops/{id}/deform, the
// library's DefOpRig) to 1e-9 of the drawing's size, bad input is refused with a message, and
// the bundled fish and the octopus (9 handles) are trained and timed.

import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { REPO, launchBrowser, outputFolder, runSplineskin, startEditor } from './harness.mjs';

const VIEWPORT = { width: 1100, height: 760 };
const WAIT = 180_000;
/**
 * The page's product against the library's, relative to the drawing's bounding-box diagonal:
 * the same G_spline and ψ, summed in another order (faer's product vs the page's dot
 * products) over |Ψ| ≈ 160 terms of size up to ~10³ (thin-plate values of far centres):
 * rounding leaves ~1e-13; 1e-9 catches any wrong function, order or scaling.
 */
const AGREEMENT = 1e-9;

const out = outputFolder('editor-defop');
const check = (...args) => out.check(...args);
let browser;

before(async () => {
  browser = await launchBrowser({ viewport: VIEWPORT });
});

after(async () => {
  await browser?.close();
  out.finish();
});

/** A page on a fresh editor serving `args`. */
async function openEditor(args) {
  const server = await startEditor(args);
  const page = await browser.context.newPage();
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto(server.url);
  await page.waitForSelector('body[data-booted]', { timeout: WAIT });
  return { server, page };
}

async function waitRig(page) {
  await page.waitForFunction(() => ['ready', 'error'].includes(document.body.dataset.rig), null, { timeout: WAIT });
  return page.evaluate(() => document.body.dataset.rig);
}

/** Chooses the weights menu entry `family` and waits for the training; returns page seconds. */
async function chooseOperator(page, family) {
  await page.evaluate(() => {
    window.splineskinEditor.stagesSeen = [];
    window.splineskinEditor.countsSeen = [];
  });
  await page.selectOption('#family', family);
  await page.waitForFunction(() => document.body.dataset.rig === 'computing');
  assert.equal(await waitRig(page), 'ready', await page.textContent('#error'));
  return page.evaluate(() => window.splineskinEditor.rigSeconds);
}

/** The page's points, the server's for the same configuration Q, and the drawing's diagonal. */
function pageAndLibrary(page) {
  return page.evaluate(async () => {
    // An operator following a drag may still be sampling or blending in: compare the drawing
    // once it has settled (for 30 s at most), as drawn by the operator in use.
    const until = performance.now() + 30_000;
    const busy = () =>
      document.body.dataset.follow === 'sampling' || Boolean(window.splineskinEditor.rig?.blendingUntil);
    while (busy() && performance.now() < until) await new Promise((ok) => setTimeout(ok, 25));
    await new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok)));
    const { rig, points, rest, scene } = window.splineskinEditor;
    const q = scene.handles.map(([x, y], i) => {
      const T = scene.pose[i];
      return [T[0] * x + T[2] * y + T[4], T[1] * x + T[3] * y + T[5]];
    });
    const response = await fetch(`/api/defops/${rig.id}/deform`, {
      method: 'POST',
      headers: { 'x-splineskin': '1', 'content-type': 'application/json' },
      body: JSON.stringify({ handles: q }),
    });
    const library = [...new Float64Array(await response.arrayBuffer())];
    let [x0, y0, x1, y1] = [Infinity, Infinity, -Infinity, -Infinity];
    for (let k = 0; k < rest.length; k += 2) {
      [x0, x1] = [Math.min(x0, rest[k]), Math.max(x1, rest[k])];
      [y0, y1] = [Math.min(y0, rest[k + 1]), Math.max(y1, rest[k + 1])];
    }
    return { page: [...points], library, rest: [...rest], diagonal: Math.hypot(x1 - x0, y1 - y0) };
  });
}

/** Microseconds per G_spline · ψ(Q) product in the page (the mean of many: the clock ticks 0.1 ms). */
function productMicroseconds(page) {
  return page.evaluate(() => {
    const { rig, scene, points } = window.splineskinEditor;
    const n = 2000;
    const t0 = performance.now();
    for (let k = 0; k < n; k++) rig.deform(scene.pose, points);
    return ((performance.now() - t0) / n) * 1000;
  });
}

const maxDifference = (a, b) => a.reduce((m, v, k) => Math.max(m, Math.abs(v - b[k])), 0);

async function mouseDrag(page, from, to, steps) {
  await page.mouse.move(...from);
  await page.mouse.down();
  for (let k = 1; k <= steps; k++) {
    await page.mouse.move(from[0] + ((to[0] - from[0]) * k) / steps, from[1] + ((to[1] - from[1]) * k) / steps);
  }
  await page.mouse.up();
}

/** Client coordinates of handle i's posed position. */
function handleOnScreen(page, i) {
  return page.evaluate((i) => {
    const { scene } = window.splineskinEditor;
    const [x, y] = scene.handles[i];
    const T = scene.pose[i];
    return window.splineskinEditor.view.toClient([T[0] * x + T[2] * y + T[4], T[1] * x + T[3] * y + T[5]]);
  }, i);
}

const median = (values) => {
  const s = [...values].sort((a, b) => a - b);
  return s.length % 2 ? s[s.length >> 1] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2;
};

check('defop: the fish bent by a symmetric ARAP operator, as the library computes it', async () => {
  const { server, page } = await openEditor([]);
  try {
    assert.equal(await waitRig(page), 'ready');
    const seconds = await chooseOperator(page, 'defop-sarap');
    const { stagesSeen, countsSeen } = await page.evaluate(() => {
      const { stagesSeen, countsSeen } = window.splineskinEditor;
      return structuredClone({ stagesSeen, countsSeen });
    });
    console.log(`fish, symmetric ARAP, default samples: trained in ${seconds.toFixed(2)} s (page clock); ${await page.textContent('#message')}`);
    // Progress: the training stage with counts of solves that grow to the total.
    assert.ok(stagesSeen.includes('training'), `stages seen: ${stagesSeen}`);
    assert.ok(countsSeen.length > 0, 'no training count shown');
    const last = countsSeen[countsSeen.length - 1];
    assert.ok(last.done <= last.total && last.step <= last.steps, JSON.stringify(last));
    assert.ok(countsSeen.every((c, k) => k === 0 || c.done >= countsSeen[k - 1].done), JSON.stringify(countsSeen));
    // The status line says what moves the drawing; flexible G¹ and the weight field are off.
    assert.match(await page.textContent('#message'), /rotating or scaling a handle changes nothing/);
    assert.equal(await page.isDisabled('#flexible'), true);
    assert.equal(await page.isVisible('#defop-samples'), true);

    // The saved scene trains the operator the page trained first; one that followed the
    // drags below has samples the scene does not hold (tested on the octopus, below).
    await page.evaluate(() => (window.splineskinEditor.follower.enabled = false));
    // The fish's own pose, then a drag: the page's product is the library's.
    let r = await pageAndLibrary(page);
    assert.equal(r.page.length, r.library.length);
    const posed = maxDifference(r.page, r.library) / r.diagonal;
    assert.ok(posed < AGREEMENT, `posed: page vs library ${posed.toExponential(2)} of the diagonal`);
    assert.ok(maxDifference(r.page, r.rest) / r.diagonal > 0.01, 'the pose should move the drawing');

    // The tail (handle 2) pulled down, the back (handle 0) pushed up: the body bends.
    await page.evaluate(() => {
      window.splineskinEditor.frameTimes = [];
      window.splineskinEditor.productTimes = [];
    });
    for (const [i, dx, dy] of [[2, 10, 120], [0, 0, -40]]) {
      const from = await handleOnScreen(page, i);
      await mouseDrag(page, from, [from[0] + dx, from[1] + dy], 40);
    }
    const { frameTimes, productTimes } = await page.evaluate(() => {
      const { frameTimes, productTimes } = window.splineskinEditor;
      return { frameTimes, productTimes };
    });
    console.log(
      `fish drag: ${frameTimes.length} frames, product median ${median(productTimes).toFixed(3)} ms, ` +
        `frame (product + path data) median ${median(frameTimes).toFixed(3)} ms`,
    );
    console.log(`fish: ${(await productMicroseconds(page)).toFixed(1)} µs per product (mean of 2 000)`);
    r = await pageAndLibrary(page);
    const dragged = maxDifference(r.page, r.library) / r.diagonal;
    console.log(`fish dragged: page vs library ${dragged.toExponential(2)} of the diagonal`);
    assert.ok(dragged < AGREEMENT, `dragged: page vs library ${dragged.toExponential(2)} of the diagonal`);
    // The path data shown are the page's points (to the digits written).
    const shown = await page.evaluate(() =>
      [...document.getElementById('canvas').shadowRoot.querySelectorAll('[data-splineskin-element]')].map((e) => e.getAttribute('d')).join(' '),
    );
    assert.ok(shown.length > 0);
    await page.screenshot({ path: join(out.path, 'fish-sarap-operator.png') });

    // The saved scene records the operator (its defop section): the command line trains the
    // same operator from it and deforms the drawing as the page shows it.
    const sceneText = await page.evaluate(async () => {
      const { info, scene } = window.splineskinEditor;
      const response = await fetch(`/api/documents/${info.id}/scene`, {
        method: 'POST',
        headers: { 'x-splineskin': '1', 'content-type': 'application/json' },
        body: JSON.stringify(scene),
      });
      return response.text();
    });
    const saved = JSON.parse(sceneText);
    assert.equal(saved.defop.energy, 'symmetric-arap');
    assert.equal(saved.defop.samples, 100);
    assert.equal(saved.weights.family, 'shepard', 'the bundled scene\'s weights are kept');
    const scenePath = join(out.path, 'fish-operator-scene.json');
    writeFileSync(scenePath, sceneText);
    const started = performance.now();
    await runSplineskin(['defop', 'train', scenePath, '-o', join(out.path, 'fish.defop'), '--held-out', '0']);
    const cliSeconds = (performance.now() - started) / 1000;
    await runSplineskin(['defop', 'deform', scenePath, '--operator', join(out.path, 'fish.defop'), '-o', join(out.path, 'fish-cli.json')]);
    const cli = JSON.parse(readFileSync(join(out.path, 'fish-cli.json'), 'utf8')).paths.flatMap((p) => p.points.flat());
    assert.equal(cli.length, r.page.length);
    const viaCli = maxDifference(r.page, cli) / r.diagonal;
    console.log(`fish dragged: page vs splineskin defop train + deform on the saved scene ${viaCli.toExponential(2)} of the diagonal (train ${cliSeconds.toFixed(2)} s)`);
    assert.ok(viaCli < AGREEMENT, `page vs command line ${viaCli.toExponential(2)} of the diagonal`);

    // Reopened in the page, the saved scene shows its weights and offers its operator, which
    // trains again to the same drawing.
    await page.setInputFiles('#open-file', scenePath);
    await page.waitForFunction(() => window.splineskinEditor.info.name.endsWith('fish-operator-scene.json'), null, { timeout: WAIT });
    assert.equal(await waitRig(page), 'ready', await page.textContent('#error'));
    assert.equal(await page.inputValue('#family'), 'shepard');
    assert.match(await page.textContent('#notice'), /symmetric ARAP operator \(100 samples\): pick it in the Weights menu/);
    // The notice has a row of its own: it does not cover the drawing.
    const [notice, canvas] = await page.evaluate(() =>
      ['notice', 'canvas'].map((id) => {
        const r = document.getElementById(id).getBoundingClientRect();
        return [r.left, r.top, r.right, r.bottom];
      }),
    );
    assert.ok(notice[1] >= canvas[3] - 0.5, `the notice (${notice}) is below the canvas (${canvas})`);
    await page.selectOption('#family', 'defop-sarap');
    assert.equal(await page.inputValue('#defop-samples'), '100');
    assert.equal(await waitRig(page), 'ready', await page.textContent('#error'));
    const reopened = await pageAndLibrary(page);
    const again = maxDifference(reopened.page, r.page) / r.diagonal;
    console.log(`fish reopened from the saved scene: ${again.toExponential(2)} of the diagonal from before`);
    assert.ok(again < AGREEMENT, `reopened: ${again.toExponential(2)} of the diagonal`);

    // An operator moves pins only: a Shift-drag, which turns a handle with weights, moves it
    // here, and no turn is stored to reappear under another family.
    const mapBefore = await page.evaluate(() => [...window.splineskinEditor.scene.pose[1]]);
    await page.keyboard.down('Shift');
    const at = await handleOnScreen(page, 1);
    await mouseDrag(page, at, [at[0] + 60, at[1]], 8);
    await page.keyboard.up('Shift');
    const mapAfter = await page.evaluate(() => [...window.splineskinEditor.scene.pose[1]]);
    assert.deepEqual(mapAfter.slice(0, 4), [1, 0, 0, 1], `the Shift-drag stored a turn: ${mapBefore} → ${mapAfter}`);
    assert.ok(mapAfter[4] - mapBefore[4] > 0, `the Shift-drag moved the handle: ${mapBefore} → ${mapAfter}`);

    // Rest configuration: the drawing comes back.
    await page.click('#reset-pose');
    await page.waitForFunction(() => document.body.dataset.rig === 'ready');
    r = await pageAndLibrary(page);
    const atRest = maxDifference(r.page, r.rest) / r.diagonal;
    console.log(`fish at rest: page vs drawing ${atRest.toExponential(2)} of the diagonal`);
    assert.ok(atRest < AGREEMENT, `rest: ${atRest.toExponential(2)} of the diagonal`);

    // Export keeps working.
    const svg = await page.evaluate(async () => {
      const { info, points } = window.splineskinEditor;
      const response = await fetch(`/api/documents/${info.id}/export`, {
        method: 'POST',
        headers: { 'x-splineskin': '1', 'content-type': 'application/octet-stream' },
        body: points,
      });
      return response.text();
    });
    assert.match(svg, /<path/);

    // ARAP too, with another sample count.
    await page.fill('#defop-samples', '60');
    await page.dispatchEvent('#defop-samples', 'change');
    assert.equal(await waitRig(page), 'ready');
    const arapSeconds = await chooseOperator(page, 'defop-arap');
    const info = await page.evaluate(() => window.splineskinEditor.rig.info);
    assert.equal(info.n_samples, 61);
    console.log(`fish, ARAP, 60 samples: ${arapSeconds.toFixed(2)} s`);
  } finally {
    await page.close();
    await server.close();
  }
});

check('defop: Stop ends a long training at once, and the next change trains again', async () => {
  const { server, page } = await openEditor([]);
  try {
    assert.equal(await waitRig(page), 'ready');
    await chooseOperator(page, 'defop-arap');
    assert.equal(await page.isVisible('#progress-stop'), false, 'no Stop button without a training');
    // 5 000 samples: minutes of training.
    await page.evaluate(() => (window.splineskinEditor.countsSeen = []));
    await page.fill('#defop-samples', '5000');
    await page.dispatchEvent('#defop-samples', 'change');
    await page.waitForFunction(() => window.splineskinEditor.countsSeen.length > 0, null, { timeout: WAIT });
    assert.equal(await page.isVisible('#progress-stop'), true);
    await page.click('#progress-stop');
    await page.waitForFunction(() => document.body.dataset.rig === 'stopped', null, { timeout: WAIT });
    const counts = await page.evaluate(() => structuredClone(window.splineskinEditor.countsSeen));
    const last = counts[counts.length - 1];
    console.log(`stopped after ${last.done} of ${last.total} solves; ${await page.textContent('#message')}`);
    assert.ok(last.done < last.total, JSON.stringify(last));
    assert.match(await page.textContent('#message'), /training stopped as asked/);
    assert.equal(await page.isVisible('#progress'), false);
    assert.equal(await page.isVisible('#error'), false, 'a stop is not an error');
    // The next change trains again, at once: the stopped training no longer holds the cores.
    await page.fill('#defop-samples', '40');
    await page.dispatchEvent('#defop-samples', 'change');
    assert.equal(await waitRig(page), 'ready', await page.textContent('#error'));
    assert.equal((await page.evaluate(() => window.splineskinEditor.rig.info)).n_samples, 41);
  } finally {
    await page.close();
    await server.close();
  }
});

check('defop: bad input is refused with a message', async () => {
  const { server, page } = await openEditor([]);
  try {
    await waitRig(page);
    const refused = (scene) =>
      page.evaluate(async (scene) => {
        const { info } = window.splineskinEditor;
        const response = await fetch('/api/defop', {
          method: 'POST',
          headers: { 'x-splineskin': '1', 'content-type': 'application/json' },
          body: JSON.stringify({ document: info.id, scene: { ...info.scene, ...scene } }),
        });
        return [response.status, (await response.json()).error];
      }, scene);
    const weights = { family: 'defop-sarap', samples: 20 };
    let [status, message] = await refused({ weights, handles: [], pose: [] });
    assert.equal(status, 400, message);
    assert.match(message, /at least one point handle/);
    // JSON has no NaN: the page's JSON.stringify writes null, which the server's parser refuses.
    [status, message] = await refused({ weights, handles: [[Number.NaN, 0]], pose: [[1, 0, 0, 1, 0, 0]] });
    assert.equal(status, 422, message);
    assert.match(message, /scene\.handles\[0\]/);
    [status, message] = await refused({ weights, flexible: true });
    assert.equal(status, 400, message);
    assert.match(message, /flexible G¹ does not apply/);
    [status, message] = await refused({ weights: { family: 'defop-sarap', samples: 0 } });
    assert.equal(status, 400, message);
    assert.match(message, /training samples/);

    // In the page: a sample count out of range is refused with a message, nothing retrains.
    await page.selectOption('#family', 'defop-sarap');
    assert.equal(await waitRig(page), 'ready');
    await page.fill('#defop-samples', '0');
    await page.dispatchEvent('#defop-samples', 'change');
    assert.match(await page.textContent('#error'), /training samples: 0 is not a whole number/);
    assert.equal(await page.evaluate(() => document.body.dataset.rig), 'ready');
    await page.click('#error');

    // Too few samples for the handles: the server says how many it needs.
    await page.fill('#defop-samples', '5');
    await page.dispatchEvent('#defop-samples', 'change');
    assert.equal(await waitRig(page), 'error');
    assert.match(await page.textContent('#error'), /5 handles need at least 10 training samples/);
    // Every handle deleted (10-sample ARAP operators in between, quick): the page asks for one.
    await page.fill('#defop-samples', '10');
    await page.dispatchEvent('#defop-samples', 'change');
    assert.equal(await waitRig(page), 'ready', await page.textContent('#error'));
    await page.selectOption('#family', 'defop-arap');
    assert.equal(await waitRig(page), 'ready', await page.textContent('#error'));
    for (let left = 5; left > 0; left--) {
      const at = await handleOnScreen(page, 0);
      await page.mouse.click(...at);
      await page.click('#delete-handle');
      if (left > 1) assert.equal(await waitRig(page), 'ready', await page.textContent('#error'));
    }
    assert.equal(await page.evaluate(() => document.body.dataset.rig), 'none');
    assert.match(await page.textContent('#message'), /click on the art to add point handles/);
    assert.equal(await page.isVisible('#error'), false);
  } finally {
    await page.close();
    await server.close();
  }
});

check('defop: the octopus (9 handles) trained with the default sample count', async () => {
  const { server, page } = await openEditor([join(REPO, 'crates/splineskin/assets/octopus-scene.json')]);
  try {
    assert.equal(await waitRig(page), 'ready');
    // The scene's defop section asks for 1 000 samples (discs of 0.1 of the diagonal): prefilled.
    assert.equal(await page.inputValue('#defop-samples'), '1000');
    await page.evaluate(() => (document.getElementById('defop-samples').value = '100'));
    const seconds = await chooseOperator(page, 'defop-sarap');
    const info = await page.evaluate(() => window.splineskinEditor.rig.info);
    console.log(
      `octopus, symmetric ARAP, ${info.n_samples - 1} samples: ${seconds.toFixed(2)} s in the page ` +
        `(server: domain ${info.seconds[0].toFixed(2)}, training ${info.seconds[1].toFixed(2)}, join ${info.seconds[2].toFixed(2)}; ` +
        `${info.n_vertices} vertices, ${info.n_triangles} triangles, |Ψ| = ${info.n_functions})`,
    );
    // An arm pulled out and another bent in.
    await page.evaluate(() => {
      window.splineskinEditor.frameTimes = [];
    });
    for (const [i, dx, dy] of [[1, 40, -50], [4, -70, 30]]) {
      const from = await handleOnScreen(page, i);
      await mouseDrag(page, from, [from[0] + dx, from[1] + dy], 20);
    }
    const frameTimes = await page.evaluate(() => window.splineskinEditor.frameTimes);
    console.log(`octopus drag: ${frameTimes.length} frames, frame (product + path data) median ${median(frameTimes).toFixed(3)} ms`);
    console.log(`octopus: ${(await productMicroseconds(page)).toFixed(1)} µs per product (mean of 2 000)`);
    const r = await pageAndLibrary(page);
    const d = maxDifference(r.page, r.library) / r.diagonal;
    console.log(`octopus dragged: page vs library ${d.toExponential(2)} of the diagonal`);
    assert.ok(d < AGREEMENT, `octopus: page vs library ${d.toExponential(2)}`);
    await page.screenshot({ path: join(out.path, 'octopus-sarap-operator.png') });
  } finally {
    await page.close();
    await server.close();
  }
});

/**
 * The art under each pin at rest: the nearest point of the drawing's curves (path `path`'s
 * curve starting at chain point `k`, parameter `t`) and its distance `d` to the pin.
 */
function artUnderPins(page) {
  return page.evaluate(() => {
    const { rest, scene, view, info } = window.splineskinEditor;
    const bez = (P, k, t) => {
      const s = 1 - t;
      const [a, b, c, d] = [s * s * s, 3 * s * s * t, 3 * s * t * t, t * t * t];
      return [0, 1].map((i) => a * P[2 * k + i] + b * P[2 * k + 2 + i] + c * P[2 * k + 4 + i] + d * P[2 * k + 6 + i]);
    };
    return scene.handles.map(([px, py]) => {
      let best = { d: Infinity };
      info.paths.forEach((path, p) => {
        for (let k = view.offsets[p]; k + 3 < view.offsets[p] + path.n_points; k += 3) {
          for (let j = 0; j <= 200; j++) {
            const [x, y] = bez(rest, k, j / 200);
            const d = Math.hypot(x - px, y - py);
            if (d < best.d) best = { d, k, t: j / 200 };
          }
        }
      });
      return best;
    });
  });
}

/**
 * For each pin: how far the distance from its posed position to its art point moved from the
 * rest distance (the art under a pin stays on it: 0 for a pin on a curve that follows it).
 */
function pinSlips(page, under) {
  return page.evaluate((under) => {
    const { points, scene } = window.splineskinEditor;
    return under.map(({ d, k, t }, i) => {
      const s = 1 - t;
      const w = [s * s * s, 3 * s * s * t, 3 * s * t * t, t * t * t];
      const [x, y] = [0, 1].map((c) => w.reduce((sum, wi, j) => sum + wi * points[2 * (k + j) + c], 0));
      const [hx, hy] = scene.handles[i];
      const T = scene.pose[i];
      const q = [T[0] * hx + T[2] * hy + T[4], T[1] * hx + T[3] * hy + T[5]];
      return Math.abs(Math.hypot(x - q[0], y - q[1]) - d);
    });
  }, under);
}

check('defop: the operator follows a long drag on the octopus and settles on its pins', async () => {
  const { server, page } = await openEditor([join(REPO, 'crates/splineskin/assets/octopus-scene.json')]);
  try {
    assert.equal(await waitRig(page), 'ready');
    await page.evaluate(() => (document.getElementById('defop-samples').value = '100'));
    // The scene's pins sit 6 units inside the arm tips; put each on the outline nearest to it
    // (as a click on the art places one), so that "the art under a pin" is a curve point.
    const inside = await artUnderPins(page);
    console.log(`octopus pins: the scene's are ${inside.map((u) => u.d.toFixed(2)).join(', ')} units from the art`);
    await page.evaluate((inside) => {
      const { scene, rest } = window.splineskinEditor;
      scene.handles = inside.map(({ k, t }) => {
        const s = 1 - t;
        const w = [s * s * s, 3 * s * s * t, 3 * s * t * t, t * t * t];
        return [0, 1].map((c) => w.reduce((sum, wi, j) => sum + wi * rest[2 * (k + j) + c], 0));
      });
    }, inside);
    await chooseOperator(page, 'defop-sarap');
    const under = await artUnderPins(page);
    assert.ok(under.every((u) => u.d < 1e-9), `pins on the art: ${under.map((u) => u.d)}`);
    const size = await page.evaluate(() => {
      const { rest } = window.splineskinEditor;
      let [x0, y0, x1, y1] = [Infinity, Infinity, -Infinity, -Infinity];
      for (let k = 0; k < rest.length; k += 2) {
        [x0, x1] = [Math.min(x0, rest[k]), Math.max(x1, rest[k])];
        [y0, y1] = [Math.min(y0, rest[k + 1]), Math.max(y1, rest[k + 1])];
      }
      return Math.max(x1 - x0, y1 - y0);
    });
    // The top arm's tip (handle 1) pulled sideways 40 % of the drawing's size.
    const dragged = 1;
    const reach = await page.evaluate(() => window.splineskinEditor.rig.info.reach);
    const from = await handleOnScreen(page, dragged);
    const scale = await page.evaluate(() => {
      const v = window.splineskinEditor.view;
      const [a, b] = [v.toClient([0, 0]), v.toClient([100, 0])];
      return (b[0] - a[0]) / 100;
    });
    const distance = 0.4 * size;
    console.log(`octopus: size ${size.toFixed(1)}, drag ${distance.toFixed(1)} units (${(distance / reach).toFixed(1)} × the sampling radius ${reach.toFixed(1)})`);
    await page.evaluate(() => {
      const { follower } = window.splineskinEditor;
      follower.swaps = 0;
    });
    // The first operator's extrapolation at the end of the drag, for comparison: the library's
    // join of the operator trained first, at the final configuration.
    const firstId = await page.evaluate(() => window.splineskinEditor.rig.id);
    await page.mouse.move(...from);
    await page.mouse.down();
    const steps = 30;
    for (let k = 1; k <= steps; k++) {
      await page.mouse.move(from[0] + (distance * scale * k) / steps, from[1]);
      await page.waitForTimeout(16);
    }
    // Pins hold the art under them whatever operator is in use: at release, through every
    // swap and blend, and once settled.
    const worstSlips = new Array(under.length).fill(0);
    const slipsNow = async () => {
      const slips = await pinSlips(page, under);
      slips.forEach((v, i) => (worstSlips[i] = Math.max(worstSlips[i], v)));
    };
    await page.mouse.up();
    const released = performance.now();
    await slipsNow();
    const atRelease = await page.evaluate(() => [...window.splineskinEditor.points]);
    let settled = null;
    while (performance.now() - released < 30_000) {
      await page.waitForTimeout(25);
      await slipsNow();
      const state = await page.evaluate(() => ({
        follow: document.body.dataset.follow,
        blending: Boolean(window.splineskinEditor.rig.blendingUntil),
      }));
      if (state.follow === 'idle' && !state.blending) {
        settled = (performance.now() - released) / 1000;
        break;
      }
    }
    assert.ok(settled !== null, 'the operator did not settle within 30 s');
    await slipsNow();
    const info = await page.evaluate(() => window.splineskinEditor.rig.info);
    const swaps = await page.evaluate(() => window.splineskinEditor.follower.swaps);
    const r = await pageAndLibrary(page);
    const q = await page.evaluate(() => [...window.splineskinEditor.rig.q]);
    const handles = q.reduce((h, v, k) => (k % 2 ? h : [...h, [v, q[k + 1]]]), []);
    // The settled operator has the final configuration among its samples: asked again, it
    // stays (its ground truth is reproduced there).
    const again = await page.evaluate(async ({ id, handles }) => {
      const response = await fetch(`/api/defops/${id}/follow`, {
        method: 'POST',
        headers: { 'x-splineskin': '1', 'content-type': 'application/json' },
        body: JSON.stringify({ handles, settle: true }),
      });
      return [response.headers.get('x-splineskin-defop'), await response.json().catch(() => null)];
    }, { id: info.id, handles });
    assert.equal(again[0], null, 'the settled operator asked to follow again');
    assert.equal(again[1].reason, 'inside');
    assert.ok(again[1].distance < 1e-9 * r.diagonal, `final configuration ${again[1].distance} from the samples`);
    const first = await page.evaluate(async ({ id, handles }) => {
      const response = await fetch(`/api/defops/${id}/deform`, {
        method: 'POST',
        headers: { 'x-splineskin': '1', 'content-type': 'application/json' },
        body: JSON.stringify({ handles }),
      });
      return response.ok ? [...new Float64Array(await response.arrayBuffer())] : null;
    }, { id: firstId, handles });
    const moved = maxDifference(r.page, atRelease);
    console.log(
      `octopus follow: settled ${settled.toFixed(2)} s after release (page clock, ${process.env.SPLINESKIN_BIN ?? "dev build"}); ${swaps} operators swapped in, ` +
        `${info.n_followed} samples added (${info.n_samples} in all); the drawing moved ${moved.toFixed(2)} units after release` +
        (first ? `; the first operator's drawing there is ${maxDifference(first, r.page).toFixed(2)} units from the settled one` : '') +
        `; largest pin slip at any time ${worstSlips.map((v) => v.toExponential(1)).join(', ')}`,
    );
    assert.ok(swaps > 0, 'no operator followed the drag');
    assert.ok(info.n_followed > 0);
    assert.ok(maxDifference(r.page, r.library) / r.diagonal < AGREEMENT, 'the page shows the library\'s join of the followed operator');
    const others = worstSlips.filter((_, i) => i !== dragged);
    assert.ok(Math.max(...others) <= 0.5, `pins slipped ${others}`);
    assert.ok(worstSlips[dragged] <= 0.1, `the dragged handle's art was ${worstSlips[dragged]} from it`);
    await page.screenshot({ path: join(out.path, 'octopus-followed.png') });
  } finally {
    await page.close();
    await server.close();
  }
});

check('defop: a followed operator is blended in from the one before, without a jump', async () => {
  const { blendIn, BLEND_MS } = await import('../crates/splineskin-cli/web/follow.js');
  // Two "rigs" of two points: the old puts them at 0, the new at 10 and 20.
  const old = { nPoints: 1, deform: (pose, out) => out.fill(0) };
  const rig = { nPoints: 1, deform: (pose, out) => out.set([10, 20]) };
  const out = new Float64Array(2);
  const start = performance.now();
  blendIn(rig, old, start);
  rig.deform(null, out);
  const elapsed = (performance.now() - start) / BLEND_MS;
  // At the swap the drawing is where the old operator had it, but for the blend's progress in
  // the time the call took (smoothstep of it: well under 1e-3 on an idle machine; a loaded one
  // can take a millisecond).
  const progress = elapsed * elapsed * (3 - 2 * elapsed);
  assert.ok(elapsed < 0.05 && out[0] <= 10 * progress + 1e-12 && out[1] <= 20 * progress + 1e-12, `at the swap: ${out} (${elapsed} of the blend)`);
  let last = [...out];
  let steps = 0;
  while (rig.blendingUntil) {
    await new Promise((ok) => setTimeout(ok, 10));
    rig.deform(null, out);
    // Monotone from the old to the new, the two coordinates in proportion (one blend factor).
    assert.ok(out[0] >= last[0] - 1e-12 && out[0] <= 10 && Math.abs(out[1] - 2 * out[0]) < 1e-9, `${out}`);
    last = [...out];
    steps++;
  }
  assert.deepEqual([...out], [10, 20]);
  assert.ok(steps >= 2, `the blend took ${steps} frames of 10 ms (BLEND_MS ${BLEND_MS})`);
  assert.ok(performance.now() - start >= BLEND_MS - 1);
});
