// The rig of the scene's rest part: precomputed (or, for an operator family, trained) when the
// handles or settings change, a coarse stand-in shown while a mesh family's weights compute, and
// the server's progress followed in the progress bar.

import * as affine from './affine.js';
import { refineForPoses } from './adaptive.js';
import * as api from './api.js';
import { isStatic } from './backend.js';
import { DefOpLiveRig } from './defop.js';
import { blendIn } from './follow.js';
import { blendFrames, fetchCarry, flexibleSolve, render } from './frames.js';
import { clearError, plural, progress, say, showError } from './messages.js';
import { updateMesh, updateWeights } from './overlays.js';
import { updateOnion } from './playback.js';
import { LiveRig } from './rig.js';
import { DEFOP_ENERGIES, MESH_FAMILIES, editor, isDefop, rigKeyOf, setRigState, shortName } from './store.js';

const $ = (id) => document.getElementById(id);

/** How often the progress of a precomputation is asked for, ms. */
const PROGRESS_POLL_MS = 150;

/**
 * Precomputes the rig of the scene's rest part (trains the operator of an operator family),
 * superseding any precomputation under way; then redraws with it.
 */
export async function precompute() {
  const seq = ++editor.precomputeSeq;
  editor.abort?.abort();
  // A training the new request supersedes would go on to its end on the server, taking the
  // cores this one needs: it is asked to stop.
  if (editor.job) api.stopJob(editor.job).catch(() => {});
  const abort = new AbortController();
  editor.abort = abort;
  const scene = structuredClone(editor.scene);
  const key = rigKeyOf(scene);
  setRigState('computing');
  const defop = isDefop(scene);
  const job = `rig-${seq}-${Math.random().toString(36).slice(2, 10)}`;
  editor.job = job;
  progress(defop ? 'training the operator' : 'precomputing');
  $('progress-stop').hidden = !defop;
  render();
  const follow = followProgress(job, seq);
  try {
    const started = performance.now();
    let bytes;
    if (defop) {
      const { info, data } = await api.trainOperator(editor.info.id, scene, abort.signal, job);
      if (seq !== editor.precomputeSeq) return;
      editor.rig = new DefOpLiveRig(info, data, editor.view.nPoints, scene.handles);
      fetchCarry(editor.rig);
      bytes = data.byteLength;
    } else {
      editor.previewSeconds = null;
      if (MESH_FAMILIES.has(scene.weights.family)) preview(scene, key, seq, abort.signal, started);
      const { id, operator } = await api.precompute(editor.info.id, scene, abort.signal, job);
      if (seq !== editor.precomputeSeq) return;
      // The exact weights replace the coarse stand-in under the pose shown: blended in over
      // BLEND_MS (follow.js) rather than with a jump of the stand-in's error.
      const standIn = editor.rigPreview && editor.rigKey === key ? editor.rig : null;
      editor.rig = new LiveRig(id, operator, editor.view.nPoints, scene.handles.length);
      fetchCarry(editor.rig);
      // (With flexible G¹ on, the server's solve replaces the points after the swap anyway.)
      if (standIn && !scene.flexible && !editor.scene.pose.every((T) => affine.isIdentity(T))) {
        blendIn(editor.rig, standIn);
        blendFrames();
      }
      bytes = operator.byteLength;
    }
    editor.rigKey = key;
    editor.rigPreview = false;
    editor.rigSeconds = (performance.now() - started) / 1000;
    setRigState('ready');
    const size = bytes < 1 << 20 ? `${(bytes / 1024).toFixed(0)} KiB` : `${(bytes / (1 << 20)).toFixed(1)} MiB`;
    if (defop) {
      const { info } = editor.rig;
      const [domain, training, join] = info.seconds;
      say(
        `${shortName()}: ${plural(scene.handles.length, 'handle')}, ${DEFOP_ENERGIES[scene.weights.family]} operator ` +
          `(${info.n_samples} samples, ${info.kind} |Ψ| = ${info.n_functions}, ${info.n_triangles} triangles) ` +
          `trained in ${editor.rigSeconds.toFixed(2)} s (domain ${domain.toFixed(2)}, training ` +
          `${training.toFixed(2)}, join ${join.toFixed(2)}); ${size}. Only dragging moves the drawing: ` +
          `the operator follows handle positions, so rotating or scaling a handle changes nothing`,
      );
    } else {
      say(
        `${shortName()}: ${editor.info.n_curves} curves, ${plural(scene.handles.length, 'handle')} ` +
          `(${scene.weights.family}); rig of ${size} in ${editor.rigSeconds.toFixed(2)} s`,
      );
    }
    clearError();
  } catch (e) {
    if (abort.signal.aborted || seq !== editor.precomputeSeq) return;
    editor.rig = null;
    editor.rigKey = null;
    editor.rigPreview = false;
    if (e.status === 409) {
      // Stopped by the user (the Stop button): no operator, and no error either.
      setRigState('stopped');
      say(`${shortName()}: training stopped as asked; the next change of the handles or settings trains again`);
    } else {
      setRigState('error');
      showError(e);
    }
  } finally {
    follow.stop();
    if (editor.job === job) editor.job = null;
    if (seq === editor.precomputeSeq) progress(null);
  }
  if (seq !== editor.precomputeSeq) return;
  render();
  flexibleSolve();
  updateWeights();
  updateOnion();
  updateMesh();
  refineForPoses();
}

