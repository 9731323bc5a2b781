// The npm package of the JavaScript API (npm/, packed by tools/npm-package) as a developer uses
// it: `npm install` of the packed tarball into a fresh Vite project, `vite build`, the built page
// run in chromium; its deformation (one pin moved) equals the native `splineskin deform` with the
// same pins and move, to 1e-9 of the diagonal. The same package under Node (`load()` with no
// argument reads the module beside it) and its TypeScript types, resolved by name.
//
// Needs the WebAssembly module (tools/build-wasm); without it these tests skip, saying so, unless
// CI is set. No network: the tarball has no dependencies, and Vite is the test folder's own.

import assert from 'node:assert/strict';
import { execFile } from 'node:child_process';
import { existsSync, mkdirSync, readdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after } from 'node:test';
import { promisify } from 'node:util';

import { launchBrowser, outputFolder, pathDifference, REPO, runSplineskin, serveFolder, splineskinBinary } from './harness.mjs';

const run = promisify(execFile);
const WASM = process.env.SPLINESKIN_WASM || join(REPO, 'target', 'wasm', 'wasm32-unknown-unknown', 'release', 'splineskin_wasm.wasm');
const MISSING = !existsSync(WASM) && !process.env.CI && `${WASM} is missing (build it: tools/build-wasm)`;
if (!existsSync(WASM) && process.env.CI) throw new Error(`${WASM} is missing; CI builds it in .ci/run`);

const DEMO_SVG = join(REPO, 'crates', 'splineskin', 'assets', 'demo.svg');
const PINS = [[440, 215], [150, 210], [300, 150]];
const MOVE = [-20, 35];
const SAME = 1e-9;
const NODE_MODULES = join(REPO, 'browser-tests', 'node_modules');

const out = outputFolder('npm-package');
const check = (...args) => out.check(...args);
after(() => out.finish());

/** What a developer writes: the package imported by name, a pin moved, the SVG shown. */
const APP_JS = `import { load } from 'splineskin';

const splineskin = await load();
const text = await (await fetch('/drawing.svg')).text();
const drawing = splineskin.open(text, 'drawing.svg');
const pins = ${JSON.stringify(PINS)};
const rig = drawing.rig({ pins });
const pose = pins.map(() => [1, 0, 0, 1, 0, 0]);
pose[0] = [1, 0, 0, 1, ${MOVE}];
const points = rig.update(pose, new Float64Array(2 * drawing.nPoints));
const svg = drawing.svg(points, { rig, pose });
document.getElementById('art').innerHTML = svg;
window.deformed = svg;
document.body.dataset.done = drawing.nCurves;
`;

const INDEX_HTML = `<!doctype html>
<html lang="en">
<head><meta charset="utf-8"><title>splineskin in a Vite project</title></head>
<body><div id="art"></div><script type="module" src="/main.js"></script></body>
</html>
`;

/** The same calls typed: tsc must accept them through the package's own declarations. */
const APP_TS = `import { load, SplineskinError, type Drawing } from 'splineskin';

const splineskin = await load();
const drawing: Drawing = splineskin.open('<svg/>', 'x.svg');
const points: Float64Array = drawing.rig({ pins: [[0, 0]] }).update([[1, 0, 0, 1, 0, 0]], new Float64Array(2 * drawing.nPoints));
const error: SplineskinError | null = null;
export { points, error };
`;

/** Packs the package, makes a fresh project with it installed; resolves to the project's folder. */
async function freshProject() {
  const { stdout } = await run(join(REPO, 'tools', 'npm-package'), [join(out.path, 'npm')], {
    env: { ...process.env, SPLINESKIN: splineskinBinary(), SPLINESKIN_WASM: WASM },
  });
  const tarball = stdout.trim().split('\n').at(-1);
  assert.ok(existsSync(tarball), `${tarball}: packed`);
  const project = join(out.path, 'vite-app');
  mkdirSync(join(project, 'public'), { recursive: true });
  writeFileSync(join(project, 'package.json'), JSON.stringify({ name: 'vite-app', private: true, version: '0.0.0', type: 'module' }, null, 2));
  writeFileSync(join(project, 'index.html'), INDEX_HTML);
  writeFileSync(join(project, 'main.js'), APP_JS);
  writeFileSync(join(project, 'app.ts'), APP_TS);
  writeFileSync(join(project, 'public', 'drawing.svg'), readFileSync(DEMO_SVG));
  await run('npm', ['install', '--offline', '--no-audit', '--no-fund', tarball], { cwd: project });
  return project;
}

/** `splineskin deform` of the bundled fish with PINS, smooth weights, pin 0 moved by `move`. */
async function native(move = MOVE) {
  const file = join(out.path, `native-${move}.svg`);
  await runSplineskin(['deform', DEMO_SVG, ...PINS.flatMap(([x, y]) => ['--pin', `${x},${y}`]), '--weights', 'bbw', '--move', `0:${move}`, '-o', file]);
  return readFileSync(file, 'utf8');
}

