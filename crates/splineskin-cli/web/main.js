// The editor: opens a drawing, places and drags handles, and keeps the drawing following
// them — one matrix–vector product per frame in the page, precomputation on the server.
//
// State: `editor.scene` is what a scene file holds and the undo history snapshots (rest
// handles, one map per handle, weight family, junction overrides, flexible G¹, the timeline's
// keyframes as `animation`); the rig is precomputed for the scene's rest part (`rigKey`) and
// reused while only the pose changes. `editor.time` is the timeline's shown time; the session
// is saved to the browser's storage after every change (Autosave, below).

import * as api from './api.js';
import { isStatic } from './backend.js';
import * as affine from './affine.js';
import * as anim from './animation.js';
import { weightColour, weightImage } from './colour.js';
import { History } from './history.js';
import { LiveRig, littleEndian } from './rig.js';
import { DefOpLiveRig } from './defop.js';
import { OperatorFollower, blendIn, endBlend } from './follow.js';
import { installGestures, selectionCentre } from './gestures.js';
import { TimelineRuler } from './timeline.js';
import { DrawingView, JUNCTION_KINDS, posedHandles } from './view.js';

const $ = (id) => document.getElementById(id);

/** Frames kept for the frame-time figure in the status bar. */
const FRAME_WINDOW = 120;
/** Samples on the long side of the weight grid. */
const WEIGHT_GRID = 200;
/** Samples on the long side of the weight grid drawn on the posed drawing (cells of a mesh). */
const POSED_WEIGHT_GRID = 90;
/** How often the progress of a precomputation is asked for, ms. */
const PROGRESS_POLL_MS = 150;
/** Training samples of an operator when the user has not chosen (DEFAULT_EDITOR_SAMPLES). */
const DEFAULT_DEFOP_SAMPLES = 100;
/** Most training samples the server takes (MAX_EDITOR_SAMPLES). */
const MAX_DEFOP_SAMPLES = 5000;
/** The operator "families" of the weights menu and their ground truths. */
const DEFOP_ENERGIES = { 'defop-arap': 'ARAP', 'defop-sarap': 'symmetric ARAP' };
/** The weight families solved on a triangulated domain: seconds on big drawings. */
const MESH_FAMILIES = new Set(['bbw', 'harmonic', 'biharmonic']);
/** The art-shaped domain's margin, a fraction of the diagonal: its default and largest value
 * (splineskin::domain::DEFAULT_MARGIN, MAX_MARGIN). */
const DEFAULT_MARGIN = 0.01;
const MAX_MARGIN = 1;

const editor = {
  info: null,
  view: null,
  scene: null,
  rig: null,
  rigKey: null,
  /** Whether `rig` is the coarse stand-in of a mesh family still computing. */
  rigPreview: false,
  /** Seconds from the request to the stand-in's arrival, and to the real rig's (for the tests). */
  previewSeconds: null,
  rigSeconds: null,
  rest: null,
  points: null,
  /** The primary selected handle (weight field, last pressed), or null. */
  selected: null,
  /** Every selected handle, `selected` among them. */
  selection: [],
  /** The time shown on the timeline, seconds. */
  time: 0,
  /** The keyframe selected on the timeline (index), or null. */
  selectedKey: null,
  /** Whether the timeline plays. */
  playing: false,
  /**
   * Whether the pose follows the timeline (once the user goes to a time, plays or keys): then
   * a dragged pin is keyed at the shown time.
   */
  animating: false,
  ruler: null,
  /** Chain points of the onion skin's two outlines. */
  onionPoints: [null, null],
  history: new History(),
  /** Milliseconds of each frame drawn while dragging (product + path data). */
  frameTimes: [],
  /** Milliseconds of the product alone, same frames. */
  productTimes: [],
  precomputeSeq: 0,
  /** Stages the server reported for precomputations, in order (for the tests). */
  stagesSeen: [],
  /** Training counts the server reported, { done, total, step, steps } (for the tests). */
  countsSeen: [],
  solveSeq: 0,
  /** The server's last report on the viewBox ({ view_box, fitted, outside }), for the tests. */
  viewBoxReport: null,
  viewBoxSeq: 0,
  abort: null,
  /** The job name of the precomputation under way (`POST /api/progress/{job}/stop` stops it), or null. */
  job: null,
  weightsShown: null,
  /**
   * Adaptive control points: whether they are on, the tolerance (fraction of the diagonal),
   * and while the shown drawing is a refined one, the drawing as opened (`original`: its info,
   * source, rig and rig key) with `toOriginal`, per path and joint of the shown drawing, the
   * opened drawing's joint (-1: inserted).
   */
  adaptive: { on: false, tolerance: 1e-3, original: null, toOriginal: null, busy: false, pending: false, answers: [] },
  /** Whether handles only move (an operator's family: no rotate or scale). */
  translateOnly: () => editor.scene !== null && isDefop(editor.scene),
};
// For the browser tests and the console.
window.splineskinEditor = editor;

// ---------------------------------------------------------------------------------------------
// Messages

function showError(error) {
  const box = $('error');
  box.textContent = error instanceof Error ? error.message : String(error);
  box.hidden = false;
  document.body.dataset.error = '1';
}

function clearError() {
  $('error').hidden = true;
  delete document.body.dataset.error;
}

/** Something the user should know about what was opened; stays until clicked. */
function showNotice(text) {
  const box = $('notice');
  box.textContent = text;
  box.hidden = !text;
}

function say(text) {
  $('message').textContent = text;
}

let progressTimer = null;
let progressStart = 0;
/**
 * Shows `label` with a running clock (restarted unless `restart` is false: a count within the
 * same stage), and a filled bar for `fraction` (0…1) when given.
 */
