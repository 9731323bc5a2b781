// The selected handle's gizmo: three arrows along the world's axes move it, three rings about
// them turn it (about its pivot). The gizmo keeps its size on screen (GIZMO_PIXELS long
// whatever the zoom); it is drawn as line segments (gl-view.js) and picked on screen (pick.js).

import { project } from './pick.js';

/** Length of an arrow on screen, CSS pixels; the rings' radius is RING of it. */
export const GIZMO_PIXELS = 70;
const RING = 0.8;
/** Segments of each ring. */
const RING_SEGMENTS = 48;
/** Pixels from a part that pick it. */
const PICK_PIXELS = 6;

/** Vertices of the gizmo's segments: two per arrow, two per ring segment. */
export const GIZMO_VERTICES = 6 + 3 * 2 * RING_SEGMENTS;

const AXES = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
const COLOURS = [[0.85, 0.15, 0.15], [0.1, 0.6, 0.15], [0.15, 0.3, 0.9]];

/**
 * The gizmo's parts as gl-view draws them: `{ first, count, colour, kind, axis }`, `first` and
 * `count` in vertices of the segments `gizmoLines` writes.
 */
export const GIZMO_PARTS = [
  ...AXES.map((_, k) => ({ first: 2 * k, count: 2, colour: COLOURS[k], kind: 'move', axis: k })),
  ...AXES.map((_, k) => ({ first: 6 + 2 * RING_SEGMENTS * k, count: 2 * RING_SEGMENTS, colour: COLOURS[k], kind: 'turn', axis: k })),
];

/** The world axis `k` (0: x, 1: y, 2: z). */
export const axisOf = (k) => AXES[k];

/**
 * Writes the gizmo's segments about `centre` with arrows `size` long into `out` (x, y, z flat,
 * GIZMO_VERTICES points): the arrows, then ring k in the plane normal to axis k.
 */
export function gizmoLines(centre, size, out) {
  const put = (v, p) => {
    out[3 * v] = p[0];
    out[3 * v + 1] = p[1];
    out[3 * v + 2] = p[2];
  };
  AXES.forEach((a, k) => {
    put(2 * k, centre);
    put(2 * k + 1, centre.map((c, i) => c + size * a[i]));
  });
  const r = RING * size;
  AXES.forEach((_, k) => {
    const [u, w] = [(k + 1) % 3, (k + 2) % 3];
    for (let s = 0; s < RING_SEGMENTS; s++) {
      for (const [end, angle] of [[0, s], [1, s + 1]]) {
        const t = (2 * Math.PI * angle) / RING_SEGMENTS;
        const p = [...centre];
        p[u] += r * Math.cos(t);
        p[w] += r * Math.sin(t);
        put(6 + 2 * RING_SEGMENTS * k + 2 * s + end, p);
      }
    }
  });
  return out;
}

/** The part of the gizmo (`lines`, as gizmoLines wrote them) under the screen point `at`, or null. */
export function pickGizmo(matrix, lines, at, { width, height }) {
  let best = null;
  let bestDistance = PICK_PIXELS;
  for (const part of GIZMO_PARTS) {
    for (let v = part.first; v < part.first + part.count; v += 2) {
      const a = project(matrix, lines.subarray(3 * v, 3 * v + 3), width, height);
      const b = project(matrix, lines.subarray(3 * v + 3, 3 * v + 6), width, height);
      if (!a || !b) continue;
      const d = segmentDistance(a, b, at);
      if (d < bestDistance) {
        best = part;
        bestDistance = d;
      }
    }
  }
  return best;
}

/** Distance on screen from `p` to the segment `a`–`b`. */
function segmentDistance(a, b, p) {
  const dx = b[0] - a[0];
  const dy = b[1] - a[1];
  const l2 = dx * dx + dy * dy;
  const t = l2 > 0 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2)) : 0;
  return Math.hypot(a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
}

/**
 * The move along axis `k` of a drag from screen point `from` to `to` on the arrow of a gizmo at
 * `centre`, `size` long: the pointer's motion along the arrow's image on screen, in the
 * arrow's world units. A world vector.
 */
export function axisMove(matrix, centre, size, k, from, to, { width, height }) {
  const a = project(matrix, centre, width, height);
  const b = project(matrix, centre.map((c, i) => c + size * AXES[k][i]), width, height);
  if (!a || !b) return [0, 0, 0];
  const dx = b[0] - a[0];
  const dy = b[1] - a[1];
  const l2 = dx * dx + dy * dy;
  if (l2 < 4) return [0, 0, 0]; // the arrow points at the viewer: no motion along it on screen
  const s = (((to[0] - from[0]) * dx + (to[1] - from[1]) * dy) / l2) * size;
  return AXES[k].map((v) => v * s);
}

/**
 * The turn (radians, right-handed about axis `k`) of a drag from screen point `from` to `to`
 * about a gizmo at `centre`: the angle the pointer swept about the centre's image, its sign
 * by whether the axis points at the viewer (`forward`: the view's direction).
 */
export function ringTurn(matrix, centre, k, forward, from, to, { width, height }) {
  const c = project(matrix, centre, width, height);
  if (!c) return 0;
  const a0 = Math.atan2(from[1] - c[1], from[0] - c[0]);
  const a1 = Math.atan2(to[1] - c[1], to[0] - c[0]);
  let swept = a1 - a0;
  if (swept > Math.PI) swept -= 2 * Math.PI;
  if (swept < -Math.PI) swept += 2 * Math.PI;
  // Screen y points down: a sweep of decreasing angle is anticlockwise as seen, which is a
  // positive turn about an axis pointing at the viewer.
  const towardViewer = AXES[k][0] * forward[0] + AXES[k][1] * forward[1] + AXES[k][2] * forward[2] < 0;
  return towardViewer ? -swept : swept;
}
