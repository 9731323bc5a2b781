// The Catmull–Clark page: open an OBJ cage, see its limit surface shaded, turn it about. The
// page's state is the one `page` object below; the modules it uses hold none.
//
//   surface.js   the limit surface from cage positions (stencils), normals, bounds
//   camera.js    the orbit camera and its matrices
//   gl-view.js   the WebGL2 drawing

import { eye, fitCamera, orbit, pan, viewProjection, zoom } from './camera.js';
import { createView } from './gl-view.js';
import { bounds, tessellate, vertexNormals } from './surface.js';

const page = {
  /** The opened cage ([`CageWire`] of POST /api/subdiv/open), or null. */
  cage: null,
  /** Surface positions and normals (f32, drawn) and the cage's positions (f64). */
  positions: null,
  normals: null,
  camera: null,
  showCage: false,
  /** The pointer drag in progress: `{x, y, panning}`, or null. */
  drag: null,
  /** Milliseconds of the last tessellation (stencil product and normals). */
  tessellateMs: 0,
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
  const response = await fetch('/api/subdiv/open', {
    method: 'POST',
    // The server answers POSTs that carry this header only (its guard against other sites).
    headers: { 'x-splineskin': '1', 'x-file-name': encodeURIComponent(file.name) },
    body: await file.arrayBuffer(),
  });
  if (!response.ok) {
    const text = await response.text();
    let message = text;
    try {
      message = JSON.parse(text).error ?? text;
    } catch {
      // Not JSON: the text as it came.
    }
    say(message, { error: true });
    return;
  }
  const cage = await response.json();
  page.cage = cage;
  page.positions = new Float32Array(3 * cage.surface.n_vertices);
  page.normals = new Float32Array(3 * cage.surface.n_vertices);
  page.view.setMesh(cage.surface.triangles, cage.edges);
  update(cage.positions);
  page.camera = fitCamera(bounds(page.positions));
  draw();
  const [creases, corners, holes] = cage.n_tags;
  say(`${cage.name}: ${cage.positions.length / 3} vertices, ${cage.face_sizes.length} faces, ` +
    `${creases} creases, ${corners} corners, ${holes} holes; limit surface level ${cage.surface.level}, ` +
    `${cage.surface.triangles.length / 3} triangles, tessellated in ${page.tessellateMs.toFixed(1)} ms`);
}

/** The surface of the cage at `cagePositions`, uploaded. */
function update(cagePositions) {
  const start = performance.now();
  const surface = page.cage.surface;
  tessellate(surface, cagePositions, page.positions);
  vertexNormals(page.positions, surface.triangles, page.normals);
  page.tessellateMs = performance.now() - start;
  page.view.setPositions(page.positions, page.normals, cagePositions);
}

function draw() {
  if (!page.cage) return;
  const aspect = canvas.clientWidth / Math.max(1, canvas.clientHeight);
  page.view.draw(viewProjection(page.camera, aspect), eye(page.camera), { showCage: page.showCage });
}

document.getElementById('open').addEventListener('change', (event) => {
  const [file] = event.target.files;
  if (file) open(file).catch((e) => say(`${file.name}: ${e.message}`, { error: true }));
});

document.getElementById('show-cage').addEventListener('change', (event) => {
  page.showCage = event.target.checked;
  draw();
});

document.getElementById('reset-view').addEventListener('click', () => {
  if (!page.cage) return;
  page.camera = fitCamera(bounds(page.positions));
  draw();
});

canvas.addEventListener('pointerdown', (event) => {
  if (!page.cage) return;
  canvas.setPointerCapture(event.pointerId);
  page.drag = { x: event.clientX, y: event.clientY, panning: event.shiftKey || event.button === 2 };
});

canvas.addEventListener('pointermove', (event) => {
  if (!page.drag) return;
  const dx = event.clientX - page.drag.x;
  const dy = event.clientY - page.drag.y;
  page.drag.x = event.clientX;
  page.drag.y = event.clientY;
  if (page.drag.panning) {
    pan(page.camera, dx, dy, canvas.clientHeight);
  } else {
    orbit(page.camera, dx, dy);
  }
  draw();
});

for (const end of ['pointerup', 'pointercancel']) {
  canvas.addEventListener(end, () => {
    page.drag = null;
  });
}

canvas.addEventListener('contextmenu', (event) => event.preventDefault());

canvas.addEventListener('wheel', (event) => {
  if (!page.cage) return;
  event.preventDefault();
  zoom(page.camera, event.deltaY);
  draw();
}, { passive: false });

window.addEventListener('resize', draw);

const stage = document.getElementById('stage');
stage.addEventListener('dragover', (event) => event.preventDefault());
stage.addEventListener('drop', (event) => {
  event.preventDefault();
  const [file] = event.dataTransfer.files;
  if (file) open(file).catch((e) => say(`${file.name}: ${e.message}`, { error: true }));
});
