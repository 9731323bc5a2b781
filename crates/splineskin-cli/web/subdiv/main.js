// The Catmull–Clark page: open an OBJ cage, see its limit surface shaded, turn it about; click
// the surface to add point handles, Alt-drag for bones, move and turn them with the mouse or
// the gizmo, and the cage is fitted so that its limit surface follows the skinned one; key
// poses on the timeline and play them; every edit is autosaved. The page's state is the one
// `page` object below; the modules it uses hold none.
//
//   surface.js       the limit surface from cage positions (stencils), normals, bounds
//   rig.js           the fitted cage from the rig's factors and the handles' maps; skinning; distances
//   handles.js       point handles and bones, in the scene's order
//   camera.js        the orbit camera and its matrices
//   pick.js          what the pointer is over
//   gizmo.js         the selected handle's arrows and rings
//   gestures.js      what the pointer does on the view
//   keys.js          keyframes of the handles' poses and their interpolation
//   timeline-row.js  the ruler, the keys' buttons, playback
//   exports.js       the scene file, the server's exports, downloads
//   autosave.js      the session in IndexedDB
//   server.js        requests to the server (or the WebAssembly worker of a static build)
//   gl-view.js       the WebGL2 drawing
//   ../history.js    undo and redo (the 2D editor's, on this page's snapshots)

import { eye, fitCamera, pixelSize, viewProjection } from './camera.js';
import { autosave, savedSession } from './autosave.js';
import { exportAs } from './exports.js';
import { installGestures } from './gestures.js';
import { GIZMO_PIXELS, GIZMO_VERTICES, gizmoLines } from './gizmo.js';
import { createView } from './gl-view.js';
import { boneCount, boneHandle, boneSegments, pivots, pointHandle, sceneHandles, withHandle } from './handles.js';
import { History } from '../history.js';
import { project } from './pick.js';
import { IDENTITY_ROTATION, distances, fitCage, handleMap, skin, weightColumn } from './rig.js';
import { post } from './server.js';
import { bounds, tessellate, vertexNormals } from './surface.js';
import { installTimeline } from './timeline-row.js';

/** The distance to the skinned surface painted full red, a fraction of the cage's diagonal. */
const DISTANCE_SCALE = 0.01;

const page = {
  /** The opened cage ([`CageWire`] of POST /api/subdiv/open) and its OBJ text, or null. */
  cage: null,
  objText: '',
  /** Surface positions and normals (f32, drawn) and the fitted cage (f64). */
  positions: null,
  normals: null,
  fitted: null,
  camera: null,
  showCage: false,
  paint: false,
  /** `ours` (the fitted cage) or `naive` (the cage's vertices skinned, then subdivided). */
  method: 'ours',
  /** Colour the surface by its distance to the skinned surface. */
  showDistance: false,
  /** The rest surface (f64) and the skinned surface, for `showDistance`. */
  restSurface: null,
  skinned: null,
  /** The values painted on the surface (weights or distances) and what they are of. */
  painted: null,
  paintedFor: null,
  /** The last frame's distance to the skinned surface: `{max, rms}` in the cage's units. */
  error: null,
  /** Keyframes (keys.js), time order; the playhead (s); the selected key; the playback's frame request. */
  keys: [],
  time: 0,
  selectedKey: null,
  playing: null,
  /** Undo and redo of the edits: snapshots of the handles, keys, selection and family. */
  history: new History(),
  family: 'shepard',
  /** Point handles, then bones (handles.js). */
  handles: [],
  /** The bones' segments now (six numbers each), drawn. */
  boneLines: new Float32Array(0),
  /** What dragging a handle's dot does: `move` it in the view's plane or `turn` it about the view's axis. */
  mode: 'move',
  selected: null,
  /** The selected handle's gizmo (gizmoLines) and its arrows' world length, or null. */
  gizmo: null,
  gizmoSize: 0,
  /** The rig of the handles ([`RigWire`] of POST /api/subdiv/rig), or null; `asked` counts requests. */
  rig: null,
  asked: 0,
  /** The press in progress (gestures.js), or null. */
  drag: null,
  /** Milliseconds of the last frame's cage product and tessellation. */
  frameMs: 0,
  view: null,
};

const status = document.getElementById('status');
const canvas = document.getElementById('view');

function say(message, { error = false } = {}) {
  status.textContent = message;
  status.classList.toggle('error', error);
}

try {
  page.view = createView(canvas);
} catch (error) {
  say(error.message, { error: true });
}

