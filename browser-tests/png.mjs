// Minimal PNG reading and writing for comparing screenshots, with no dependency beyond node:zlib.
//
// Reads what browsers write: 8 bits per channel, not interlaced, grey / grey+alpha / RGB / RGBA,
// any of the five row filters. Anything else is refused with an error, never misread.
// Images are { width, height, data } with data an RGBA Uint8Array of width * height * 4 bytes.

import { deflateSync, inflateSync } from 'node:zlib';

const SIGNATURE = Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);
const CHANNELS = { 0: 1, 2: 3, 4: 2, 6: 4 }; // colour type -> samples per pixel

const CRC_TABLE = (() => {
  const table = new Uint32Array(256);
  for (let n = 0; n < 256; n++) {
    let c = n;
    for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    table[n] = c >>> 0;
  }
  return table;
})();

function crc32(bytes) {
  let c = 0xffffffff;
  for (const b of bytes) c = CRC_TABLE[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}

function paeth(a, b, c) {
  const p = a + b - c;
  const pa = Math.abs(p - a);
  const pb = Math.abs(p - b);
  const pc = Math.abs(p - c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/** Decodes a PNG file's bytes into an RGBA image. */
export function decodePng(bytes) {
  const buf = Buffer.from(bytes);
  if (buf.length < 8 || !buf.subarray(0, 8).equals(SIGNATURE)) throw new Error('not a PNG file');
  let pos = 8;
  let header = null;
  const idat = [];
  for (;;) {
    if (pos + 12 > buf.length) throw new Error('PNG: truncated (no IEND chunk)');
    const length = buf.readUInt32BE(pos);
    const type = buf.toString('latin1', pos + 4, pos + 8);
    const body = buf.subarray(pos + 8, pos + 8 + length);
    if (body.length !== length) throw new Error(`PNG: chunk ${type} truncated`);
    if (crc32(buf.subarray(pos + 4, pos + 8 + length)) !== buf.readUInt32BE(pos + 8 + length)) {
      throw new Error(`PNG: chunk ${type} fails its CRC`);
    }
    pos += 12 + length;
    if (type === 'IHDR') {
      header = {
        width: body.readUInt32BE(0),
        height: body.readUInt32BE(4),
        depth: body[8],
        colour: body[9],
        interlace: body[12],
      };
    } else if (type === 'IDAT') {
      idat.push(body);
    } else if (type === 'IEND') {
      break;
    }
  }
  if (!header) throw new Error('PNG: no IHDR chunk');
  const { width, height, depth, colour, interlace } = header;
  const channels = CHANNELS[colour];
  if (depth !== 8 || channels === undefined || interlace !== 0) {
    throw new Error(
      `PNG: unsupported format (bit depth ${depth}, colour type ${colour}, interlace ${interlace}; ` +
        'expected 8-bit grey/RGB with or without alpha, not interlaced)',
    );
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  if (raw.length !== height * (stride + 1)) {
    throw new Error(`PNG: ${raw.length} bytes of image data, expected ${height * (stride + 1)}`);
  }
  const samples = new Uint8Array(height * stride);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    const out = y * stride;
    for (let x = 0; x < stride; x++) {
      const a = x >= channels ? samples[out + x - channels] : 0;
      const b = y > 0 ? samples[out - stride + x] : 0;
      const c = x >= channels && y > 0 ? samples[out - stride + x - channels] : 0;
      let predictor;
      switch (filter) {
        case 0: predictor = 0; break;
        case 1: predictor = a; break;
        case 2: predictor = b; break;
        case 3: predictor = (a + b) >> 1; break;
        case 4: predictor = paeth(a, b, c); break;
        default: throw new Error(`PNG: row ${y} has unknown filter ${filter}`);
      }
      samples[out + x] = (line[x] + predictor) & 0xff;
    }
  }
  const data = new Uint8Array(width * height * 4);
  for (let i = 0; i < width * height; i++) {
    const s = samples.subarray(i * channels, (i + 1) * channels);
    const grey = channels <= 2;
    data[i * 4] = s[0];
    data[i * 4 + 1] = grey ? s[0] : s[1];
    data[i * 4 + 2] = grey ? s[0] : s[2];
    data[i * 4 + 3] = channels === 2 ? s[1] : channels === 4 ? s[3] : 255;
  }
  return { width, height, data };
}

/** Encodes an RGBA image as a PNG file, every row with the given filter (0–4). */
export function encodePng({ width, height, data }, { filter = 0 } = {}) {
  const stride = width * 4;
  const raw = Buffer.alloc(height * (stride + 1));
  for (let y = 0; y < height; y++) {
    raw[y * (stride + 1)] = filter;
    for (let x = 0; x < stride; x++) {
      const i = y * stride + x;
      const a = x >= 4 ? data[i - 4] : 0;
      const b = y > 0 ? data[i - stride] : 0;
      const c = x >= 4 && y > 0 ? data[i - stride - 4] : 0;
      const predictor = [0, a, b, (a + b) >> 1, paeth(a, b, c)][filter];
      raw[y * (stride + 1) + 1 + x] = (data[i] - predictor) & 0xff;
    }
  }
  const chunk = (type, body) => {
    const head = Buffer.alloc(8);
    head.writeUInt32BE(body.length, 0);
    head.write(type, 4, 'latin1');
    const crc = Buffer.alloc(4);
    crc.writeUInt32BE(crc32(Buffer.concat([head.subarray(4), body])), 0);
    return Buffer.concat([head, body, crc]);
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(width, 0);
  ihdr.writeUInt32BE(height, 4);
  ihdr.set([8, 6, 0, 0, 0], 8);
  return Buffer.concat([
    SIGNATURE,
    chunk('IHDR', ihdr),
    chunk('IDAT', deflateSync(raw)),
    chunk('IEND', Buffer.alloc(0)),
  ]);
}

/**
 * How two images of the same size differ: `mean` is the mean absolute difference per channel
 * (0–255, over R, G, B and A of every pixel), `max` the largest, `changed` the fraction of
 * pixels with some channel differing by more than `threshold`. `diff` is an image of the
 * differences (black where equal, brighter where they differ), to look at.
 */
export function compareImages(a, b, { threshold = 32 } = {}) {
  if (a.width !== b.width || a.height !== b.height) {
    throw new Error(`images differ in size: ${a.width}x${a.height} and ${b.width}x${b.height}`);
  }
  const n = a.width * a.height;
  const diff = new Uint8Array(n * 4);
  let sum = 0;
  let max = 0;
  let changed = 0;
  for (let i = 0; i < n; i++) {
    let pixelMax = 0;
    for (let k = 0; k < 4; k++) {
      const d = Math.abs(a.data[i * 4 + k] - b.data[i * 4 + k]);
      sum += d;
      if (d > pixelMax) pixelMax = d;
    }
    if (pixelMax > max) max = pixelMax;
    if (pixelMax > threshold) changed++;
    diff.fill(pixelMax, i * 4, i * 4 + 3);
    diff[i * 4 + 3] = 255;
  }
  return {
    mean: sum / (n * 4),
    max,
    changed: changed / n,
    diff: { width: a.width, height: a.height, data: diff },
  };
}

/** The fraction of pixels whose colour is not (nearly) `background` (default white; alpha ignored). */
export function inkFraction({ width, height, data }, background = [255, 255, 255]) {
  let ink = 0;
  for (let i = 0; i < width * height; i++) {
    const off = Math.max(...background.map((v, k) => Math.abs(data[i * 4 + k] - v)));
    if (off > 16) ink++;
  }
  return ink / (width * height);
}
