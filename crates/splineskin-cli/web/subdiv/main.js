// The Catmull–Clark page: open an OBJ cage, see its limit surface shaded, turn it about; click
// the surface to add point handles, drag a handle to move it, and the cage is fitted so that
// its limit surface follows the skinned one. The page's state is the one `page` object below;
// the modules it uses hold none.
//
//   surface.js   the limit surface from cage positions (stencils), normals, bounds
//   rig.js       the fitted cage from the rig's factors and the handles' maps; skinning; distances
//   camera.js    the orbit camera and its matrices
//   pick.js      what the pointer is over
//   keys.js      keyframes of the handles' poses and their interpolation
//   exports.js   the scene file, the server's exports, downloads
//   server.js    requests to the server
//   gl-view.js   the WebGL2 drawing
//   ../history.js  undo and redo (the 2D editor's, on this page's snapshots)

import { dragInView, eye, fitCamera, orbit, pan, viewAxes, viewProjection, zoom } from './camera.js';
import { exportAs } from './exports.js';
import { createView } from './gl-view.js';
import { History } from '../history.js';
import { keyOf, poseAt, withKey } from './keys.js';
import { pickPoint, pickSurface, project } from './pick.js';
import { IDENTITY_ROTATION, distances, fitCage, handleMap, skin, turned, weightColumn } from './rig.js';
import { post } from './server.js';
import { bounds, tessellate, vertexNormals } from './surface.js';

/** Pixels a press may move and still be a click. */
const CLICK_SLOP = 4;
/** Pixels from a handle's dot that pick it. */
const HANDLE_RADIUS = 10;
/** Radians a handle turns per pixel dragged sideways. */
const TURN_PER_PIXEL = 0.01;
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
  /** Keyframes (keys.js), time order; the playback's animation frame request, or null. */
  keys: [],
  playing: null,
  /** Undo and redo of the edits: snapshots of the handles, keys, selection and family. */
  history: new History(),
  family: 'shepard',
  /** Point handles: `{ rest: [x, y, z], offset: [dx, dy, dz], rotation: 3 × 3 rows flat }`. */
  handles: [],
  /** What dragging a handle does: `move` it in the view's plane or `turn` it about the view's axis. */
  mode: 'move',
  selected: null,
  /** The rig of the handles ([`RigWire`] of POST /api/subdiv/rig), or null; `asked` counts requests. */
  rig: null,
  asked: 0,
  /** The press in progress: `{x, y, startX, startY, handle, panning}`, or null. */
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

/** Opens `file` (an OBJ cage): the server samples its limit surface. */
async function open(file) {
  say(`${file.name}: opening…`);
  const text = await file.text();
  const cage = await post('/api/subdiv/open', text, { 'x-file-name': encodeURIComponent(file.name) });
  Object.assign(page, { cage, objText: text, handles: [], selected: null, rig: null });
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
  say(`${page.handles.length} handles: computing ${page.family} weights and the rig…`);
  const scene = {
    handles: page.handles.map((h) => ({ position: h.rest })),
    weights: { family: page.family },
  };
  const body = JSON.stringify({ name: page.cage.name, obj: page.objText, level: page.cage.surface.level, scene });
  const answer = await post('/api/subdiv/rig', body, { 'content-type': 'application/json' });
  if (asked !== page.asked) return;
  page.rig = answer;
  update();
  draw();
  say(`${page.handles.length} handles, ${page.family} weights: weights and rig in ${answer.seconds.toFixed(2)} s; ` +
    'drag a handle to move it.');
}

/** The cage (ours or naive) and its surface for the handles' offsets, uploaded. */
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
  page.view.setHandles(handlePositions());
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

/** Goes back (`undo`) or forward (`redo`) one edit; a new set of handles or family asks for its rig. */
function travel(direction) {
  const target = direction === 'undo' ? page.history.undo(snapshot()) : page.history.redo(snapshot());
  if (!target || !page.cage) return;
  const sameRig =
    target.family === page.family &&
    target.handles.length === page.handles.length &&
    target.handles.every((h, i) => h.rest.every((v, k) => v === page.handles[i].rest[k]));
  Object.assign(page, structuredClone(target));
  document.getElementById('family').value = page.family;
  showKeys();
  if (sameRig && page.rig) {
    update();
    draw();
  } else if (page.handles.length > 0) {
    // The old rig has other handles: the cage stays at rest until the new one arrives.
    page.rig = null;
    update();
    draw();
    rig().catch((e) => say(e.message, { error: true }));
  } else {
    page.rig = null;
    update();
    draw();
  }
  say(`${direction === 'undo' ? 'undone' : 'redone'}: ${page.handles.length} handles, ${page.keys.length} keys`);
}

