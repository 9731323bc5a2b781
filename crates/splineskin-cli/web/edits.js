// Edits of the scene, each one undo step: handles added where the posed drawing shows the click,
// deleted, junction kinds cycled, keyframes keyed, deleted and duplicated; the selection; undo
// and redo. Every edit ends in `notify('scene-changed')` (main.js redraws and precomputes).

import * as affine from './affine.js';
import * as anim from './animation.js';
import { syncControls } from './controls.js';
import { say } from './messages.js';
import { drawOverlay, updateWeights } from './overlays.js';
import { drawTimeline, pause, showTime } from './playback.js';
import { blendMaps } from './skinning.js';
import { editor, fps, isDefop, junctionKind, keyframes, notify } from './store.js';
import { JUNCTION_KINDS } from './constants.js';

/** The translation that puts point `h` where map `T` does. */
function translationOf(T, h) {
  const [x, y] = affine.apply(T, h);
  return [1, 0, 0, 1, x - h[0], y - h[1]];
}

/**
 * Replaces every handle's map by the translation that puts the handle where its map does;
 * whether any map changed.
 */
export function translationsOnly(scene) {
  let changed = false;
  const only = (pose) =>
    pose.map((T, i) => {
      if (T[0] === 1 && T[1] === 0 && T[2] === 0 && T[3] === 1) return T;
      changed = true;
      return translationOf(T, scene.handles[i]);
    });
  scene.pose = only(scene.pose);
  for (const key of scene.animation?.keyframes ?? []) key.pose = only(key.pose);
  return changed;
}

/** One undo step: `change` edits the scene in place, then the page follows the change. */
export function edit(change) {
  editor.history.record(editor.scene);
  change(editor.scene);
  notify('scene-changed');
}

/**
 * The rest position and map of a handle added where the posed drawing shows point q: with
 * every handle at rest, q itself and the identity; otherwise the point p whose skinned image
 * Σ wᵢ(p) Tᵢ p is q (Newton steps on Shepard weights of the rest handles, an approximation of
 * the rig's family good enough to place a handle) and the blended map Σ wᵢ(p) Tᵢ there, so
 * that adding the handle leaves the drawing nearly where it is.
 */
function placeHandle(q) {
  const { handles, pose } = editor.scene;
  if (pose.every((T) => affine.isIdentity(T))) return { rest: q, map: [...affine.IDENTITY] };
  const blend = (p) => blendedMap(handles, pose, p);
  let p = [...q];
  for (let step = 0; step < 30; step++) {
    const T = blend(p);
    const s = affine.apply(T, p);
    const inv = affine.inverse([T[0], T[1], T[2], T[3], 0, 0]);
    if (!inv) break;
    const [dx, dy] = affine.apply(inv, [q[0] - s[0], q[1] - s[1]]);
    p = [p[0] + dx, p[1] + dy];
    if (Math.hypot(dx, dy) < 1e-9 * (1 + Math.hypot(p[0], p[1]))) break;
  }
  return { rest: p, map: blend(p) };
}

/** Σ wᵢ(p) Tᵢ: the maps of `pose` blended at rest point p by Shepard weights of `handles`. */
function blendedMap(handles, pose, p) {
  if (pose.every((T) => affine.isIdentity(T))) return [...affine.IDENTITY];
  const w = handles.map(([x, y]) => 1 / Math.max(1e-12, (x - p[0]) ** 2 + (y - p[1]) ** 2));
  const total = w.reduce((a, b) => a + b, 0);
  return blendMaps(pose, w.map((wi) => wi / total));
}

/** `blended` as a pin at `rest` of `scene` takes it: an operator's pins carry translations only. */
function pinMap(scene, blended, rest) {
  return isDefop(scene) ? translationOf(blended, rest) : blended;
}

/**
 * Adds a pin at rest point `rest` with map `map` to `scene`; every keyframe gives it the map
 * its pose has there (blended from the other pins), so that the animation plays on as before.
 */
function pushPin(scene, rest, map) {
  for (const key of scene.animation?.keyframes ?? []) {
    key.pose.push(pinMap(scene, blendedMap(scene.handles, key.pose, rest), rest));
  }
  scene.handles.push(rest);
  scene.pose.push(pinMap(scene, map, rest));
}

/** Whether `p` is a finite point where no pin of the scene is yet. */
function isNewPin(p) {
  return p.every(Number.isFinite) && !editor.scene.handles.some(([x, y]) => x === p[0] && y === p[1]);
}

/** Adds a handle where the drawing as shown has point q, selected (an undo step). */
export function addHandle(q) {
  const { rest, map } = placeHandle(q);
  if (!isNewPin(rest)) return;
  edit((scene) => pushPin(scene, rest, map));
  const i = editor.scene.handles.length - 1;
  editor.selected = i;
  editor.selection = [i];
  drawOverlay();
  syncControls();
  drawTimeline();
  updateWeights();
}