/** Opens the OBJ cage `text` named `name`: the server samples its limit surface. */
async function openCage(name, text) {
  say(`${name}: opening…`);
  const cage = await post('/api/subdiv/open', text, { 'x-file-name': encodeURIComponent(name) });
  Object.assign(page, { cage, objText: text, handles: [], selected: null, rig: null, keys: [], time: 0, selectedKey: null });
  page.history.clear();
  page.positions = new Float32Array(3 * cage.surface.n_vertices);
  page.normals = new Float32Array(3 * cage.surface.n_vertices);
  page.fitted = Float64Array.from(cage.positions);
  page.restSurface = tessellate(cage.surface, cage.positions, new Float64Array(3 * cage.surface.n_vertices));
  page.skinned = new Float64Array(3 * cage.surface.n_vertices);
  page.painted = new Float32Array(cage.surface.n_vertices);
  page.paintedFor = null;
  page.view.setMesh(cage.surface.triangles, cage.edges);
  page.view.setHandles([]);
  update();
  page.camera = fitCamera(bounds(page.positions));
  draw();
  timeline.show();
  const [creases, corners, holes] = cage.n_tags;
  say(`${cage.name}: ${cage.positions.length / 3} vertices, ${cage.face_sizes.length} faces, ` +
    `${creases} creases, ${corners} corners, ${holes} holes; limit surface level ${cage.surface.level}, ` +
    `${cage.surface.triangles.length / 3} triangles, tessellated in ${page.frameMs.toFixed(1)} ms. ` +
    'Click the surface to add handles.');
}

/** Asks for the rig of the current handles; a later request supersedes it. */
async function rig() {
  const asked = ++page.asked;
  page.rig = null;
  const what = describeHandles();
  say(`${what}: computing ${page.family} weights and the rig…`);
  const scene = { ...sceneHandles(page.handles), weights: { family: page.family } };
  const body = JSON.stringify({ name: page.cage.name, obj: page.objText, level: page.cage.surface.level, scene });
  const answer = await post('/api/subdiv/rig', body, { 'content-type': 'application/json' });
  if (asked !== page.asked) return;
  page.rig = answer;
  update();
  draw();
  say(`${what}, ${page.family} weights: weights and rig in ${answer.seconds.toFixed(2)} s; ` +
    'drag a handle, or its gizmo, to move or turn it.');
}

/** "3 handles and 1 bone". */
function describeHandles() {
  const bones = boneCount(page.handles);
  const points = page.handles.length - bones;
  const plural = (n, word) => `${n} ${word}${n === 1 ? '' : 's'}`;
  return bones ? `${plural(points, 'handle')} and ${plural(bones, 'bone')}` : plural(points, 'handle');
}

/** The cage (ours or naive) and its surface for the handles' poses, uploaded. */
function update() {
  const start = performance.now();
  const transforms = page.handles.map(handleMap);
  if (!page.rig) {
    page.fitted.set(page.cage.positions);
  } else if (page.method === 'naive') {
    skin(page.cage.positions, page.rig.cage_weights, transforms, page.fitted);
  } else {
    fitCage(page.rig, transforms, page.fitted);
  }
  const surface = page.cage.surface;
  tessellate(surface, page.fitted, page.positions);
  vertexNormals(page.positions, surface.triangles, page.normals);
  page.frameMs = performance.now() - start;
  page.view.setPositions(page.positions, page.normals, page.fitted);
  page.view.setHandles(pivots(page.handles));
  const bones = boneCount(page.handles);
  if (page.boneLines.length !== 6 * bones) page.boneLines = new Float32Array(6 * bones);
  page.view.setBones(boneSegments(page.handles, page.boneLines));
  paint(transforms);
}

/**
 * The values painted on the surface, uploaded: the distance to the skinned surface (every
 * frame), or the selected handle's weight (only when the rig or the selection changed).
 */
function paint(transforms) {
  page.error = null;
  if (page.rig && page.showDistance) {
    skin(page.restSurface, page.rig.surface_weights, transforms, page.skinned);
    page.error = distances(page.positions, page.skinned, page.painted);
    const scale = page.cage.diagonal * DISTANCE_SCALE;
    for (let m = 0; m < page.painted.length; m++) page.painted[m] /= scale;
    page.paintedFor = 'distance';
  } else if (page.rig && page.selected != null) {
    const key = `weights ${page.asked} ${page.selected}`;
    if (page.paintedFor === key) return;
    weightColumn(page.rig.surface_weights, page.rig.n_handles, page.selected, page.painted);
    page.paintedFor = key;
  } else {
    return;
  }
  page.view.setWeights(page.painted);
}

/** What undo restores: the handles, keys, selection and weight family. */
function snapshot() {
  return { handles: page.handles, keys: page.keys, selected: page.selected, family: page.family };
}

/** Records the state before an edit. */
function beforeEdit() {
  page.history.record(snapshot());
}