/** Whether a handle is away from where it was placed. */
function posed(h) {
  return h.offset.some((d) => d !== 0) || h.rotation.some((v, k) => v !== IDENTITY_ROTATION[k]);
}

/** Where the handles are now (rest plus offset), x, y, z flat. */
function handlePositions() {
  return page.handles.flatMap((h) => h.rest.map((r, k) => r + h.offset[k]));
}

function matrix() {
  return viewProjection(page.camera, canvas.clientWidth / Math.max(1, canvas.clientHeight));
}

function draw() {
  if (!page.cage) return;
  const paint = page.rig != null && (page.showDistance || (page.paint && page.selected != null));
  page.view.draw(matrix(), eye(page.camera), { showCage: page.showCage, paint, selected: page.selected });
}

/** The distance to the skinned surface, as the status says it, when it is shown. */
function errorNote() {
  if (!page.error) return '';
  const percent = (d) => ((100 * d) / page.cage.diagonal).toFixed(3);
  return `; ${page.method} to the skinned surface: max ${percent(page.error.max)} %, RMS ${percent(page.error.rms)} % of the diagonal (red: 1 %)`;
}

/** A click at `at` (CSS pixels in the canvas): picks a handle, or adds one where the surface is. */
function click(at) {
  const size = { width: canvas.clientWidth, height: canvas.clientHeight };
  const hit = pickPoint(matrix(), handlePositions(), at, { ...size, radius: HANDLE_RADIUS });
  if (hit != null) {
    page.selected = hit;
    update();
    draw();
    return;
  }
  const point = pickSurface(matrix(), page.positions, page.cage.surface.triangles, at, size);
  if (!point) return;
  if (page.handles.some(posed)) {
    say('Handles are added at rest: press Rest first.', { error: true });
    return;
  }
  beforeEdit();
  page.handles = [...page.handles, { rest: point, offset: [0, 0, 0], rotation: [...IDENTITY_ROTATION] }];
  // Keys hold every handle's pose: a new handle starts a new animation.
  page.keys = [];
  showKeys();
  page.selected = page.handles.length - 1;
  page.rig = null;
  update();
  draw();
  rig().catch((e) => say(e.message, { error: true }));
}

const local = (event) => {
  const r = canvas.getBoundingClientRect();
  return [event.clientX - r.left, event.clientY - r.top];
};

canvas.addEventListener('pointerdown', (event) => {
  if (!page.cage) return;
  canvas.setPointerCapture(event.pointerId);
  const at = local(event);
  const size = { width: canvas.clientWidth, height: canvas.clientHeight, radius: HANDLE_RADIUS };
  const handle = page.rig ? pickPoint(matrix(), handlePositions(), at, size) : null;
  if (handle != null) {
    beforeEdit();
    page.selected = handle;
    // Edits replace the handles rather than change them, so snapshots stay as they were.
    page.handles = page.handles.map((h) => ({ ...h }));
  }
  page.drag = { x: at[0], y: at[1], startX: at[0], startY: at[1], handle, panning: event.shiftKey || event.button === 2 };
});

canvas.addEventListener('pointermove', (event) => {
  if (!page.drag) return;
  const [x, y] = local(event);
  const dx = x - page.drag.x;
  const dy = y - page.drag.y;
  page.drag.x = x;
  page.drag.y = y;
  if (page.drag.handle != null && page.mode === 'turn') {
    const h = page.handles[page.drag.handle];
    h.rotation = turned(h.rotation, viewAxes(page.camera)[2], -TURN_PER_PIXEL * dx);
    update();
  } else if (page.drag.handle != null) {
    const h = page.handles[page.drag.handle];
    const at = h.rest.map((r, k) => r + h.offset[k]);
    const move = dragInView(page.camera, at, dx, dy, canvas.clientHeight);
    h.offset = h.offset.map((o, k) => o + move[k]);
    update();
  } else if (page.drag.panning) {
    pan(page.camera, dx, dy, canvas.clientHeight);
  } else {
    orbit(page.camera, dx, dy);
  }
  draw();
});

