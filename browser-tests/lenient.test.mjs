// Browser-grade leniency: documents that chromium draws although they are not strictly valid
// (invalid attribute values, lengths in CSS units, `points` lists in error, a use of a
// nested <svg>, internal DTD entities) are read as chromium reads them. For each of our own
// files (crates/splineskin/tests/fixtures/lenient), chromium draws the file itself and what
// `splineskin deform` writes of it at rest (every imported element rewritten as the cubic
// path the import read); the two pictures must agree, and the command must say, naming the
// element, what it read other than written.

import assert from 'node:assert/strict';
import { copyFileSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before } from 'node:test';

import { launchBrowser, outputFolder, REPO, runSplineskin, serveFolder } from './harness.mjs';
import { compareImages, decodePng, encodePng, inkFraction } from './png.mjs';

const FIXTURES = join(REPO, 'crates', 'splineskin', 'tests', 'fixtures', 'lenient');

// Each file, the size chromium draws it at (CSS pixels of an <img>), and what the command's
// warnings must say of it.
const CASES = [
  {
    file: 'invalid-values.svg',
    size: [300, 300],
    warnings: [
      'svg (line 1): attribute width="44mmx" ignored',
      'rect (line 3): attribute x="inherit" ignored',
      'rect (line 4): attribute width="bogus" ignored',
      'path (line 5): attribute transform="rotate(30" ignored',
      'path (line 8): path data',
    ],
  },
  {
    // At its own size: the viewport units are hundredths of the size it is shown at.
    file: 'css-units.svg',
    size: [200, 100],
    warnings: ['attribute width="3rem" read as width="60"', 'attribute height="40vh" read as height="40"'],
  },
  {
    // Q, vi, vb: exact; ic: 1 em in chromium where the font has no "水" (DejaVu Sans), as ours.
    file: 'print-and-font-units.svg',
    size: [200, 100],
    warnings: ['attribute x="40Q" read as x="37.795275590551185"', 'attribute width="2IC" read as width="20"'],
  },
  {
    file: 'points.svg',
    size: [300, 300],
    warnings: [
      'polyline (line 3): attribute points="10,10 90,10 90,45 50" read as points="10,10 90,10 90,45"',
      'polygon (line 4): attribute points="10,55 45,55 45,90 x 10,90" read as points=""',
    ],
  },
  { file: 'use-nested-svg.svg', size: [300, 300], warnings: [] },
  { file: 'entities.svg', size: [300, 300], warnings: ['the entities of its DOCTYPE (green, leaf, ns_svg, st0) expanded'] },
];

// Fraction of pixels that may differ by more than 32 (of 255) in a channel between the two
// pictures: the import writes circles and arcs as cubics (within 3e-4 of their radius), which
// moves anti-aliasing along a few edge pixels.
const SAME_PICTURE = 0.003;

const out = outputFolder('lenient');
const check = (...args) => out.check(...args);
let browser;
let server;
let page;

before(async () => {
  try {
    for (const { file } of CASES) {
      copyFileSync(join(FIXTURES, file), join(out.path, file));
    }
    server = await serveFolder(out.path);
    browser = await launchBrowser({ viewport: { width: 400, height: 300 } });
    page = await browser.context.newPage();
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

/** Chromium's picture of `file` (served from the outputs folder) in an <img> of `size`. */
async function picture(file, [width, height]) {
  await page.setViewportSize({ width, height });
  await page.setContent(
    `<body style="margin:0;background:white"><img id="art" src="${server.url(file)}" width="${width}" height="${height}"></body>`,
  );
  await page.waitForFunction(() => document.getElementById('art').complete);
  const png = await page.locator('#art').screenshot();
  writeFileSync(join(out.path, `${file}.png`), png);
  return decodePng(png);
}

/** `splineskin deform FILE` at rest (one pin, not moved), or with the pin moved by `move`. */
async function deformed(file, name, move) {
  const args = ['deform', file, '--pin', '50,50', '-o', name];
  if (move) args.push('--move', `0:${move}`);
  return runSplineskin(args, { cwd: out.path });
}

for (const { file, size, warnings } of CASES) {
  check(`${file}: read as chromium draws it`, async () => {
    const stderr = await deformed(file, `rest-${file}`);
    for (const w of warnings) {
      assert.ok(stderr.includes(w), `no warning "${w}" in:\n${stderr}`);
    }
    const expected = await picture(file, size);
    const ours = await picture(`rest-${file}`, size);
    assert.ok(inkFraction(expected) > 0.1, `${file}: chromium draws almost nothing`);
    const { changed, diff } = compareImages(expected, ours);
    writeFileSync(join(out.path, `diff-${file}.png`), encodePng(diff));
    assert.ok(changed <= SAME_PICTURE, `${file}: ${(100 * changed).toFixed(3)} % of the pixels differ`);
  });
}

check('the comparison sees a pin moved by 3 % of the drawing (control)', async () => {
  const [{ file, size }] = CASES;
  await deformed(file, `moved-${file}`, '3,0');
  const expected = await picture(file, size);
  const moved = await picture(`moved-${file}`, size);
  const { changed } = compareImages(expected, moved);
  assert.ok(changed > 10 * SAME_PICTURE, `only ${(100 * changed).toFixed(3)} % differ`);
});

check('a document with nothing drawable is still refused, naming file and reason', async () => {
  const file = 'nothing.svg';
  writeFileSync(
    join(out.path, file),
    readFileSync(join(FIXTURES, 'points.svg'), 'utf8').replace(/<poly[^>]*>/g, '<polygon points="x"/>'),
  );
  await assert.rejects(deformed(file, 'nothing-out.svg'), /nothing\.svg: .*(no paths|nothing)/i);
});
