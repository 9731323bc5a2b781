// The PNG reader behind every screenshot comparison: it must read all five row filters, and
// the comparison must see a change of one pixel.

import assert from 'node:assert/strict';
import { test } from 'node:test';

import { compareImages, decodePng, encodePng, inkFraction } from './png.mjs';

/** A 7x5 image whose every byte differs from its neighbours (exercises every predictor). */
function sample() {
  const width = 7;
  const height = 5;
  const data = new Uint8Array(width * height * 4);
  for (let i = 0; i < data.length; i++) data[i] = (i * 97 + (i >> 3) * 31 + 11) & 0xff;
  return { width, height, data };
}

test('PNG round trip through every row filter', () => {
  const image = sample();
  for (const filter of [0, 1, 2, 3, 4]) {
    const back = decodePng(encodePng(image, { filter }));
    assert.equal(back.width, image.width);
    assert.equal(back.height, image.height);
    assert.deepEqual(back.data, image.data, `filter ${filter}`);
  }
});

test('a corrupted PNG is refused, not misread', () => {
  const bytes = encodePng(sample());
  bytes[bytes.length - 20] ^= 1; // inside the IDAT chunk: its CRC no longer matches
  assert.throws(() => decodePng(bytes), /CRC/);
  assert.throws(() => decodePng(Buffer.from('GIF89a')), /not a PNG/);
});

test('compareImages measures a change of one pixel', () => {
  const a = sample();
  const b = { ...a, data: a.data.slice() };
  assert.deepEqual(
    (({ mean, max, changed }) => ({ mean, max, changed }))(compareImages(a, b)),
    { mean: 0, max: 0, changed: 0 },
  );
  b.data[4 * 10 + 1] ^= 0xff; // pixel 10, green
  const diff = compareImages(a, b);
  const delta = Math.abs(a.data[41] - b.data[41]);
  assert.equal(diff.max, delta);
  assert.equal(diff.mean, delta / (7 * 5 * 4));
  assert.equal(diff.changed, delta > 32 ? 1 / 35 : 0);
  assert.equal(diff.diff.data[40], delta);
  assert.throws(() => compareImages(a, { ...a, width: 5, height: 7 }), /size/);
});

test('inkFraction counts the pixels that are not background', () => {
  const white = { width: 4, height: 1, data: new Uint8Array(16).fill(255) };
  assert.equal(inkFraction(white), 0);
  white.data.set([0, 0, 0], 4);
  white.data.set([250, 250, 250], 8); // nearly white: background
  assert.equal(inkFraction(white), 0.25);
});
