// The editor's state, in one place: `editor` holds what the page shows and edits, every module
// reads it and changes it in the open (no state kept in the DOM: the `data-*` attributes on
// <body> mirror some of it for the browser tests, and are never read back). Queries of the state
// are here too, and the two events by which a lower module asks the page for more than it can
// do itself (`notify('scene-changed')`, `notify('rig-lost')`, answered in main.js).
//
// `editor.scene` is what a scene file holds and the undo history snapshots (rest handles, one map
// per handle, weight family, junction overrides, flexible G¹, the timeline's keyframes as
// `animation`); the rig is precomputed for the scene's rest part (`rigKey`) and reused while only
// the pose changes. `editor.time` is the timeline's shown time.

import {
  DEFAULT_DEFOP_SAMPLES,
  DEFAULT_FPS,
  DEFAULT_MARGIN,
  DEFOP_FAMILIES,
  MAX_DEFOP_SAMPLES,
  MAX_MARGIN,
  MESH_FAMILIES as MESH_FAMILY_NAMES,
} from './constants.js';
import { History } from './history.js';

// Limits shared with Rust (constants.js, generated): operator samples, the domain's margin.
export { DEFAULT_DEFOP_SAMPLES, DEFAULT_MARGIN, MAX_DEFOP_SAMPLES, MAX_MARGIN };

/** How the page names each operator family's ground truth. */
const ENERGY_LABELS = { 'defop-arap': 'ARAP', 'defop-sarap': 'symmetric ARAP' };

/** The operator "families" of the weights menu (Rust's names), each its ground truth's label. */
export const DEFOP_ENERGIES = Object.fromEntries(DEFOP_FAMILIES.map((family) => [family, ENERGY_LABELS[family] ?? family]));

/** The weight families solved on a triangulated domain: seconds on big drawings. */
export const MESH_FAMILIES = new Set(MESH_FAMILY_NAMES);

export const editor = {
  /** The opened drawing as the server describes it (DocumentInfo), and its view. */
  info: null,
  view: null,
  /** The text of the file the page opened (null: the server's own drawing). */
  source: null,
  scene: null,
  rig: null,
  rigKey: null,
  /**
   * Where the rig stands: 'none' (no handles), 'computing', 'preview' (the stand-in),
   * 'ready', 'stopped' (a training stopped by the user) or 'error'; set by setRigState.
   */
  rigState: 'none',
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
  /** The scene as it was when a keyframe drag on the ruler started (one undo step), or null. */
  keyDragBefore: null,
  /** Chain points of the onion skin's two outlines. */
  onionPoints: [null, null],
  history: new History(),
  /** Milliseconds of each frame drawn while dragging (product + path data). */
  frameTimes: [],
  /** Milliseconds of the product alone, same frames. */
  productTimes: [],
  /** Whether a frame is asked for and not yet drawn (scheduleFrame). */
  frameRequested: false,
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
  /** What the weight field shows (rig, handle and pose), or null. */
  weightsShown: null,
  /** Whether the fold rings of the last viewBox check are drawn. */
  foldsShown: false,
  /** Whether the notice about a drawing too big to redraw whole in a drag's frame was shown. */
  partialFramesSaid: false,
  /** The rig's mesh as last fetched: { rig (id), mesh (api.mesh), edges } or null. */
  shownMesh: null,
  /** The rig whose mesh is being fetched ({ rig }), or null. */
  meshRequest: null,
  /** The overlays and playback options the user turned on (the checkboxes of the page). */
  shown: { junctions: false, weights: false, mesh: false, onion: false, folds: true },
  /** Whether playing starts again at the end. */
  loop: true,
  /**
   * Adaptive control points: whether they are on, the tolerance (fraction of the diagonal),
   * and while the shown drawing is a refined one, the drawing as opened (`original`: its info,
   * source, rig and rig key) with `toOriginal`, per path and joint of the shown drawing, the
   * opened drawing's joint (-1: inserted).
   */
  adaptive: { on: false, tolerance: 1e-3, original: null, toOriginal: null, busy: false, pending: false, answers: [] },
  /** Whether handles only move (an operator's family: no rotate or scale). */
  translateOnly: () => editor.scene !== null && isDefop(editor.scene),
  /** The operator follower (frames.js), for the tests. */
  follower: null,
  /** The last Lottie export's report, for the tests. */
  lottieReport: null,
  /** The pending autosave's timer, and whether a saved session is being put back (no saving). */
  autosaveTimer: null,
  restoring: false,
};
/** Sets where the rig stands (editor.rigState), mirrored in `body[data-rig]` for the tests. */
export function setRigState(state) {
  editor.rigState = state;
  document.body.dataset.rig = state;
}

/** The page's answers to each event, in the order they were given. */
const listeners = new Map();

/**
 * Answers event `name` with `answer` from now on: 'scene-changed' (the scene was edited: redraw,
 * and precompute if its rest part changed) or 'rig-lost' (the backend no longer has the rig:
 * build it again).
 */
export function listen(name, answer) {
  listeners.set(name, [...(listeners.get(name) ?? []), answer]);
}

/** Tells the page that `name` happened (see listen). */
export function notify(name) {
  for (const answer of listeners.get(name) ?? []) answer();
}

/** Whether the scene's "family" is a trained deformation operator. */
export function isDefop(scene) {
  return scene.weights.family in DEFOP_ENERGIES;
}

/** What the rig depends on (everything but the pose). */
export function rigKeyOf(scene) {
  return JSON.stringify([scene.handles, scene.weights, scene.junctions, scene.flexible, scene.margin ?? null]);
}

/** Whether the rig matches the scene's rest part. */
export function rigReady() {
  return editor.rig !== null && editor.rigKey === rigKeyOf(editor.scene);
}

/** The scene's keyframes (empty without an animation). */
export function keyframes() {
  return editor.scene?.animation?.keyframes ?? [];
}

/** The animation's frames per second (its own, or the default). */
export function fps() {
  return editor.scene?.animation?.fps ?? DEFAULT_FPS;
}

/** The kind of junction `j` ({ path, joint }): the scene's override, or as classified. */
export function junctionKind(j) {
  const o = editor.scene.junctions.find((x) => x.path === j.path && x.joint === j.joint);
  return o ? o.kind : editor.info.paths[j.path].joints[j.joint];
}

/** `junctions` moved by `map` (per path, joint → joint, or -1: dropped). */
export function movedJunctions(junctions, map) {
  return junctions.flatMap((j) => {
    const to = map[j.path]?.[j.joint] ?? -1;
    return to < 0 ? [] : [{ ...j, joint: to }];
  });
}

/** The scene as the drawing as opened has it (junction kinds on its own joints). */
export function sceneOfOriginal() {
  const map = editor.adaptive.toOriginal;
  return map ? { ...editor.scene, junctions: movedJunctions(editor.scene.junctions, map) } : editor.scene;
}

/** The opened file's name without its folder. */
export function shortName() {
  return editor.info.name.split(/[\\/]/).pop() || editor.info.name;
}

/** The opened file's name without its folder, its extension or " (bundled)": exports' stem. */
export function baseName() {
  const name = editor.info.name.split(/[\\/]/).pop() || 'drawing';
  return name.replace(/\.(svg|json)$/i, '').replace(/\s*\(bundled\)$/, '');
}
