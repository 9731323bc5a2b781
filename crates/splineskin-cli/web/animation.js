// Keyframed poses in the page: the scene's `animation` ({ fps, keyframes: [{ time, pose,
// easing }] }) sampled at a time exactly as the library samples it (crates/splineskin/src/
// animation.rs), so that the timeline shows what `splineskin animate` writes.
//
// Each handle's map is split about its pivot (the handle's rest position) into where the pivot
// goes q, a turn θ, scales (s_x, s_y) and a shear k:
//
//   T(x) = q + R(θ) · diag(s_x, s_y) · [[1, k], [0, 1]] · (x − c)
//
// and between keyframes at u = e((t − t₀)/(t₁ − t₀)) (e: the first keyframe's easing) q and k
// move linearly, θ along the shortest arc, s_x and s_y geometrically (s_y linearly when its
// sign changes). At e(u) = 0 or 1 a keyframe's own maps are returned.

import { DEFAULT_FPS, EASINGS, MAX_FPS } from './constants.js';

// Easings of a keyframe's segment in menu order, the default and largest frame rates: Rust's.
export { DEFAULT_FPS, EASINGS, MAX_FPS };

/** Plain-language labels of the easings. */
export const EASING_LABELS = {
  linear: 'Linear',
  'ease-in': 'Ease in',
  'ease-out': 'Ease out',
  'ease-in-out': 'Ease in and out',
  hold: 'Hold',
};


/** e(u) of easing `name` for u in [0, 1] (Easing::apply). */
export function ease(name, u) {
  switch (name) {
    case 'ease-in':
      return u * u;
    case 'ease-out':
      return u * (2 - u);
    case 'ease-in-out':
      return u * u * (3 - 2 * u);
    case 'hold':
      return u >= 1 ? 1 : 0;
    default:
      return u;
  }
}

/** `to − from` wrapped to (−π, π]: the shortest turn (shortest_turn). */
export function shortestTurn(from, to) {
  const tau = 2 * Math.PI;
  let r = (Math.PI - (to - from)) % tau;
  if (r < 0) r += tau;
  return Math.PI - r;
}

/** The parts of map T about pivot c, or null when T is singular (AffineParts::decompose). */
export function decompose(T, [px, py]) {
  const [a, b, c, d, e, f] = T;
  if (!T.every(Number.isFinite)) return null;
  const det = a * d - b * c;
  const sx = Math.hypot(a, b);
  if (!(det !== 0 && Number.isFinite(det) && sx > 0)) return null;
  const cos = a / sx;
  const sin = b / sx;
  return {
    q: [a * px + c * py + e, b * px + d * py + f],
    angle: Math.atan2(b, a),
    sx,
    sy: -sin * c + cos * d,
    shear: (cos * c + sin * d) / sx,
  };
}

/** The map of `parts` about pivot c (AffineParts::compose). */
export function compose({ q, angle, sx, sy, shear }, [px, py]) {
  const sin = Math.sin(angle);
  const cos = Math.cos(angle);
  const a = cos * sx;
  const b = sin * sx;
  const c = cos * sx * shear - sin * sy;
  const d = sin * sx * shear + cos * sy;
  return [a, b, c, d, q[0] - (a * px + c * py), q[1] - (b * px + d * py)];
}

/** The parts at fraction u from p0 to p1 (AffineParts::interpolate). */
export function interpolateParts(p0, p1, u) {
  if (u === 0) return p0;
  if (u === 1) return p1;
  const lerp = (x, y) => x + u * (y - x);
  const geometric = (x, y) => x * (y / x) ** u;
  return {
    q: [lerp(p0.q[0], p1.q[0]), lerp(p0.q[1], p1.q[1])],
    angle: p0.angle + u * shortestTurn(p0.angle, p1.angle),
    sx: geometric(p0.sx, p1.sx),
    sy: p0.sy * p1.sy > 0 ? geometric(p0.sy, p1.sy) : lerp(p0.sy, p1.sy),
    shear: lerp(p0.shear, p1.shear),
  };
}

/** Map T0 at fraction u towards T1, split about pivot c; T0 itself if either is singular. */
export function interpolateMap(T0, T1, pivot, u) {
  if (u === 0) return [...T0];
  if (u === 1) return [...T1];
  const p0 = decompose(T0, pivot);
  const p1 = decompose(T1, pivot);
  if (!p0 || !p1) return [...T0];
  return compose(interpolateParts(p0, p1, u), pivot);
}

/**
 * The pose of `animation` at time t (seconds), one map per handle, the handles' rest positions
 * `pivots` the pivots (PoseSampler::pose_at): before the first keyframe and after the last
 * their poses hold.
 */
export function poseAt(animation, pivots, t) {
  const keys = animation.keyframes;
  let next = 0;
  while (next < keys.length && keys[next].time <= t) next++;
  if (next === 0 || next === keys.length || keys[next - 1].time === t) {
    return keys[Math.max(0, next - 1)].pose.map((T) => [...T]);
  }
  const k0 = keys[next - 1];
  const k1 = keys[next];
  const u = ease(k0.easing, (t - k0.time) / (k1.time - k0.time));
  if (u === 0 || u === 1) return (u === 0 ? k0 : k1).pose.map((T) => [...T]);
  return k0.pose.map((T0, i) => interpolateMap(T0, k1.pose[i], pivots[i], u));
}

/** How long the animation plays: its last keyframe's time (0 without keyframes). */
export function duration(animation) {
  const keys = animation?.keyframes ?? [];
  return keys.length ? keys[keys.length - 1].time : 0;
}

/** The index of the keyframe at time t (within `slack` seconds), or -1. */
export function keyAt(animation, t, slack = 1e-9) {
  return animation ? animation.keyframes.findIndex((k) => Math.abs(k.time - t) <= slack) : -1;
}

/**
 * Sets the keyframe at time t to `pose` (whole) or, with `only` (handle indices), changes just
 * those handles' maps of the pose the animation has at t; makes the animation if there is none.
 * Returns the keyframe's index. Mutates `scene`.
 */
export function setKey(scene, t, pose, only = null) {
  if (!scene.animation) scene.animation = { fps: DEFAULT_FPS, keyframes: [] };
  const { animation } = scene;
  let k = keyAt(animation, t);
  const base = only && animation.keyframes.length ? poseAt(animation, scene.handles, t) : null;
  const maps = pose.map((T, i) => [...(base && !only.includes(i) ? base[i] : T)]);
  if (k >= 0) {
    animation.keyframes[k].pose = maps;
  } else {
    // The new keyframe's segment runs as the one it splits did.
    k = animation.keyframes.filter((key) => key.time < t).length;
    const easing = k > 0 ? animation.keyframes[k - 1].easing : 'linear';
    animation.keyframes.splice(k, 0, { time: t, pose: maps, easing });
  }
  return k;
}