function progress(label, fraction = null, restart = true) {
  const box = $('progress');
  clearInterval(progressTimer);
  const bar = box.querySelector('.bar');
  bar.classList.toggle('determinate', fraction !== null);
  bar.querySelector('.fill').style.width = fraction === null ? '0' : `${(100 * fraction).toFixed(1)}%`;
  if (!label) {
    box.hidden = true;
    $('progress-stop').hidden = true;
    return;
  }
  if (restart || box.hidden) progressStart = performance.now();
  const start = progressStart;
  const tick = () => {
    $('progress-text').textContent = `${label} ${((performance.now() - start) / 1000).toFixed(1)} s`;
  };
  tick();
  box.hidden = false;
  progressTimer = setInterval(tick, 100);
}

/** `n thing` or `n things`. */
function plural(n, thing) {
  return `${n} ${thing}${n === 1 ? '' : 's'}`;
}

function median(values) {
  if (!values.length) return NaN;
  const s = [...values].sort((a, b) => a - b);
  const m = s.length >> 1;
  return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
}

// ---------------------------------------------------------------------------------------------
// Opening

/** Shows document `info`; `source` is the text of the file the page opened (null: the server's). */
function show(info, source = null) {
  const view = new DrawingView($('canvas'), info);
  editor.info = info;
  editor.source = source;
  editor.view = view;
  editor.scene = structuredClone(info.scene);
  editor.rest = Float64Array.from(info.rest);
  editor.points = Float64Array.from(info.rest);
  editor.rig = null;
  editor.rigKey = null;
  editor.rigPreview = false;
  editor.selected = null;
  editor.selection = [];
  pause();
  editor.time = 0;
  editor.selectedKey = null;
  editor.animating = false;
  editor.onionPoints = [null, null];
  editor.weightsShown = null;
  editor.adaptive.original = null;
  editor.adaptive.toOriginal = null;
  editor.history.clear();
  editor.frameTimes = [];
  editor.productTimes = [];
  editor.viewBoxReport = null;
  showViewBoxReport(null);
  document.body.dataset.rig = 'none';
  document.title = `${info.name} — splineskin editor`;
  clearError();
  // Junction markers are hidden by default (they clutter the art); showing them is the
  // junction-editing mode, in which a click on a marker changes its kind.
  $('show-junctions').checked = false;
  say(`${shortName()}: ${info.n_curves} curves in ${info.paths.length} paths`);
  // A scene's defop section: offered in the Weights menu, its sample count prefilled.
  $('defop-samples').value = info.operator?.samples ?? DEFAULT_DEFOP_SAMPLES;
  const offer = info.operator
    ? [`this scene describes a ${DEFOP_ENERGIES[info.operator.family]} operator (${info.operator.samples} samples): ` +
        'pick it in the Weights menu to train it']
    : [];
  showNotice([...info.warnings, ...offer].join('\n'));
  syncControls();
  sceneChanged();
}

async function open(file) {
  say(`opening ${file.name}…`);
  progress(`reading ${file.name}`);
  try {
    const source = await file.text();
    show(await api.openFile(file), source);
  } catch (e) {
    showError(e);
    say(`${file.name} was not opened`);
  } finally {
    progress(null);
  }
}

// ---------------------------------------------------------------------------------------------
// Scene changes, rig and drawing

/** Whether the scene's "family" is a trained deformation operator. */
function isDefop(scene) {
  return scene.weights.family in DEFOP_ENERGIES;
}

/** What the rig depends on (everything but the pose). */
function rigKeyOf(scene) {
  return JSON.stringify([scene.handles, scene.weights, scene.junctions, scene.flexible, scene.margin ?? null]);
}

/** After any change of the scene: precompute if its rest part changed, else redraw. */
function sceneChanged() {
  const key = rigKeyOf(editor.scene);
  if (editor.scene.handles.length === 0) {
    editor.abort?.abort();
    editor.rig = null;
    editor.rigKey = key;
    editor.rigPreview = false;
    document.body.dataset.rig = 'none';
    progress(null);
    if (isDefop(editor.scene)) say(`${shortName()}: click on the art to add point handles; the operator is trained for them`);
    render();
  } else if (key !== editor.rigKey) {
    precompute();
  } else {
    render();
    flexibleSolve();
  }
  syncControls();
  updateWeights();
  updateMesh();
  drawTimeline();
  updateOnion();
  autosave();
}