/** After an edit: said, and the session autosaved. */
function edited(message) {
  if (message) say(message);
  autosave(page, (text) => say(text, { error: true }));
}

/** Whether `a` and `b` are the same handles where they were placed (the same rig). */
function sameRest(a, b) {
  return a.length === b.length && a.every((h, i) => h.kind === b[i].kind && h.rest.every((v, k) => v === b[i].rest[k]) &&
    (h.end ?? []).every((v, k) => v === b[i].end[k]));
}

/** Goes back (`undo`) or forward (`redo`) one edit; a new set of handles or family asks for its rig. */
function travel(direction) {
  const target = direction === 'undo' ? page.history.undo(snapshot()) : page.history.redo(snapshot());
  if (!target || !page.cage) return;
  const sameRig = target.family === page.family && sameRest(target.handles, page.handles);
  Object.assign(page, structuredClone(target));
  page.selectedKey = null;
  document.getElementById('family').value = page.family;
  timeline.show();
  if (!sameRig) page.rig = null;
  frame();
  if (!sameRig && page.handles.length > 0) rig().catch((e) => say(e.message, { error: true }));
  edited(`${direction === 'undo' ? 'undone' : 'redone'}: ${describeHandles()}, ${page.keys.length} keys`);
}

/** Whether a handle is away from where it was placed. */
function posed(h) {
  return h.offset.some((d) => d !== 0) || h.rotation.some((v, k) => v !== IDENTITY_ROTATION[k]);
}

function matrix() {
  return viewProjection(page.camera, canvas.clientWidth / Math.max(1, canvas.clientHeight));
}

/** Draws the view; the selected handle's gizmo follows it. */
function draw() {
  if (!page.cage) return;
  placeGizmo();
  const paint = page.rig != null && (page.showDistance || (page.paint && page.selected != null));
  const nPoints = page.handles.length - boneCount(page.handles);
  const selectedBone = page.selected != null && page.selected >= nPoints ? page.selected - nPoints : null;
  page.view.draw(matrix(), eye(page.camera), { showCage: page.showCage, paint, selected: page.selected, selectedBone });
}

/** The gizmo at the selected handle (GIZMO_PIXELS long on screen), or none. */
function placeGizmo() {
  const h = page.selected != null && page.rig ? page.handles[page.selected] : null;
  if (!h) {
    page.gizmo = null;
    page.view.setGizmo(null);
    return;
  }
  const centre = h.rest.map((r, k) => r + h.offset[k]);
  page.gizmoSize = GIZMO_PIXELS * pixelSize(page.camera, centre, canvas.clientHeight);
  page.gizmo = gizmoLines(centre, page.gizmoSize, page.gizmo ?? new Float32Array(3 * GIZMO_VERTICES));
  page.view.setGizmo(page.gizmo);
}

/** The cage and surface for the handles now, drawn. */
function frame() {
  update();
  draw();
}

/** The distance to the skinned surface, as the status says it, when it is shown. */
function errorNote() {
  if (!page.error) return '';
  const percent = (d) => ((100 * d) / page.cage.diagonal).toFixed(3);
  return `; ${page.method} to the skinned surface: max ${percent(page.error.max)} %, RMS ${percent(page.error.rms)} % of the diagonal (red: 1 %)`;
}

/** Adds `h` (a point handle or a bone) at rest, selected; keys start again; the rig is asked for. */
function addHandle(h) {
  if (page.handles.some(posed)) {
    say('Handles are added at rest: press Rest first.', { error: true });
    return;
  }
  beforeEdit();
  const [handles, at] = withHandle(page.handles, h);
  page.handles = handles;
  // Keys hold every handle's pose: a new handle starts a new animation.
  page.keys = [];
  page.selectedKey = null;
  timeline.show();
  page.selected = at;
  page.rig = null;
  frame();
  rig().then(() => edited()).catch((e) => say(e.message, { error: true }));
}

installGestures(canvas, page, {
  matrix,
  size: () => ({ width: canvas.clientWidth, height: canvas.clientHeight }),
  frame,
  draw,
  beforeEdit,
  say,
  select(i) {
    page.selected = i;
    frame();
  },
  addPoint: (p) => addHandle(pointHandle(p)),
  addBone(a, b) {
    if (Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) < 1e-6 * page.cage.diagonal) {
      say('A bone needs two distinct ends: drag from one point of the surface to another.', { error: true });
      return;
    }
    addHandle(boneHandle(a, b));
  },
  edited: (what) => edited(`${what}; frame (cage product and surface) ${page.frameMs.toFixed(1)} ms${errorNote()}`),
});

const timeline = installTimeline(page, { frame, beforeEdit, edited, say });