/**
 * Adds pins at rest points `points` (pins placed over the art), one undo step: each takes the
 * map the pins' pose blends there (in every keyframe too), so the drawing stays as shown.
 * Returns how many were added (a point already pinned is passed over).
 */
export function addPins(points) {
  const fresh = points.filter(isNewPin);
  if (!fresh.length) return 0;
  edit((scene) => {
    for (const p of fresh) pushPin(scene, [...p], blendedMap(scene.handles, scene.pose, p));
  });
  return fresh.length;
}

/** Deletes the selected handles (from every keyframe too). */
export function deleteHandles() {
  const doomed = new Set(editor.selection);
  if (!doomed.size) return;
  editor.selected = null;
  editor.selection = [];
  const keep = (_, i) => !doomed.has(i);
  edit((scene) => {
    scene.handles = scene.handles.filter(keep);
    scene.pose = scene.pose.filter(keep);
    for (const key of scene.animation?.keyframes ?? []) key.pose = key.pose.filter(keep);
  });
}

/** Gives junction `j` the next kind of JUNCTION_KINDS (C0, C1, G1, angle; an undo step). */
export function cycleJunction(j) {
  const current = junctionKind(j);
  const next = JUNCTION_KINDS[(JUNCTION_KINDS.indexOf(current) + 1) % JUNCTION_KINDS.length];
  const classified = editor.info.paths[j.path].joints[j.joint];
  edit((scene) => {
    scene.junctions = scene.junctions.filter((x) => !(x.path === j.path && x.joint === j.joint));
    if (next !== classified) scene.junctions.push({ path: j.path, joint: j.joint, kind: next });
  });
  say(`junction ${j.joint} of path ${j.path}: ${next}`);
}

/** Puts back a scene from the history (undo or redo); nothing when the history has none. */
export function restore(scene) {
  if (!scene) return;
  editor.scene = scene;
  editor.selection = editor.selection.filter((i) => i < scene.handles.length);
  if (editor.selected !== null && editor.selected >= scene.handles.length) editor.selected = null;
  const keys = scene.animation?.keyframes.length ?? 0;
  if (editor.selectedKey !== null && editor.selectedKey >= keys) editor.selectedKey = null;
  notify('scene-changed');
}

/** Selects the handles `selection`, `primary` among them (its weight field shown) or null. */
export function select(selection, primary) {
  editor.selection = selection;
  editor.selected = primary;
  drawOverlay();
  syncControls();
  drawTimeline();
  updateWeights();
}

/** Selects no handle (nothing when none is selected). */
export function deselect() {
  if (editor.selected === null && !editor.selection.length) return;
  select([], null);
}

/**
 * Moves the selected pins by `[dx, dy]` drawing units (the arrow keys: one screen pixel, ten
 * with Shift), one undo step: each map `T` becomes `translate(d) ∘ T`. While animating, the
 * moved pins are keyed at the shown time, as a drag keys them.
 */
export function nudge([dx, dy]) {
  const moved = [...editor.selection];
  if (!moved.length) return;
  pause();
  edit((scene) => {
    for (const i of moved) {
      const T = scene.pose[i];
      scene.pose[i] = [T[0], T[1], T[2], T[3], T[4] + dx, T[5] + dy];
    }
    if (editor.animating && scene.animation?.keyframes.length) {
      editor.selectedKey = anim.setKey(scene, editor.time, scene.pose, moved);
    }
  });
}

/** K: keys the selected pins, or the whole pose when none is selected. */
export function keyShortcut() {
  key(editor.selection.length ? [...editor.selection] : null);
}

/** Undoes the last edit (pausing playback). */
export function undo() {
  pause();
  restore(editor.history.undo(editor.scene));
}

/** Redoes the last undone edit. */
export function redo() {
  restore(editor.history.redo(editor.scene));
}

/** Keys the whole pose (`only` null) or the handles `only` at the shown time. */
export function key(only = null) {
  if (!editor.scene.handles.length) return;
  pause();
  editor.animating = true;
  edit((scene) => {
    editor.selectedKey = anim.setKey(scene, editor.time, scene.pose, only);
  });
}

/** Deletes the selected keyframe (the animation goes with its last one). */
export function deleteKey() {
  const k = editor.selectedKey;
  if (k === null) return;
  editor.selectedKey = null;
  edit((scene) => {
    scene.animation.keyframes.splice(k, 1);
    if (!scene.animation.keyframes.length) scene.animation = null;
  });
  if (keyframes().length) showTime(editor.time, { timed: false });
}

/**
 * Copies the selected keyframe's pose to the shown time (or, when the shown time is that
 * keyframe's, one second after the last keyframe).
 */
export function duplicateKey() {
  const k = editor.selectedKey;
  if (k === null) return;
  const source = keyframes()[k];
  let t = editor.time;
  if (anim.keyAt(editor.scene.animation, t) === k) t = anim.duration(editor.scene.animation) + 1;
  t = Math.round(t * fps()) / fps();
  edit((scene) => {
    editor.selectedKey = anim.setKey(scene, t, source.pose);
  });
  showTime(t, { timed: false });
}
