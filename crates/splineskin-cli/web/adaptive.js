// Adaptive control points: where the fit cannot follow the pose the user dragged to, the server
// splits those curves at rest (splineskin::adaptive) and the page shows the refined drawing, its
// rig sharing the weights. The artist's anchors stay; turning it off brings the drawing as opened
// back.

import * as affine from './affine.js';
import * as api from './api.js';
import { autosave } from './autosave.js';
import { MAX_REFINE_POSES } from './constants.js';
import { syncControls } from './controls.js';
import { flexibleSolve, render } from './frames.js';
import { plural, say, showError } from './messages.js';
import { updateMesh, updateWeights } from './overlays.js';
import { drawTimeline, updateOnion } from './playback.js';
import { LiveRig } from './rig.js';
import { editor, isDefop, keyframes, movedJunctions, notify, rigKeyOf, rigReady, shortName } from './store.js';
import { DrawingView } from './view.js';

const $ = (id) => document.getElementById(id);

/** The poses that matter: the one shown and the keyframes'. */
function posesThatMatter() {
  const poses = [editor.scene.pose, ...keyframes().map((k) => k.pose)];
  return structuredClone(poses.slice(0, MAX_REFINE_POSES));
}

/** Turns adaptive control points on (refining for the poses that matter) or off. */
export function setAdaptive(on) {
  editor.adaptive.on = on;
  syncControls();
  if (on) refineForPoses();
  else backToOriginal();
  autosave();
}

/** Asks the server to add control points for the poses that matter (one request at a time). */
export async function refineForPoses() {
  const a = editor.adaptive;
  const { scene } = editor;
  if (!a.on || isDefop(scene) || !(editor.rig instanceof LiveRig) || !rigReady() || editor.rigPreview) return;
  const poses = posesThatMatter();
  if (poses.every((pose) => pose.every((T) => affine.isIdentity(T)))) return; // the rest needs none
  if (a.busy) {
    a.pending = true;
    return;
  }
  a.busy = true;
  document.body.dataset.refine = 'running';
  const rig = editor.rig;
  const sent = structuredClone(scene);
  try {
    const answer = await api.refine(rig.id, sent, poses, a.tolerance);
    a.answers.push(answer);
    const still = () => a.on && editor.rig === rig && editor.rigKey === rigKeyOf(sent);
    const percent = `${(100 * answer.worst).toPrecision(2)} % of the diagonal`;
    if (answer.refined) {
      const operator = await api.rigOperator(answer.rig);
      if (still()) {
        showRefined(answer, operator);
        say(
          `${shortName()}: ${plural(answer.n_inserted, 'control point')} added where the curves could not follow ` +
            `(${answer.n_curves} curves; the fit is within ${percent}${answer.met ? '' : ', the curve budget ran out first'}); ` +
            'show junctions to see them ringed',
        );
      }
    } else if (still()) {
      say(`${shortName()}: the curves follow the pose within ${percent}: no control point needed`);
    }
  } catch (e) {
    showError(`adding control points: ${e.message ?? e}`);
  } finally {
    a.busy = false;
    document.body.dataset.refine = 'idle';
    if (a.pending) {
      a.pending = false;
      refineForPoses();
    }
  }
}

/** Moves the junction kinds of every undo step by `map` (as movedJunctions). */
function moveJunctions(map) {
  for (const s of [...editor.history.undoStack, ...editor.history.redoStack]) s.junctions = movedJunctions(s.junctions, map);
}

/** Shows document `info` in place of the shown one, keeping the scene and the zoom. */
function showInPlace(info) {
  const frame = [...editor.view.frame];
  editor.view = new DrawingView($('canvas'), info);
  editor.view.setFrame(frame);
  editor.info = info;
  editor.rest = Float64Array.from(info.rest);
  editor.points = Float64Array.from(info.rest);
  editor.onionPoints = [null, null];
  editor.weightsShown = null;
}

/** Shows the refined drawing of `answer` (api.refine) with its rig, whose operator is `operator`. */
function showRefined(answer, operator) {
  const a = editor.adaptive;
  if (!a.original) a.original = { info: editor.info, source: editor.source, rig: editor.rig, rigKey: editor.rigKey };
  const before = a.toOriginal ?? editor.info.paths.map((p) => p.joints.map((_, k) => k));
  a.toOriginal = answer.document.paths.map((p, i) => {
    const m = new Array(p.joints.length).fill(-1);
    answer.moved[i].forEach((to, k) => (m[to] = before[i][k]));
    return m;
  });
  moveJunctions(answer.moved);
  showInPlace(answer.document);
  // The server moved the scene's junction kinds to the new joints (the inserted ones G¹).
  editor.scene.junctions = structuredClone(answer.document.scene.junctions);
  editor.rig = new LiveRig(answer.rig, operator, editor.view.nPoints, editor.scene.handles.length);
  editor.rigKey = rigKeyOf(editor.scene);
  render();
  flexibleSolve();
  updateWeights();
  updateMesh();
  updateOnion();
  drawTimeline();
  autosave();
}

/** Shows the drawing as opened again (adaptive control points turned off). */
function backToOriginal() {
  const a = editor.adaptive;
  const original = a.original;
  if (!original) return;
  moveJunctions(a.toOriginal);
  editor.scene.junctions = movedJunctions(editor.scene.junctions, a.toOriginal);
  a.original = null;
  a.toOriginal = null;
  showInPlace(original.info);
  editor.source = original.source;
  if (original.rig && original.rigKey === rigKeyOf(editor.scene)) {
    editor.rig = original.rig;
    editor.rigKey = original.rigKey;
  } else {
    editor.rig = null;
    editor.rigKey = null;
  }
  say(`${shortName()}: the drawing's own ${editor.info.n_curves} curves again`);
  notify('scene-changed');
}