window.addEventListener('resize', draw);

const openFile = (file) =>
  file.text().then((text) => openCage(file.name, text)).then(() => edited()).catch((e) => say(`${file.name}: ${e.message}`, { error: true }));

document.getElementById('open').addEventListener('change', (event) => {
  const [file] = event.target.files;
  // Emptied, so that choosing the same file again opens it again.
  event.target.value = '';
  if (file) openFile(file);
});

const stage = document.getElementById('stage');
stage.addEventListener('dragover', (event) => event.preventDefault());
stage.addEventListener('drop', (event) => {
  event.preventDefault();
  const [file] = event.dataTransfer.files;
  if (file) openFile(file);
});

document.getElementById('show-cage').addEventListener('change', (event) => {
  page.showCage = event.target.checked;
  draw();
});

document.getElementById('paint').addEventListener('change', (event) => {
  page.paint = event.target.checked;
  frame();
});

document.getElementById('mode').addEventListener('change', (event) => {
  page.mode = event.target.value;
});

document.getElementById('method').addEventListener('change', (event) => {
  page.method = event.target.value;
  frame();
  if (page.rig) say(`showing ${page.method}${errorNote()}`);
  edited();
});

document.getElementById('distance').addEventListener('change', (event) => {
  page.showDistance = event.target.checked;
  frame();
  if (page.rig) say(`showing ${page.method}${errorNote()}`);
});

document.getElementById('family').addEventListener('change', (event) => {
  beforeEdit();
  page.family = event.target.value;
  event.target.blur();
  if (page.handles.length > 0) rig().then(() => edited()).catch((e) => say(e.message, { error: true }));
});

document.getElementById('rest').addEventListener('click', () => {
  if (!page.cage) return;
  beforeEdit();
  page.handles = page.handles.map((h) => ({ ...h, offset: [0, 0, 0], rotation: [...IDENTITY_ROTATION] }));
  frame();
  edited('every handle at rest');
});

document.getElementById('export').addEventListener('change', (event) => {
  const format = event.target.value;
  event.target.value = '';
  if (format) exportAs(page, format, say).catch((e) => say(e.message, { error: true }));
});

document.getElementById('undo').addEventListener('click', () => travel('undo'));
document.getElementById('redo').addEventListener('click', () => travel('redo'));
window.addEventListener('keydown', (event) => {
  if (!(event.ctrlKey || event.metaKey) || event.key.toLowerCase() !== 'z') return;
  if (event.target instanceof HTMLInputElement) return;
  event.preventDefault();
  travel(event.shiftKey ? 'redo' : 'undo');
});

document.getElementById('reset-view').addEventListener('click', () => {
  if (!page.cage) return;
  page.camera = fitCamera(bounds(page.positions));
  draw();
});

/** Offers back the autosaved session, if any: the cage opened again, its handles, keys and family. */
async function restore() {
  const saved = await savedSession();
  if (!saved || page.cage) return;
  try {
    await openCage(saved.name, saved.obj);
    Object.assign(page, {
      handles: saved.handles,
      keys: saved.keys,
      family: saved.family,
      method: saved.method,
      selected: saved.selected,
      time: saved.time,
    });
    document.getElementById('family').value = page.family;
    document.getElementById('method').value = page.method;
    timeline.show();
    frame();
    if (page.handles.length > 0) await rig();
    say(`${saved.name}: the session autosaved ${new Date(saved.savedAt).toLocaleString()} is back (${describeHandles()}, ${page.keys.length} keys)`);
  } catch (e) {
    say(`the autosaved session of ${saved.name} could not be restored: ${e.message}`, { error: true });
  }
  document.body.dataset.restored = '1';
}
restore();

/** What the page shows, for its tests: handles, the selection, whether the rig is ready, the last frame's time. */
window.subdivPageState = () => ({
  handles: page.handles.map((h) => ({ kind: h.kind, rest: [...h.rest], end: h.end && [...h.end], offset: [...h.offset], rotation: [...h.rotation] })),
  selected: page.selected,
  rigReady: page.rig != null,
  frameMs: page.frameMs,
  method: page.method,
  family: page.family,
  keys: page.keys.map((k) => k.time),
  easings: page.keys.map((k) => k.easing),
  time: page.time,
  playing: page.playing != null,
  error: page.error && { ...page.error },
  fitted: page.fitted ? Array.from(page.fitted) : null,
  gizmoSize: page.gizmoSize,
});

/** Where the world point `p` is drawn, CSS pixels in the canvas: `[x, y, depth]`, for the page's tests. */
window.subdivProject = (p) => project(matrix(), p, canvas.clientWidth, canvas.clientHeight);
