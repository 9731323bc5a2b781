// Keyframes of the handles' poses: each key holds every handle's offset and rotation at a time,
// and the easing of the motion to the next key. Between keys, at the eased fraction
// e(u) (../animation.js `ease`, the library's `Easing`), a handle's pivot (where it was placed)
// moves linearly and its rotation turns along the shorter arc (quaternion slerp): for these
// rigid maps, what the library's keyframe interpolation does (`splineskin::animation`,
// SpaceParts: pivot image linear, polar rotation slerped, stretch the identity).

import { ease } from '../animation.js';

/**
 * A key at `time` of the handles' current offsets and rotations, with `easing` (an easing's
 * name, ../animation.js) the motion to the next key takes.
 */
export function keyOf(time, handles, easing = 'linear') {
  return { time, easing, poses: handles.map((h) => ({ offset: [...h.offset], rotation: [...h.rotation] })) };
}

/** The time of the last key (0 without keys). */
export function lastTime(keys) {
  return keys.length ? keys[keys.length - 1].time : 0;
}

/** `keys` with `key` in time order, replacing one at the same time. */
export function withKey(keys, key) {
  return [...keys.filter((k) => k.time !== key.time), key].sort((a, b) => a.time - b.time);
}

/** The handles' offsets and rotations at `time` (seconds), written into `handles`. */
export function poseAt(keys, time, handles) {
  if (keys.length === 0) return;
  const next = keys.findIndex((k) => k.time > time);
  const [a, b] = next <= 0 ? [keys[next === 0 ? 0 : keys.length - 1], null] : [keys[next - 1], keys[next]];
  handles.forEach((h, i) => {
    const p = a.poses[i];
    if (!p) return;
    if (!b || !b.poses[i]) {
      h.offset = [...p.offset];
      h.rotation = [...p.rotation];
      return;
    }
    const u = ease(a.easing ?? 'linear', (time - a.time) / (b.time - a.time));
    const q = b.poses[i];
    h.offset = p.offset.map((o, k) => o + u * (q.offset[k] - o));
    h.rotation = matrixOf(slerp(quaternionOf(p.rotation), quaternionOf(q.rotation), u));
  });
}

/** The unit quaternion `[w, x, y, z]` of a rotation matrix (rows, flat). */
function quaternionOf(r) {
  const trace = r[0] + r[4] + r[8];
  let q;
  if (trace > 0) {
    const s = 0.5 / Math.sqrt(trace + 1);
    q = [0.25 / s, (r[7] - r[5]) * s, (r[2] - r[6]) * s, (r[3] - r[1]) * s];
  } else if (r[0] > r[4] && r[0] > r[8]) {
    const s = 2 * Math.sqrt(1 + r[0] - r[4] - r[8]);
    q = [(r[7] - r[5]) / s, 0.25 * s, (r[1] + r[3]) / s, (r[2] + r[6]) / s];
  } else if (r[4] > r[8]) {
    const s = 2 * Math.sqrt(1 + r[4] - r[0] - r[8]);
    q = [(r[2] - r[6]) / s, (r[1] + r[3]) / s, 0.25 * s, (r[5] + r[7]) / s];
  } else {
    const s = 2 * Math.sqrt(1 + r[8] - r[0] - r[4]);
    q = [(r[3] - r[1]) / s, (r[2] + r[6]) / s, (r[5] + r[7]) / s, 0.25 * s];
  }
  const n = Math.hypot(...q);
  return q.map((v) => v / n);
}

/** The rotation matrix (rows, flat) of a unit quaternion. */
function matrixOf([w, x, y, z]) {
  return [
    1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
    2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
    2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y),
  ];
}

/** Spherical interpolation along the shorter arc. */
function slerp(a, b, u) {
  let cos = a.reduce((s, v, k) => s + v * b[k], 0);
  const c = cos < 0 ? b.map((v) => -v) : b;
  cos = Math.abs(cos);
  let wa = 1 - u;
  let wb = u;
  if (cos < 1 - 1e-12) {
    const angle = Math.acos(Math.min(1, cos));
    wa = Math.sin((1 - u) * angle) / Math.sin(angle);
    wb = Math.sin(u * angle) / Math.sin(angle);
  }
  const q = a.map((v, k) => wa * v + wb * c[k]);
  const n = Math.hypot(...q);
  return q.map((v) => v / n);
}
