// Drawing frames: the rig's product into the chain points and the paths written from them (the
// per-frame path), the frame-time figure, blends between rigs, the flexible G¹ solve of a pose,
// and the operator's following of handles dragged beyond its training.

import * as affine from './affine.js';
import * as api from './api.js';
import { DefOpLiveRig } from './defop.js';
import { OperatorFollower, blendIn, endBlend } from './follow.js';
import { plural, say, showError, showNotice } from './messages.js';
import { drawOverlay } from './overlays.js';
import { editor, isDefop, notify, rigReady, shortName } from './store.js';
import { checkViewBox } from './viewbox.js';

const $ = (id) => document.getElementById(id);

/**
 * Time a drag's frame may spend writing path data, ms: a drawing whose paths take longer (tens
 * of thousands of curves) has its most moved elements written first, the others in the frames
 * after, so that the drawing follows the pointer at the screen's rate.
 */
export const FRAME_BUDGET_MS = 8;

/** Frames kept for the frame-time figure in the status bar. */
const FRAME_WINDOW = 120;

/** The median of `values` (NaN when there are none). */
function median(values) {
  if (!values.length) return NaN;
  const s = [...values].sort((a, b) => a - b);
  const m = s.length >> 1;
  return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
}

/** Deforms (if the rig is ready) and draws everything; returns the time taken in ms. */
export function render({ timed = false } = {}) {
  const { view, scene } = editor;
  const t0 = performance.now();
  if (scene.handles.length === 0) {
    editor.points.set(editor.rest);
  } else if (rigReady()) {
    editor.rig.deform(scene.pose, editor.points, !timed);
    if (timed && editor.rig instanceof DefOpLiveRig) follower.moved();
  }
  const t1 = performance.now();
  // Text, images, paint copies and the stroke frames of elements stroked in stretched frames
  // by their best-fit maps, as Export SVG writes them (null: where the document has them).
  const maps = scene.handles.length && rigReady() && editor.rig.carryMaps ? editor.rig.carryMaps(scene.pose) : null;
  view.setFrames(maps);
  // A drag's frames write what FRAME_BUDGET_MS allows, the most moved first; the rest follow
  // in the next frames (drawn without waiting for the pointer), the release writes everything.
  if (view.writePaths(editor.points, timed ? FRAME_BUDGET_MS : Infinity)) {
    scheduleFrame();
    if (!editor.partialFramesSaid) {
      editor.partialFramesSaid = true;
      showNotice(
        `${shortName()} is big (${editor.info.n_curves} curves): while you drag, the parts that move most are ` +
          'redrawn first and the rest follow within a few frames; everything is exact when you let go',
      );
    }
  }
  view.writeCarried(maps);
  const t2 = performance.now();
  drawOverlay();
  // While dragging, once on mouse-up (dragged → sceneChanged → render). The fold rings
  // of the last check are stale while the drawing moves: cleared until the next one.
  if (!timed) checkViewBox();
  else if (editor.foldsShown) {
    view.drawFolds([]);
    editor.foldsShown = false;
  }
  if (timed) {
    editor.productTimes.push(t1 - t0);
    editor.frameTimes.push(t2 - t0);
    if (editor.frameTimes.length > 4 * FRAME_WINDOW) {
      editor.frameTimes.splice(0, FRAME_WINDOW);
      editor.productTimes.splice(0, FRAME_WINDOW);
    }
    const recent = editor.frameTimes.slice(-FRAME_WINDOW);
    $('frame-time').textContent = `frame ${median(recent).toFixed(2)} ms`;
  }
  return t2 - t0;
}

