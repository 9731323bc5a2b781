// The timeline shown and played: keyframes of the pose (the scene's `animation`), played as
// `splineskin animate` plays them (animation.js samples them as the library does), and the onion
// skin of the keyframes around the shown time. Keying and editing keyframes is in edits.js.

import * as anim from './animation.js';
import { autosave } from './autosave.js';
import { render, scheduleFrame } from './frames.js';
import { updateMesh, updateWeights } from './overlays.js';
import { editor, fps, isDefop, keyframes, rigReady } from './store.js';

const $ = (id) => document.getElementById(id);

/** A time in seconds as the readout shows it, with its frame. */
function timeLabel(t) {
  return `${t.toFixed(2)} s`;
}

/** Draws the ruler and sets the timeline's readout and buttons from the state. */
export function drawTimeline() {
  if (!editor.ruler || !editor.scene) return;
  const keys = keyframes();
  const k = editor.selectedKey;
  editor.ruler.draw({ animation: editor.scene.animation, time: editor.time, selectedKey: k, fps: fps() });
  $('time-readout').textContent = timeLabel(editor.time);
  $('time-readout').title = `frame ${Math.round(editor.time * fps())} at ${fps()} fps`;
  $('play').textContent = editor.playing ? '❚❚ Pause' : '▶ Play';
  $('play').disabled = anim.duration(editor.scene.animation) <= 0;
  const noHandles = editor.scene.handles.length === 0;
  $('key-pose').disabled = noHandles;
  $('key-pins').disabled = noHandles || editor.selection.length === 0;
  $('duplicate-key').disabled = k === null;
  $('delete-key').disabled = k === null;
  $('easing').disabled = k === null || k === keys.length - 1;
  $('easing').value = k === null ? 'linear' : keys[k].easing;
  $('fps').disabled = !editor.scene.animation;
  // The exports say why they cannot run, in their hover text.
  const why = anim.duration(editor.scene.animation) <= 0
    ? 'key the pose at two times or more to export an animation'
    : isDefop(editor.scene)
      ? 'the trained operators (Rigid) are not exported as animations yet: pick a weight family'
      : '';
  for (const id of ['export-lottie', 'export-animation']) {
    const button = $(id);
    button.dataset.title ??= button.title;
    button.disabled = Boolean(why);
    button.title = why ? `${button.dataset.title} — not now: ${why}` : button.dataset.title;
  }
  if (document.activeElement !== $('fps')) $('fps').value = fps();
  document.body.dataset.keyframes = String(keys.length);
}

/**
 * Shows time t: the pose is the animation's there (when it has keyframes). `timed`: drawn in
 * the next animation frame and counted in the frame time (playback, scrubbing).
 */
export function showTime(t, { timed = true } = {}) {
  editor.time = t;
  if (keyframes().length) {
    editor.scene.pose = anim.poseAt(editor.scene.animation, editor.scene.handles, t);
    editor.solveSeq++;
  }
  drawTimeline();
  updateOnion();
  if (!editor.playing) {
    updateWeights();
    updateMesh();
  }
  if (timed) scheduleFrame();
  else render();
}

/** Goes to time t (a click or drag on the ruler): from now on the pose follows the timeline. */
export function seek(t) {
  pause();
  editor.animating = true;
  showTime(t);
  autosave();
}

/** Plays the animation from the shown time (from the start when at its end), frame by frame. */
export function play() {
  const D = anim.duration(editor.scene?.animation);
  if (!(D > 0) || editor.playing) return;
  editor.playing = true;
  editor.animating = true;
  document.body.dataset.playing = '1';
  const start = editor.time >= D - 1e-9 ? 0 : editor.time;
  const t0 = performance.now();
  const step = () => {
    if (!editor.playing) return;
    const duration = anim.duration(editor.scene.animation);
    const rate = fps();
    let t = start + (performance.now() - t0) / 1000;
    if (t >= duration) {
      if (editor.loop && duration > 0) {
        t %= duration;
      } else {
        editor.playing = false;
        delete document.body.dataset.playing;
        showTime(duration, { timed: false });
        return;
      }
    }
    // Whole frames, as the exported animation has them: frame f is at f / fps exactly.
    const frame = Math.floor(t * rate + 1e-9);
    const shown = Math.min(frame / rate, duration);
    if (shown !== editor.time) showTime(shown);
    requestAnimationFrame(step);
  };
  drawTimeline();
  requestAnimationFrame(step);
}

/** Stops playing (nothing when not playing). */
export function pause() {
  if (!editor.playing) return;
  editor.playing = false;
  delete document.body.dataset.playing;
  drawTimeline();
  render();
  autosave();
}

/** The drawing at the keyframes before and after the shown time, outlined (onion skin). */
export function updateOnion() {
  const view = editor.view;
  if (!view) return;
  const keys = keyframes();
  if (!editor.shown.onion || !keys.length || !rigReady()) {
    view.drawOnion(null, null);
    return;
  }
  const t = editor.time;
  const before = keys.filter((k) => k.time < t - 1e-9).pop();
  const after = keys.find((k) => k.time > t + 1e-9);
  const points = [before, after].map((k, side) => {
    if (!k) return null;
    const out = editor.onionPoints[side]?.length === 2 * view.nPoints ? editor.onionPoints[side] : new Float64Array(2 * view.nPoints);
    editor.onionPoints[side] = out;
    editor.rig.deform(k.pose, out);
    return out;
  });
  view.drawOnion(...points);
}