/**
 * While a mesh family's weights compute (a second or more on big drawings), a rig of the same
 * handles with the same family solved on a coarse triangulation of the same domain stands in
 * (`weights.coarse`: shape-aware like the real weights, the same parts of the art, in a tenth
 * of their time or less), so that the drawing follows the handles at once; `precompute` swaps
 * the real rig in when it arrives. The pose is the scene's and stays as it is: only the weights
 * under it change.
 */
async function preview(scene, key, seq, signal, started) {
  const quick = { ...scene, weights: { ...scene.weights, coarse: true } };
  try {
    const { id, operator } = await api.precompute(editor.info.id, quick, signal, `preview-${seq}`);
    if (seq !== editor.precomputeSeq || editor.rigState !== 'computing') return;
    editor.rig = new LiveRig(id, operator, editor.view.nPoints, scene.handles.length);
    fetchCarry(editor.rig);
    editor.rigKey = key;
    editor.rigPreview = true;
    editor.previewSeconds = (performance.now() - started) / 1000;
    setRigState('preview');
    say(
      `${shortName()}: ${plural(scene.handles.length, 'handle')}; preview: ${scene.weights.family} ` +
        `weights on a coarser mesh of the same domain, while the exact ones compute`,
    );
    render();
    flexibleSolve();
    updateWeights();
  } catch {
    // The real rig's request reports what went wrong.
  }
}

/** What the progress bar says in each stage the server reports. */
const STAGE_LABELS = {
  // The static build has no server: its requests wait for a worker of the page.
  queued: isStatic ? 'waiting for a worker' : 'waiting for the server',
  weights: 'computing the weights',
  rig: 'precomputing the rig',
  domain: 'triangulating the domain',
  training: 'training the operator',
  join: 'joining the operator with the curves',
};

/** The progress label and fraction of a server report (see api.progressOf). */
function progressLabel({ stage, done, total, step, steps }) {
  const label = STAGE_LABELS[stage] ?? stage;
  if (done === undefined || !total) return [label, null];
  const percent = Math.floor((100 * done) / total);
  return [`${label}: stage ${step}/${steps}, ${done}/${total} ground-truth solves (${percent} %)`, done / total];
}

/**
 * Asks the server every PROGRESS_POLL_MS where precomputation `job` is and shows it, while
 * precomputation `seq` is the current one; `stop()` ends it.
 */
function followProgress(job, seq) {
  let stopped = false;
  let shown = null;
  const poll = async () => {
    if (stopped || seq !== editor.precomputeSeq) return;
    try {
      const report = await api.progressOf(job);
      const { stage } = report;
      const key = `${stage}/${report.done}`;
      if (!stopped && stage && key !== shown && seq === editor.precomputeSeq) {
        const newStage = !shown || !shown.startsWith(`${stage}/`);
        if (newStage) editor.stagesSeen.push(stage);
        if (report.done !== undefined) {
          const { done, total, step, steps } = report;
          editor.countsSeen.push({ done, total, step, steps });
        }
        shown = key;
        progress(...progressLabel(report), newStage);
      }
    } catch {
      // A missed poll only delays the label.
    }
    if (!stopped) timer = setTimeout(poll, PROGRESS_POLL_MS);
  };
  let timer = setTimeout(poll, PROGRESS_POLL_MS);
  return {
    stop() {
      stopped = true;
      clearTimeout(timer);
    },
  };
}