// An operator follows the user's drags beyond where it was trained (follow.js): the server
// samples the ground truth there and answers a refitted operator, blended in without a jump.
const follower = new OperatorFollower({
  send: (rig, handles, settle) => api.followOperator(rig.id, handles, settle),
  current: () =>
    editor.rig instanceof DefOpLiveRig && rigReady() && editor.rigState === 'ready' ? editor.rig : null,
  swap(old, info, data) {
    const rig = new DefOpLiveRig(info, data, editor.view.nPoints, editor.scene.handles);
    rig.configuration(editor.scene.pose); // where the handles are, before its first frame
    rig.followsFrom(old); // carries text and paint until its own carry operator arrives
    fetchCarry(rig);
    blendIn(rig, old);
    editor.rig = rig;
    const [, solve, join] = info.seconds;
    say(
      `${shortName()}: the operator followed the handles (${plural(info.n_followed, 'sample')} added where ` +
        `the training did not reach, ${info.n_samples} in all; solved in ${solve.toFixed(2)} s, joined in ${join.toFixed(2)} s)`,
    );
    blendFrames();
  },
  state(name) {
    document.body.dataset.follow = name;
  },
  failed(e) {
    showError(`following the handles: ${e.message}`);
  },
});
editor.follower = follower;

/**
 * Draws frames until a blend (a followed operator, or exact weights after their stand-in)
 * ends, then once more as after any change (the viewBox and fold checks of the final points).
 */
export function blendFrames() {
  requestAnimationFrame(() => {
    render({ timed: true });
    if (editor.rig?.blendingUntil) blendFrames();
    else {
      render();
      flexibleSolve();
    }
  });
}

/** Ends a blend in progress: the points become the new rig's alone (what exports send). */
export function settleBlend() {
  if (!editor.rig?.blendingUntil) return;
  endBlend(editor.rig);
  render();
}

/** Draws a timed frame at the next animation frame (once, however often it is asked for). */
export function scheduleFrame() {
  if (editor.frameRequested) return;
  editor.frameRequested = true;
  requestAnimationFrame(() => {
    editor.frameRequested = false;
    render({ timed: true });
  });
}

/** With flexible G¹ on, the server's solve of the current pose replaces the drawn points. */
export async function flexibleSolve() {
  const { scene } = editor;
  if (!scene.flexible || isDefop(scene) || !rigReady() || scene.pose.every((T) => affine.isIdentity(T))) {
    delete document.body.dataset.solve;
    return;
  }
  const seq = ++editor.solveSeq;
  const pose = structuredClone(scene.pose);
  const rig = editor.rig;
  document.body.dataset.solve = 'running';
  try {
    const points = await api.solve(rig.id, pose);
    if (seq !== editor.solveSeq || rig !== editor.rig) return;
    if (JSON.stringify(pose) !== JSON.stringify(editor.scene.pose)) return;
    editor.points.set(points);
    editor.view.writePaths(editor.points);
    drawOverlay();
    checkViewBox();
    document.body.dataset.solve = 'done';
  } catch (e) {
    if (seq !== editor.solveSeq) return;
    document.body.dataset.solve = 'error';
    if (e.status === 404) {
      // The backend dropped the rig (it keeps a few): built again.
      editor.rigKey = null;
      notify('rig-lost');
    } else {
      showError(e);
    }
  }
}

/**
 * Asks for `rig`'s carry operator (a LiveRig's or a DefOpLiveRig's) when the document has text, images, user-space paint or strokes in stretched frames
 * (they then move with the art on the canvas as Export SVG moves them), and draws again once it is there
 * (`body[data-carry]` names the rig, for the tests).
 */
export async function fetchCarry(rig) {
  const n = editor.info.carried.length + editor.info.painted.length;
  if (!n) return;
  try {
    rig.setCarry(await api.rigCarry(rig.id, rig instanceof DefOpLiveRig), n);
    if (editor.rig !== rig) return;
    document.body.dataset.carry = rig.id;
    // Only what the carry maps move: a full render would draw the rig's product over the
    // points of a flexible G¹ solve that came first, and Export would send those.
    // The points shown are written again only where a stroke frame turned.
    const { scene, view } = editor;
    const maps = scene.handles.length && rigReady() ? rig.carryMaps(scene.pose) : null;
    if (view.setFrames(maps)) view.writePaths(editor.points);
    view.writeCarried(maps);
  } catch (e) {
    if (editor.rig === rig) showError(`${shortName()}: moving its text and images with the art: ${e.message}`);
  }
}
