// Colours of weight values: viridis on [0, 1] (as `splineskin weights` draws them), and two
// ramps no viridis colour is confused with outside it: reds below 0, pinks above 1.

// Viridis sampled at 0, 1/8, …, 1 (matplotlib's table), interpolated linearly between.
const VIRIDIS = [
  [68, 1, 84], [71, 44, 122], [59, 81, 139], [44, 113, 142], [33, 144, 141],
  [39, 173, 129], [92, 200, 99], [170, 220, 50], [253, 231, 37],
];

/** [r, g, b] (0–255) of weight w. */
export function weightColour(w) {
  if (!Number.isFinite(w)) return [128, 128, 128];
  if (w < 0) {
    const t = Math.min(1, -w / 0.5);
    return [Math.round(255 - 60 * t), Math.round(150 - 130 * t), Math.round(150 - 130 * t)];
  }
  if (w > 1) {
    const t = Math.min(1, (w - 1) / 0.5);
    return [255, Math.round(190 - 120 * t), Math.round(230 - 40 * t)];
  }
  const s = w * (VIRIDIS.length - 1);
  const k = Math.min(VIRIDIS.length - 2, Math.floor(s));
  const f = s - k;
  const [a, b] = [VIRIDIS[k], VIRIDIS[k + 1]];
  return [0, 1, 2].map((c) => Math.round(a[c] + (b[c] - a[c]) * f));
}

/** A PNG data URL of a width × height grid of weights (row by row from the top). */
export function weightImage(values, width, height) {
  const canvas = document.createElement('canvas');
  canvas.width = width;
  canvas.height = height;
  const context = canvas.getContext('2d');
  const image = context.createImageData(width, height);
  for (let i = 0; i < width * height; i++) {
    const [r, g, b] = weightColour(values[i]);
    image.data[4 * i] = r;
    image.data[4 * i + 1] = g;
    image.data[4 * i + 2] = b;
    image.data[4 * i + 3] = 255;
  }
  context.putImageData(image, 0, 0);
  return canvas.toDataURL('image/png');
}