let project;

check('npm pack: the package carries its module, the API, its types and README, and its version is the crates\'', { skip: MISSING }, async () => {
  project = await freshProject();
  const installed = join(project, 'node_modules', 'splineskin');
  const files = readdirSync(installed).sort();
  for (const file of ['README.md', 'package.json', 'splineskin.d.ts', 'splineskin.js', 'splineskin.wasm', 'wasm-editor.js']) {
    assert.ok(files.includes(file), `${file} in ${files.join(', ')}`);
  }
  const manifest = JSON.parse(readFileSync(join(installed, 'package.json'), 'utf8'));
  const crates = /\[workspace\.package\]\s*\nversion = "([^"]+)"/.exec(readFileSync(join(REPO, 'Cargo.toml'), 'utf8'))[1];
  assert.equal(manifest.version, crates);
  assert.equal(manifest.type, 'module');
  assert.equal(manifest.exports['.'].types, './splineskin.d.ts');
});

check('in a fresh Vite project: built, run in chromium, one pin moved: the native deformation', { skip: MISSING }, async () => {
  assert.ok(project, 'the project was made by the test before');
  const vite = join(NODE_MODULES, 'vite', 'bin', 'vite.js');
  const built = await run(process.execPath, [vite, 'build'], { cwd: project });
  const printed = built.stdout + built.stderr;
  console.log(`npm-package: vite build:\n${printed.trim()}`);
  assert.doesNotMatch(printed, /externalized|warning|error/i, 'vite builds it without a warning');
  const assets = readdirSync(join(project, 'dist', 'assets'));
  assert.ok(assets.some((f) => f.endsWith('.wasm')), `the module copied into the build: ${assets.join(', ')}`);

  const site = await serveFolder(join(project, 'dist'));
  const browser = await launchBrowser({ viewport: { width: 800, height: 600 } });
  try {
    const page = await browser.context.newPage();
    const errors = [];
    page.on('pageerror', (e) => errors.push(e.message));
    await page.goto(site.url('index.html'));
    await page.waitForSelector('body[data-done]', { timeout: 60_000 });
    const deformed = await page.evaluate(() => window.deformed);
    writeFileSync(join(out.path, 'vite.svg'), deformed);
    await page.screenshot({ path: join(out.path, 'vite.png') });
    const { paths, relative } = pathDifference(deformed, await native(), 'vite');
    console.log(`npm-package: the Vite build's deformation: ${paths} paths, ${relative.toExponential(2)} of the diagonal from native`);
    assert.ok(relative <= SAME, `${relative} of the diagonal`);
    // A control: the rest drawing is far from it, so the comparison can fail.
    const { relative: rest } = pathDifference(await native([0, 0]), deformed, 'rest');
    assert.ok(rest > 1e-3, `the move is visible (${rest})`);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
    await site.close();
  }
});

check('under Node in the same project: load() by name, with no argument, reads the module beside it', { skip: MISSING }, async () => {
  assert.ok(project, 'the project was made by the test before');
  const script = join(project, 'node-check.mjs');
  writeFileSync(script, `import { readFileSync } from 'node:fs';
import { load } from 'splineskin';
const splineskin = await load();
const drawing = splineskin.open(readFileSync('public/drawing.svg', 'utf8'), 'drawing.svg');
console.log(drawing.nCurves);
`);
  const { stdout } = await run(process.execPath, [script], { cwd: project });
  assert.ok(Number(stdout.trim()) > 10, `curves: ${stdout}`);
});

check('the package\'s TypeScript types, found by name (tsc --strict, bundler resolution)', { skip: MISSING }, async () => {
  assert.ok(project, 'the project was made by the test before');
  const tsc = join(NODE_MODULES, 'typescript', 'bin', 'tsc');
  const args = ['--noEmit', '--strict', '--target', 'es2022', '--module', 'es2022', '--moduleResolution', 'bundler', '--lib', 'es2022,dom', 'app.ts'];
  try {
    await run(process.execPath, [tsc, ...args], { cwd: project });
  } catch (e) {
    assert.fail(`tsc: ${e.stdout}${e.stderr}`);
  }
  // A control: a mistyped call is refused, so the types are read.
  writeFileSync(join(project, 'wrong.ts'), `import { load } from 'splineskin';\nconst s = await load();\ns.open(42);\n`);
  const refused = await run(process.execPath, [tsc, ...args.slice(0, -1), 'wrong.ts'], { cwd: project }).then(() => null, (e) => e.stdout);
  assert.match(refused ?? 'accepted', /TS2345/, 'open(42) refused: a number is not a string');
});