canvas.addEventListener('pointerup', (event) => {
  const drag = page.drag;
  page.drag = null;
  if (!drag) return;
  const [x, y] = local(event);
  const still = Math.hypot(x - drag.startX, y - drag.startY) < CLICK_SLOP;
  if (drag.handle != null && !still) {
    say(`handle ${drag.handle + 1} ${page.mode === 'turn' ? 'turned' : 'moved'}; frame (cage product and surface) ${page.frameMs.toFixed(1)} ms${errorNote()}`);
  } else if (still && !drag.panning) {
    click([x, y]);
  }
});

canvas.addEventListener('pointercancel', () => {
  page.drag = null;
});

canvas.addEventListener('contextmenu', (event) => event.preventDefault());

canvas.addEventListener('wheel', (event) => {
  if (!page.cage) return;
  event.preventDefault();
  zoom(page.camera, event.deltaY);
  draw();
}, { passive: false });

window.addEventListener('resize', draw);

const openFile = (file) => open(file).catch((e) => say(`${file.name}: ${e.message}`, { error: true }));

document.getElementById('open').addEventListener('change', (event) => {
  const [file] = event.target.files;
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
  update();
  draw();
});

document.getElementById('mode').addEventListener('change', (event) => {
  page.mode = event.target.value;
});

document.getElementById('method').addEventListener('change', (event) => {
  page.method = event.target.value;
  update();
  draw();
  if (page.rig) say(`showing ${page.method}${errorNote()}`);
});

document.getElementById('distance').addEventListener('change', (event) => {
  page.showDistance = event.target.checked;
  update();
  draw();
  if (page.rig) say(`showing ${page.method}${errorNote()}`);
});

document.getElementById('family').addEventListener('change', (event) => {
  beforeEdit();
  page.family = event.target.value;
  if (page.handles.length > 0) rig().catch((e) => say(e.message, { error: true }));
});

document.getElementById('rest').addEventListener('click', () => {
  if (!page.cage) return;
  beforeEdit();
  page.handles = page.handles.map((h) => ({ ...h, offset: [0, 0, 0], rotation: [...IDENTITY_ROTATION] }));
  update();
  draw();
});

document.getElementById('export').addEventListener('change', (event) => {
  const format = event.target.value;
  event.target.value = '';
  if (format) exportAs(page, format, say).catch((e) => say(e.message, { error: true }));
});

/** The keys' times in the toolbar. */
function showKeys() {
  const times = page.keys.map((k) => `${k.time} s`).join(', ');
  document.getElementById('keys').textContent = page.keys.length ? `keys: ${times}` : 'no keys';
}

document.getElementById('add-key').addEventListener('click', () => {
  if (!page.rig) {
    say('Add handles first: a key holds their pose.', { error: true });
    return;
  }
  const input = document.getElementById('key-time');
  const time = Math.max(0, Number(input.value) || 0);
  beforeEdit();
  page.keys = withKey(page.keys, keyOf(time, page.handles));
  input.value = String(time + 1);
  showKeys();
});

document.getElementById('clear-keys').addEventListener('click', () => {
  beforeEdit();
  page.keys = [];
  showKeys();
});

/** Plays the keys from 0 to the last, then leaves the last pose. */
document.getElementById('play').addEventListener('click', () => {
  if (page.keys.length < 2 || page.playing) return;
  const end = page.keys[page.keys.length - 1].time;
  const start = performance.now();
  let worst = 0;
  const frame = () => {
    const t = Math.min(end, (performance.now() - start) / 1000);
    poseAt(page.keys, t, page.handles);
    update();
    draw();
    worst = Math.max(worst, page.frameMs);
    if (t < end) {
      page.playing = requestAnimationFrame(frame);
    } else {
      page.playing = null;
      say(`played ${end} s; slowest frame (cage product and surface) ${worst.toFixed(1)} ms`);
    }
  };
  page.playing = requestAnimationFrame(frame);
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

/** What the page shows, for its tests: handles, the selection, whether the rig is ready, the last frame's time. */
window.subdivPageState = () => ({
  handles: page.handles.map((h) => ({ rest: [...h.rest], offset: [...h.offset], rotation: [...h.rotation] })),
  selected: page.selected,
  rigReady: page.rig != null,
  frameMs: page.frameMs,
  method: page.method,
  keys: page.keys.map((k) => k.time),
  playing: page.playing != null,
  error: page.error && { ...page.error },
  fitted: page.fitted ? Array.from(page.fitted) : null,
});

/** Where the world point `p` is drawn, CSS pixels in the canvas: `[x, y, depth]`, for the page's tests. */
window.subdivProject = (p) => project(matrix(), p, canvas.clientWidth, canvas.clientHeight);