async function precompute() {
  const seq = ++editor.precomputeSeq;
  editor.abort?.abort();
  // A training the new request supersedes would go on to its end on the server, taking the
  // cores this one needs: it is asked to stop.
  if (editor.job) api.stopJob(editor.job).catch(() => {});
  const abort = new AbortController();
  editor.abort = abort;
  const scene = structuredClone(editor.scene);
  const key = rigKeyOf(scene);
  document.body.dataset.rig = 'computing';
  const defop = isDefop(scene);
  const job = `rig-${seq}-${Math.random().toString(36).slice(2, 10)}`;
  editor.job = job;
  progress(defop ? 'training the operator' : 'precomputing');
  $('progress-stop').hidden = !defop || isStatic;
  render();
  const follow = followProgress(job, seq);
  try {
    const started = performance.now();
    let bytes;
    if (defop) {
      const { info, data } = await api.trainOperator(editor.info.id, scene, abort.signal, job);
      if (seq !== editor.precomputeSeq) return;
      editor.rig = new DefOpLiveRig(info, data, editor.view.nPoints, scene.handles);
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
    document.body.dataset.rig = 'ready';
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
      document.body.dataset.rig = 'stopped';
      say(`${shortName()}: training stopped as asked; the next change of the handles or settings trains again`);
    } else {
      document.body.dataset.rig = 'error';
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
    if (seq !== editor.precomputeSeq || document.body.dataset.rig !== 'computing') return;
    editor.rig = new LiveRig(id, operator, editor.view.nPoints, scene.handles.length);
    editor.rigKey = key;
    editor.rigPreview = true;
    editor.previewSeconds = (performance.now() - started) / 1000;
    document.body.dataset.rig = 'preview';
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
  queued: 'waiting for the server',
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

/** Whether the rig matches the scene's rest part. */
function rigReady() {
  return editor.rig !== null && editor.rigKey === rigKeyOf(editor.scene);
}

/** Deforms (if the rig is ready) and draws everything; returns the time taken in ms. */
function render({ timed = false } = {}) {
  const { view, scene } = editor;
  const t0 = performance.now();
  if (scene.handles.length === 0) {
    editor.points.set(editor.rest);
  } else if (rigReady()) {
    editor.rig.deform(scene.pose, editor.points);
    if (timed && editor.rig instanceof DefOpLiveRig) follower.moved();
  }
  const t1 = performance.now();
  view.writePaths(editor.points);
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

function junctionKind(j) {
  const o = editor.scene.junctions.find((x) => x.path === j.path && x.joint === j.joint);
  return o ? o.kind : editor.info.paths[j.path].joints[j.joint];
}

function drawOverlay() {
  const { view } = editor;
  view.drawJunctions(editor.points, junctionKind, $('show-junctions').checked);
  // An operator moves pins only: no rotate or scale widgets.
  const centre = isDefop(editor.scene) ? null : selectionCentre(editor.scene, editor.selection);
  view.drawHandles(posedHandles(editor.scene), editor.selection, centre);
}

// An operator follows the user's drags beyond where it was trained (follow.js): the server
// samples the ground truth there and answers a refitted operator, blended in without a jump.
const follower = new OperatorFollower({
  send: (rig, handles, settle) => api.followOperator(rig.id, handles, settle),
  current: () =>
    editor.rig instanceof DefOpLiveRig && rigReady() && document.body.dataset.rig === 'ready' ? editor.rig : null,
  swap(old, info, data) {
    const rig = new DefOpLiveRig(info, data, editor.view.nPoints, editor.scene.handles);
    rig.configuration(editor.scene.pose); // where the handles are, before its first frame
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
function blendFrames() {
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
function settleBlend() {
  if (!editor.rig?.blendingUntil) return;
  endBlend(editor.rig);
  render();
}

let frameRequested = false;
function scheduleFrame() {
  if (frameRequested) return;
  frameRequested = true;
  requestAnimationFrame(() => {
    frameRequested = false;
    render({ timed: true });
  });
}

/** With flexible G¹ on, the server's solve of the current pose replaces the drawn points. */
async function flexibleSolve() {
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
      editor.rigKey = null;
      precompute();
    } else {
      showError(e);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The viewBox: whether the deformed art leaves it (the server's report, after each change)

/** A distance in drawing units, to about four significant digits. */
// ---------------------------------------------------------------------------------------------
// Adaptive control points: where the fit cannot follow the pose the user dragged to, the server
// splits those curves at rest (splineskin::adaptive) and the page shows the refined drawing,
// its rig sharing the weights. The artist's anchors stay; turning it off brings the drawing as
// opened back.

/** Largest number of poses one request measures (editor.rs MAX_REFINE_POSES). */
const MAX_REFINE_POSES = 64;

/** The poses that matter: the one shown and the keyframes'. */
function posesThatMatter() {
  const poses = [editor.scene.pose, ...keyframes().map((k) => k.pose)];
  return structuredClone(poses.slice(0, MAX_REFINE_POSES));
}

/** Turns adaptive control points on (refining for the poses that matter) or off. */
function setAdaptive(on) {
  editor.adaptive.on = on;
  syncControls();
  if (on) refineForPoses();
  else backToOriginal();
  autosave();
}

/** Asks the server to add control points for the poses that matter (one request at a time). */
async function refineForPoses() {
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

/** `junctions` moved by `map` (per path, joint → joint, or -1: dropped). */
function movedJunctions(junctions, map) {
  return junctions.flatMap((j) => {
    const to = map[j.path]?.[j.joint] ?? -1;
    return to < 0 ? [] : [{ ...j, joint: to }];
  });
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
  sceneChanged();
}

/** The scene as the drawing as opened has it (junction kinds on its own joints). */
function sceneOfOriginal() {
  const map = editor.adaptive.toOriginal;
  return map ? { ...editor.scene, junctions: movedJunctions(editor.scene.junctions, map) } : editor.scene;
}

function units(v) {
  return Number(v.toPrecision(4)).toString();
}

/**
 * Asks the server whether the drawing as shown leaves the document's viewBox and says so in
 * the status line; the latest answer wins. `body[data-viewbox]` is 'inside', 'outside' or
 * 'checking' (for the tests).
 */
async function checkViewBox() {
  const seq = ++editor.viewBoxSeq;
  const { info } = editor;
  const points = Float64Array.from(editor.points);
  document.body.dataset.viewbox = 'checking';
  try {
    const report = await api.outside(info.id, points);
    if (seq !== editor.viewBoxSeq || info !== editor.info) return;
    editor.viewBoxReport = report;
    showViewBoxReport(report);
  } catch (e) {
    if (seq !== editor.viewBoxSeq) return;
    delete document.body.dataset.viewbox;
    if (e.status !== 404) showError(e);
  }
}

/**
 * Rings the folds of the report in red and says how many in the status line;
 * `body[data-folds]` is their count (for the tests).
 */
function showFolds(report) {
  const folds = report?.folds ?? [];
  editor.view?.drawFolds(folds.map((f) => f.at));
  editor.foldsShown = folds.length > 0;
  document.body.dataset.folds = String(folds.length);
  const note = $('fold-note');
  note.hidden = folds.length === 0;
  note.textContent = folds.length
    ? `${folds.length} fold${folds.length === 1 ? '' : 's'}: an outline crosses itself (red)`
    : '';
  note.title = folds.map((f) => `path ${f.path}: curves ${f.curves[0]} and ${f.curves[1]}`).join('\n');
}

function showViewBoxReport(report) {
  showFolds(report);
  const note = $('viewbox-note');
  const outside = report?.outside ?? [];
  editor.view?.showViewBox(outside.length > 0);
  if (!report) {
    delete document.body.dataset.viewbox;
  } else {
    document.body.dataset.viewbox = outside.length ? 'outside' : 'inside';
  }
  note.hidden = outside.length === 0;
  if (!outside.length) {
    note.textContent = '';
    return;
  }
  const far = outside[0];
  const n = outside.length;
  note.textContent =
    `${n} path${n === 1 ? '' : 's'} leave${n === 1 ? 's' : ''} the viewBox (dashed), ` +
    `farthest ${far.element} by ${units(far.distance)} units`;
  const [x, y, w, h] = report.fitted;
  note.title =
    outside.map((o) => `${o.element}: ${units(o.distance)}`).join('\n') +
    `\n\nExport with viewBox "keep" crops them; "fit art" writes viewBox ${[x, y, w, h].map(units).join(' ')}`;
}

// ---------------------------------------------------------------------------------------------
// Edits

/** The translation that puts point `h` where map `T` does. */
function translationOf(T, h) {
  const [x, y] = affine.apply(T, h);
  return [1, 0, 0, 1, x - h[0], y - h[1]];
}

/**
 * Replaces every handle's map by the translation that puts the handle where its map does;
 * whether any map changed.
 */
function translationsOnly(scene) {
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

function edit(change) {
  editor.history.record(editor.scene);
  change(editor.scene);
  sceneChanged();
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
  const T = [0, 0, 0, 0, 0, 0];
  pose.forEach((Ti, i) => Ti.forEach((v, c) => (T[c] += (w[i] / total) * v)));
  return T;
}

function addHandle(q) {
  const { rest, map: blended } = placeHandle(q);
  // An operator's handles carry translations only (their posed point kept).
  const map = isDefop(editor.scene) ? translationOf(blended, rest) : blended;
  if (!rest.every(Number.isFinite)) return;
  if (editor.scene.handles.some(([x, y]) => x === rest[0] && y === rest[1])) return;
  edit((scene) => {
    // Every keyframe gives the new pin the map its pose has there (blended from the others), so
    // that the animation plays on as before.
    for (const key of scene.animation?.keyframes ?? []) {
      const keyed = blendedMap(scene.handles, key.pose, rest);
      key.pose.push(isDefop(scene) ? translationOf(keyed, rest) : keyed);
    }
    scene.handles.push(rest);
    scene.pose.push(map);
  });
  const i = editor.scene.handles.length - 1;
  editor.selected = i;
  editor.selection = [i];
  drawOverlay();
  syncControls();
  drawTimeline();
  updateWeights();
}

/** Deletes the selected handles (from every keyframe too). */
function deleteHandles() {
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

function cycleJunction(j) {
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
function restore(scene) {
  if (!scene) return;
  editor.scene = scene;
  editor.selection = editor.selection.filter((i) => i < scene.handles.length);
  if (editor.selected !== null && editor.selected >= scene.handles.length) editor.selected = null;
  const keys = scene.animation?.keyframes.length ?? 0;
  if (editor.selectedKey !== null && editor.selectedKey >= keys) editor.selectedKey = null;
  sceneChanged();
}

/** K: keys the selected pins, or the whole pose when none is selected. */
function keyShortcut() {
  key(editor.selection.length ? [...editor.selection] : null);
}

function undo() {
  pause();
  restore(editor.history.undo(editor.scene));
}

function redo() {
  restore(editor.history.redo(editor.scene));
}

function syncControls() {
  const { scene } = editor;
  $('family').value = scene.weights.family;
  $('flexible').checked = scene.flexible;
  const defop = isDefop(scene);
  $('flexible').disabled = defop;
  $('flexible').parentElement.title = defop
    ? 'Flexible G¹ does not apply to a trained operator: its join keeps the junction constraints as they are'
    : 'G¹ junctions keep parallel tangents but not their length ratio (solved on mouse-up)';
  $('adaptive').checked = editor.adaptive.on;
  $('adaptive').disabled = defop;
  $('adaptive-label').title = defop
    ? 'Control points are added to the spline fit of weights; a trained operator joins the drawing as it is'
    : "Where a curve cannot follow the pose you drag to, split it at rest and add a control point there (the artist's anchors stay; added ones are ringed among the junctions)";
  $('adaptive-tolerance-label').hidden = !editor.adaptive.on || defop;
  $('defop-samples-label').hidden = !defop;
  $('margin-label').hidden = !MESH_FAMILIES.has(scene.weights.family);
  $('margin').value = String(Number(((scene.margin ?? DEFAULT_MARGIN) * 100).toPrecision(6)));
  if (defop) $('defop-samples').value = scene.weights.samples ?? DEFAULT_DEFOP_SAMPLES;
  $('show-weights').disabled = defop;
  $('undo').disabled = !editor.history.canUndo;
  $('redo').disabled = !editor.history.canRedo;
  $('delete-handle').disabled = editor.selection.length === 0;
  $('reset-pose').disabled = scene.pose.every((T) => affine.isIdentity(T));
}

// ---------------------------------------------------------------------------------------------
// Weight field

async function updateWeights() {
  const wanted =
    $('show-weights').checked && editor.selected !== null && rigReady() && !(editor.rig instanceof DefOpLiveRig);
  $('weight-legend').hidden = !wanted;
  if (!wanted) {
    editor.weightsShown = null;
    editor.view?.showWeights(null);
    return;
  }
  const { pose } = editor.scene;
  const atRest = pose.every((T) => affine.isIdentity(T));
  // Posed, the field is drawn where the pose puts it (its key changes with the pose).
  const key = `${editor.rig.id}/${editor.selected}${atRest ? '' : `/${JSON.stringify(pose)}`}`;
  if (editor.weightsShown === key) return;
  editor.weightsShown = key;
  const [x, y, w, h] = editor.info.view_box;
  const box = [x, y, x + w, y + h];
  const cells = atRest ? WEIGHT_GRID : POSED_WEIGHT_GRID;
  const scale = cells / Math.max(w, h);
  const width = Math.max(2, Math.round(w * scale));
  const height = Math.max(2, Math.round(h * scale));
  try {
    if (atRest) {
      const values = await api.weightGrid(editor.rig.id, editor.selected, box, width, height);
      if (editor.weightsShown !== key) return;
      editor.view.showWeights(weightImage(values, width, height), box);
      return;
    }
    // Every handle's weights at the grid's points, each point carried where the skinning
    // map Σᵢ wᵢ(x) Tᵢ x puts it, the selected handle's weight coloured over the cells between.
    const grids = await Promise.all(pose.map((_, i) => api.weightGrid(editor.rig.id, i, box, width, height)));
    if (editor.weightsShown !== key) return;
    const [x0, y0, x1, y1] = box;
    const points = new Float64Array(2 * width * height);
    for (let r = 0; r < height; r++) {
      for (let c = 0; c < width; c++) {
        const k = r * width + c;
        const p = [x0 + ((c + 0.5) * (x1 - x0)) / width, y0 + ((r + 0.5) * (y1 - y0)) / height];
        let [sx, sy] = [0, 0];
        pose.forEach((T, i) => {
          const wi = grids[i][k];
          sx += wi * (T[0] * p[0] + T[2] * p[1] + T[4]);
          sy += wi * (T[1] * p[0] + T[3] * p[1] + T[5]);
        });
        points[2 * k] = sx;
        points[2 * k + 1] = sy;
      }
    }
    editor.view.showWeightMesh(points, grids[editor.selected], width, height, weightColour);
  } catch (e) {
    editor.weightsShown = null;
    showError(e);
  }
}

// ---------------------------------------------------------------------------------------------
// Mesh: the triangulated domain the weights are solved on, carried by the pose

/** The rig's mesh as last fetched: { rig (id), mesh (api.mesh), edges } or null. */
let shownMesh = null;
let meshRequest = null;

/** Draws the mesh at the current pose (fetched once per rig), or hides it. */
async function updateMesh() {
  const view = editor.view;
  if (!view) return;
  const wanted = $('show-mesh').checked && rigReady() && !isDefop(editor.scene) && !editor.rigPreview;
  if (!wanted) {
    view.drawMesh(null);
    return;
  }
  const id = editor.rig.id;
  if (shownMesh?.rig !== id) {
    if (meshRequest?.rig === id) return;
    meshRequest = { rig: id };
    try {
      const mesh = await api.mesh(id);
      const edges = new Map();
      const t = mesh.triangles;
      for (let k = 0; k < t.length; k += 3) {
        for (const [a, b] of [[t[k], t[k + 1]], [t[k + 1], t[k + 2]], [t[k + 2], t[k]]]) {
          edges.set(a < b ? `${a},${b}` : `${b},${a}`, a < b ? [a, b] : [b, a]);
        }
      }
      shownMesh = { rig: id, mesh, edges: [...edges.values()] };
      say(`${shortName()}: the weights' mesh has ${mesh.vertices.length / 2} vertices and ${t.length / 3} triangles over ${mesh.boundary}`);
    } catch (e) {
      shownMesh = null;
      view.drawMesh(null);
      // Weights without a mesh: said in the status line, the box stays as the user left it.
      if (e.status === 400) say(`${shortName()}: ${e.message}`);
      else showError(e);
      return;
    } finally {
      meshRequest = null;
    }
    if (editor.rig?.id !== id) return;
  }
  // Each vertex where the skinning map puts it: Σᵢ wᵢ(v) Tᵢ v.
  const { mesh, edges } = shownMesh;
  const pose = editor.scene.pose;
  const n = mesh.n_handles;
  if (pose.length !== n) return;
  const points = new Float64Array(mesh.vertices.length);
  for (let v = 0; v < mesh.vertices.length / 2; v++) {
    const [x, y] = [mesh.vertices[2 * v], mesh.vertices[2 * v + 1]];
    let [sx, sy] = [0, 0];
    for (let i = 0; i < n; i++) {
      const w = mesh.weights[v * n + i];
      const T = pose[i];
      sx += w * (T[0] * x + T[2] * y + T[4]);
      sy += w * (T[1] * x + T[3] * y + T[5]);
    }
    points[2 * v] = sx;
    points[2 * v + 1] = sy;
  }
  view.drawMesh(points, edges);
  document.body.dataset.mesh = String(edges.length);
}

// ---------------------------------------------------------------------------------------------
// Pointer gestures (gestures.js): what they do to the editor

const gestureActions = {
  select(selection, primary) {
    editor.selection = selection;
    editor.selected = primary;
    drawOverlay();
    syncControls();
    drawTimeline();
    updateWeights();
  },
  posed(maps) {
    pause();
    for (const [i, map] of maps) editor.scene.pose[i] = map;
    editor.solveSeq++; // a solve of an older pose must not land now
    scheduleFrame();
  },
  dragged(before, handles) {
    editor.history.record(before);
    // Animating: the dragged pins are keyed at the shown time.
    if (editor.animating && editor.scene.animation?.keyframes.length) {
      editor.selectedKey = anim.setKey(editor.scene, editor.time, editor.scene.pose, handles);
    }
    sceneChanged();
    if (editor.rig instanceof DefOpLiveRig) follower.released();
    else if (editor.adaptive.on) refineForPoses();
  },
  boxChanged(box) {
    editor.view.showBox(box);
  },
  clicked(p, [clientX, clientY], altKey) {
    const junction = $('show-junctions').checked ? editor.view.junctionAt(editor.points, p) : null;
    if (junction) {
      cycleJunction(junction);
    } else if (altKey || editor.view.artAt(clientX, clientY)) {
      // Pins go on the art, as in Puppet Warp; Alt places one anywhere (say, outside a shape).
      addHandle(p);
    } else {
      // Empty canvas: deselect.
      deselect();
    }
  },
  viewChanged() {
    drawOverlay();
  },
};

// ---------------------------------------------------------------------------------------------
// Timeline: keyframes of the pose (the scene's `animation`), played as `splineskin animate` plays
// them (animation.js samples them as the library does)

/** The scene's keyframes (empty without an animation). */
function keyframes() {
  return editor.scene?.animation?.keyframes ?? [];
}

function fps() {
  return editor.scene?.animation?.fps ?? anim.DEFAULT_FPS;
}

/** A time in seconds as the readout shows it, with its frame. */
function timeLabel(t) {
  return `${t.toFixed(2)} s`;
}

function drawTimeline() {
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
  $('export-lottie').disabled = anim.duration(editor.scene.animation) <= 0 || isDefop(editor.scene);
  if (document.activeElement !== $('fps')) $('fps').value = fps();
  document.body.dataset.keyframes = String(keys.length);
}

/**
 * Shows time t: the pose is the animation's there (when it has keyframes). `timed`: drawn in
 * the next animation frame and counted in the frame time (playback, scrubbing).
 */
function showTime(t, { timed = true } = {}) {
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
function seek(t) {
  pause();
  editor.animating = true;
  showTime(t);
  autosave();
}

function play() {
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
      if ($('loop').checked && duration > 0) {
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

function pause() {
  if (!editor.playing) return;
  editor.playing = false;
  delete document.body.dataset.playing;
  drawTimeline();
  render();
  autosave();
}

/** Keys the whole pose (`only` null) or the handles `only` at the shown time. */
function key(only = null) {
  if (!editor.scene.handles.length) return;
  pause();
  editor.animating = true;
  edit((scene) => {
    editor.selectedKey = anim.setKey(scene, editor.time, scene.pose, only);
  });
}

function deleteKey() {
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
function duplicateKey() {
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

/** Keyframe dragging on the ruler: the scene as it was when the drag started. */
let keyDragBefore = null;

const rulerActions = {
  seek,
  keyPressed(k) {
    pause();
    editor.selectedKey = k;
    keyDragBefore = structuredClone(editor.scene);
    editor.animating = true;
    showTime(keyframes()[k].time, { timed: false });
  },
  keyMoved(k, t, done) {
    const keys = keyframes();
    if (!keys[k]) return;
    const step = 1 / fps();
    const lo = k > 0 ? keys[k - 1].time : -Infinity;
    const hi = k < keys.length - 1 ? keys[k + 1].time : Infinity;
    // Between its neighbours: a keyframe does not pass another.
    if (t <= lo) t = lo + step;
    if (t >= hi) t = hi - step;
    if (t > lo && t < hi && t >= 0) {
      keys[k].time = t;
      editor.time = t;
      drawTimeline();
    }
    if (done && keyDragBefore) {
      if (JSON.stringify(keyDragBefore.animation) !== JSON.stringify(editor.scene.animation)) {
        editor.history.record(keyDragBefore);
      }
      keyDragBefore = null;
      showTime(editor.time, { timed: false });
      sceneChanged();
    }
  },
};

/** The drawing at the keyframes before and after the shown time, outlined (onion skin). */
function updateOnion() {
  const view = editor.view;
  if (!view) return;
  const keys = keyframes();
  if (!$('onion').checked || !keys.length || !rigReady()) {
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

// ---------------------------------------------------------------------------------------------
// Autosave: the session (the opened file, the scene, the shown time) in the browser's storage
// after every change, offered back after a reload

const AUTOSAVE_KEY = 'splineskin-editor-session';
/** Largest opened file kept with the session, characters (storage holds a few MB). */
const AUTOSAVE_MAX_SOURCE = 2_000_000;
let autosaveTimer = null;

/** Saves the session soon (changes in a burst are saved once). */
function autosave() {
  if (!editor.info || editor.restoring) return;
  clearTimeout(autosaveTimer);
  autosaveTimer = setTimeout(saveSessionNow, 150);
}

function saveSessionNow() {
  if (!editor.info) return;
  // A refined drawing is saved as the drawing as opened with adaptive control points on: the
  // next drag adds them again.
  const opened = editor.adaptive.original?.info ?? editor.info;
  const session = {
    version: 1,
    name: opened.name,
    // The file opened in this page (the server's own drawing needs none).
    source: editor.source && editor.source.length <= AUTOSAVE_MAX_SOURCE ? editor.source : null,
    svgLength: opened.svg.length,
    scene: sceneOfOriginal(),
    adaptive: editor.adaptive.on ? { tolerance: editor.adaptive.tolerance } : null,
    time: editor.time,
    savedAt: new Date().toISOString(),
  };
  try {
    localStorage.setItem(AUTOSAVE_KEY, JSON.stringify(session));
    document.body.dataset.autosaved = session.savedAt;
  } catch {
    // Storage full or refused: the session is simply not kept.
  }
}

/** The saved session, if any and readable. */
function savedSession() {
  try {
    const session = JSON.parse(localStorage.getItem(AUTOSAVE_KEY) ?? 'null');
    return session?.version === 1 && session.scene ? session : null;
  } catch {
    return null;
  }
}

/**
 * Puts back a saved session after a reload: its file reopened (if it was one the page opened),
 * its scene and time. Undo goes back to the drawing as it opened.
 */
async function recoverSession(session) {
  if (session.source) {
    const file = new File([session.source], session.name.split(/[\\/]/).pop());
    const info = await api.openFile(file);
    show(info, session.source);
  } else if (session.name !== editor.info.name || session.svgLength !== editor.info.svg.length) {
    return false;
  }
  const scene = session.scene;
  if (!Array.isArray(scene.handles) || !Array.isArray(scene.pose) || scene.pose.length !== scene.handles.length) return false;
  editor.history.record(editor.scene);
  editor.scene = { ...structuredClone(editor.scene), ...scene };
  editor.time = Number.isFinite(session.time) ? session.time : 0;
  editor.animating = Boolean(scene.animation);
  const tolerance = session.adaptive?.tolerance;
  if (Number.isFinite(tolerance) && tolerance > 0) {
    editor.adaptive.on = true;
    editor.adaptive.tolerance = tolerance;
    $('adaptive-tolerance').value = String(tolerance * 100);
  }
  syncControls();
  sceneChanged();
  const when = new Date(session.savedAt).toLocaleString();
  showNotice(`restored your session on ${shortName()} from ${when} (Undo goes back to the file as it opened)`);
  document.body.dataset.recovered = '1';
  return true;
}

// ---------------------------------------------------------------------------------------------
// Files out

function download(text, name, type) {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

/** The opened file's name without its folder. */
function shortName() {
  return editor.info.name.split(/[\\/]/).pop() || editor.info.name;
}

function baseName() {
  const name = editor.info.name.split(/[\\/]/).pop() || 'drawing';
  return name.replace(/\.(svg|json)$/i, '').replace(/\s*\(bundled\)$/, '');
}

/**
 * What deformed the drawing as shown, for the export (api.exportSvg): the rig and pose, or the
 * operator and its configuration Q; null without handles or while no rig matches the scene.
 */
function shownDeformation() {
  const { scene } = editor;
  if (scene.handles.length === 0 || !rigReady()) return null;
  if (isDefop(scene)) {
    editor.rig.configuration(scene.pose);
    return { defop: editor.rig.id, q: editor.rig.q };
  }
  return { rig: editor.rig.id, pose: scene.pose };
}

async function exportSvg() {
  try {
    const viewbox = $('export-viewbox').value;
    settleBlend();
    const svg = await api.exportSvg(editor.info.id, editor.points, viewbox, shownDeformation());
    download(svg, `${baseName()}-deformed.svg`, 'image/svg+xml');
    const outside = editor.viewBoxReport?.outside.length ?? 0;
    const how = !outside ? '' : viewbox === 'fit' ? ' (viewBox grown to include the art)' : ' (viewBox kept: art outside it is cropped)';
    say(`exported ${baseName()}-deformed.svg${how}`);
  } catch (e) {
    showError(e);
    // The server keeps a few rigs only: an old one is built again, and Export works again.
    if (e.status === 404 && editor.rig) {
      editor.rigKey = null;
      precompute();
    }
  }
}

async function exportLottie() {
  pause();
  progress('writing the Lottie animation');
  try {
    const { json, report } = await api.exportLottie(editor.info.id, editor.scene);
    download(json, `${baseName()}.json`, 'application/json');
    editor.lottieReport = report;
    say(`exported ${baseName()}.json: ${report?.summary ?? `${json.length} bytes`}`);
    showNotice(report?.warnings.length ? `Lottie: ${report.warnings.join('\n')}` : '');
  } catch (e) {
    showError(e);
  } finally {
    progress(null);
  }
}

async function saveScene() {
  try {
    // With an operator, the file keeps the scene's weights and says how to train the operator
    // in its `defop` section (the server writes it: scene_file.rs), so that
    // `splineskin defop train` on it trains the same one.
    const json = await api.sceneFile(editor.info.id, editor.scene);
    download(json, `${baseName()}-scene.json`, 'application/json');
    const { weights } = editor.scene;
    say(
      isDefop(editor.scene)
        ? `saved ${baseName()}-scene.json with its operator (${DEFOP_ENERGIES[weights.family]}, ` +
            `${weights.samples ?? DEFAULT_DEFOP_SAMPLES} samples) in its defop section`
        : `saved ${baseName()}-scene.json`,
    );
  } catch (e) {
    showError(e);
  }
}

// ---------------------------------------------------------------------------------------------
// Wiring

function wire() {
  installGestures($('canvas'), editor, gestureActions);
  editor.ruler = new TimelineRuler($('ruler'), rulerActions);
  $('easing').replaceChildren(
    ...anim.EASINGS.map((name) => {
      const option = document.createElement('option');
      option.value = name;
      option.textContent = anim.EASING_LABELS[name];
      return option;
    }),
  );
  $('play').addEventListener('click', () => (editor.playing ? pause() : play()));
  $('key-pose').addEventListener('click', () => key());
  $('key-pins').addEventListener('click', () => key([...editor.selection]));
  $('duplicate-key').addEventListener('click', duplicateKey);
  $('delete-key').addEventListener('click', deleteKey);
  $('easing').addEventListener('change', (event) => {
    const k = editor.selectedKey;
    if (k === null || !keyframes()[k]) return;
    edit((scene) => (scene.animation.keyframes[k].easing = event.target.value));
  });
  $('fps').addEventListener('change', (event) => {
    const rate = Number(event.target.value);
    if (!(rate > 0 && rate <= anim.MAX_FPS)) {
      showError(`frames per second: ${event.target.value} is not a number above 0 and at most ${anim.MAX_FPS}`);
      drawTimeline();
      return;
    }
    if (editor.scene.animation) edit((scene) => (scene.animation.fps = rate));
  });
  $('onion').addEventListener('change', updateOnion);

  $('open-file').addEventListener('change', (event) => {
    const file = event.target.files[0];
    event.target.value = '';
    if (file) open(file);
  });
  const stage = $('stage');
  stage.addEventListener('dragover', (event) => {
    event.preventDefault();
    stage.classList.add('dragging-file');
  });
  stage.addEventListener('dragleave', () => stage.classList.remove('dragging-file'));
  stage.addEventListener('drop', (event) => {
    event.preventDefault();
    stage.classList.remove('dragging-file');
    const file = event.dataTransfer?.files?.[0];
    if (file) open(file);
  });

  $('export-svg').addEventListener('click', exportSvg);
  $('save-scene').addEventListener('click', saveScene);
  $('export-lottie').addEventListener('click', exportLottie);
  $('progress-stop').addEventListener('click', () => {
    if (!editor.job) return;
    $('progress-stop').hidden = true;
    progress('stopping the training', null, false);
    api.stopJob(editor.job).catch(showError);
  });
  $('undo').addEventListener('click', undo);
  $('redo').addEventListener('click', redo);
  $('delete-handle').addEventListener('click', deleteHandles);
  $('reset-pose').addEventListener('click', () =>
    edit((scene) => (scene.pose = scene.pose.map(() => [...affine.IDENTITY]))),
  );
  $('family').addEventListener('change', (event) =>
    edit((scene) => {
      const family = event.target.value;
      if (family === 'shepard') {
        scene.weights = { family, exponent: 2 };
      } else if (family in DEFOP_ENERGIES) {
        const samples = Number.parseInt($('defop-samples').value, 10);
        scene.weights = { family, samples: Number.isInteger(samples) ? samples : DEFAULT_DEFOP_SAMPLES };
        scene.flexible = false; // does not apply (syncControls disables it)
        // The operator moves pins, it does not turn or scale them: set turns and scales aside
        // here, visibly and undoably, rather than keep them unseen for another family.
        if (translationsOnly(scene)) {
          showNotice('the operator moves pins only: their turns and scales were set aside (Ctrl+Z brings them back)');
        }
      } else {
        scene.weights = { family };
      }
    }),
  );
  $('defop-samples').addEventListener('change', (event) => {
    const samples = Number(event.target.value);
    if (!Number.isInteger(samples) || samples < 1 || samples > MAX_DEFOP_SAMPLES) {
      showError(`training samples: ${event.target.value} is not a whole number from 1 to ${MAX_DEFOP_SAMPLES}`);
      syncControls();
      return;
    }
    if (isDefop(editor.scene)) edit((scene) => (scene.weights = { ...scene.weights, samples }));
  });
  $('margin').addEventListener('change', (event) => {
    const percent = Number(event.target.value);
    if (event.target.value.trim() === '' || !(percent >= 0 && percent <= 100 * MAX_MARGIN)) {
      showError(`margin ${event.target.value} %: expected a number from 0 to ${100 * MAX_MARGIN}`);
      syncControls();
      return;
    }
    if (percent / 100 === (editor.scene.margin ?? DEFAULT_MARGIN)) return; // nothing to undo
    edit((scene) => (scene.margin = percent / 100));
  });
  $('flexible').addEventListener('change', (event) => edit((scene) => (scene.flexible = event.target.checked)));
  $('adaptive').addEventListener('change', (event) => setAdaptive(event.target.checked));
  $('adaptive-tolerance').addEventListener('change', (event) => {
    const percent = Number(event.target.value);
    if (!(percent > 0 && percent <= 10)) {
      showError(`add control points within ${event.target.value} %: expected a number above 0, at most 10`);
      event.target.value = String(editor.adaptive.tolerance * 100);
      return;
    }
    editor.adaptive.tolerance = percent / 100;
    refineForPoses();
  });
  $('show-junctions').addEventListener('change', drawOverlay);
  $('show-weights').addEventListener('change', updateWeights);
  $('show-mesh').addEventListener('change', updateMesh);
  $('error').addEventListener('click', clearError);
  $('notice').addEventListener('click', () => showNotice(''));
  $('fit').addEventListener('click', () => {
    if (!editor.view) return;
    editor.view.fit(posedHandles(editor.scene));
    drawOverlay();
  });

  window.addEventListener('resize', () => editor.view && drawOverlay());
  window.addEventListener('keydown', (event) => {
    // Shortcuts work whatever has the focus (a checkbox, a menu, a button), except where keys
    // type text.
    if (isTextField(event.target)) return;
    const key = event.key.toLowerCase();
    if ((event.ctrlKey || event.metaKey) && key === 'z') {
      event.preventDefault();
      event.shiftKey ? redo() : undo();
    } else if ((event.ctrlKey || event.metaKey) && key === 'y') {
      event.preventDefault();
      redo();
    } else if (key === 'delete' || key === 'backspace') {
      event.preventDefault();
      if (editor.selection.length) deleteHandles();
      else if (editor.selectedKey !== null) deleteKey();
    } else if (key === 'escape') {
      deselect();
    } else if ((event.ctrlKey || event.metaKey) && key === 'a') {
      event.preventDefault();
      const all = editor.scene.handles.map((_, i) => i);
      gestureActions.select(all, all.length ? all[all.length - 1] : null);
    } else if (key === 'k' && !event.ctrlKey && !event.metaKey) {
      keyShortcut();
    } else if ((key === ',' || key === '.') && !event.ctrlKey && !event.metaKey) {
      seek(Math.max(0, Math.round(editor.time * fps() + (key === '.' ? 1 : -1)) / fps()));
    }
  });
}

/** Whether keys pressed in `target` type text (so shortcuts leave them alone). */
function isTextField(target) {
  if (target instanceof HTMLTextAreaElement || target?.isContentEditable) return true;
  if (!(target instanceof HTMLInputElement)) return false;
  return ['text', 'search', 'email', 'url', 'password', 'tel', 'number'].includes(target.type);
}

function deselect() {
  if (editor.selected === null && !editor.selection.length) return;
  editor.selected = null;
  editor.selection = [];
  drawOverlay();
  syncControls();
  drawTimeline();
  updateWeights();
}

async function boot() {
  wire();
  if (!littleEndian()) {
    showError('this browser stores numbers big-endian; the editor reads little-endian data');
    return;
  }
  // Read before the first autosave replaces it.
  const session = savedSession();
  try {
    show(await api.initialDocument());
  } catch (e) {
    showError(e);
  }
  if (session && editor.info) {
    editor.restoring = true;
    try {
      await recoverSession(session);
    } catch (e) {
      showNotice(`the previous session could not be restored: ${e.message ?? e}`);
    } finally {
      editor.restoring = false;
      autosave();
    }
  }
  document.body.dataset.booted = '1';
}

boot();
