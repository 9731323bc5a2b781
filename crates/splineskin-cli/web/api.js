// Calls to the editor's routes (crates/splineskin-editor/src/lib.rs has their table): to the
// server, or to the WebAssembly module in a worker in a static build (backend.js). Every POST
// carries `x-splineskin: 1`; errors come back as {"error": "…"} and are thrown as Error.

import { send } from './backend.js';

const HEADERS = { 'x-splineskin': '1' };

async function failure(response) {
  let message = `${response.status} ${response.statusText}`;
  try {
    const body = await response.json();
    if (body && body.error) message = body.error;
  } catch {
    // not JSON: keep the status
  }
  const error = new Error(message);
  error.status = response.status;
  return error;
}

async function call(path, options = {}) {
  const response = await send(path, options);
  if (!response.ok) throw await failure(response);
  return response;
}

function postJson(path, body, signal, headers = {}) {
  return call(path, {
    method: 'POST',
    headers: { ...HEADERS, 'content-type': 'application/json', ...headers },
    body: JSON.stringify(body),
    signal,
  });
}

/** The drawing the server was started with. */
export async function initialDocument() {
  return (await call('/api/initial')).json();
}

/** Uploads a file (SVG or scene); resolves to the document's description. */
export async function openFile(file) {
  const response = await call('/api/open', {
    method: 'POST',
    headers: { ...HEADERS, 'x-file-name': encodeURIComponent(file.name) },
    body: file,
  });
  return response.json();
}

/**
 * Precomputes the rig of `scene` on document `id`: { id, operator: Float64Array }. `job` names
 * the request for `progressOf`.
 */
export async function precompute(document, scene, signal, job) {
  const response = await postJson('/api/rig', { document, scene }, signal, { 'x-splineskin-job': job });
  const operator = new Float64Array(await response.arrayBuffer());
  return { id: response.headers.get('x-splineskin-rig'), operator };
}

/**
 * Adds control points to rig `rig`'s drawing where its fit falls further than `tolerance`
 * (fraction of the diagonal) from the skinned target under one of `poses`: the answer
 * `{ refined, document, rig, moved, n_inserted, n_curves, worst, met }` (wire.rs
 * RefineAnswer), with the refined drawing as a new document when anchors were inserted.
 */
export async function refine(rig, scene, poses, tolerance) {
  return (await postJson(`/api/rigs/${rig}/refine`, { scene, poses, tolerance })).json();
}

/** The operator O of rig `rig`, as `precompute` gives it. */
export async function rigOperator(rig) {
  const response = await call(`/api/rigs/${rig}/operator`);
  return new Float64Array(await response.arrayBuffer());
}

/**
 * Pins over the art of document `id` as `splineskin rig` places them, the page's pins
 * `handles` (rest positions) kept first: `{ pins: [[x, y], …] }`.
 */
export async function autoPins(id, handles) {
  return (await postJson(`/api/documents/${encodeURIComponent(id)}/pins`, { handles })).json();
}

/**
 * The carry operator of a rig (`defop` false: rig `id`'s text and images' best-fit maps per pose)
 * or of an operator (`defop` true: per configuration's handle functions ψ(Q)): Float64Array.
 */
export async function rigCarry(id, defop = false) {
  const response = await call(`/api/${defop ? 'defops' : 'rigs'}/${encodeURIComponent(id)}/carry`);
  return new Float64Array(await response.arrayBuffer());
}

/**
 * Trains a deformation operator for `scene` (family defop-arap or defop-sarap) on document
 * `id` and joins it with the drawing: { info, data: Float64Array } (layout in api.rs). `job`
 * names the request for `progressOf`.
 */
export async function trainOperator(document, scene, signal, job) {
  const response = await postJson('/api/defop', { document, scene }, signal, { 'x-splineskin-job': job });
  const header = response.headers.get('x-splineskin-defop');
  if (!header) throw new Error('the server sent an operator without its x-splineskin-defop header');
  const data = new Float64Array(await response.arrayBuffer());
  return { info: JSON.parse(header), data };
}

/**
 * Asks operator rig `id` to follow the handles to `handles` (`settle`: the drag ended there):
 * `{ info, data }` of a new operator (as trainOperator gives), or null when the server keeps
 * the operator (the configuration is in its trained region, or following reached its limit).
 */
export async function followOperator(id, handles, settle) {
  const response = await postJson(`/api/defops/${encodeURIComponent(id)}/follow`, { handles, settle });
  const header = response.headers.get('x-splineskin-defop');
  if (!header) return null;
  const data = new Float64Array(await response.arrayBuffer());
  return { info: JSON.parse(header), data };
}

/** The server's (the library's) deformation of operator rig `id` at handle positions `handles`. */
export async function operatorDeform(id, handles) {
  const response = await postJson(`/api/defops/${encodeURIComponent(id)}/deform`, { handles });
  return new Float64Array(await response.arrayBuffer());
}

/** The flexible G¹ solve of `pose` on rig `rig`: the deformed points, Float64Array. */
export async function solve(rig, pose, signal) {
  const response = await postJson(`/api/rigs/${encodeURIComponent(rig)}/solve`, { pose }, signal);
  return new Float64Array(await response.arrayBuffer());
}

/** Handle `handle`'s weight on a width × height grid over box [x0, y0, x1, y1]: Float32Array. */
export async function weightGrid(rig, handle, [x0, y0, x1, y1], width, height) {
  const query = new URLSearchParams({ handle, x0, y0, x1, y1, width, height });
  const response = await call(`/api/rigs/${encodeURIComponent(rig)}/weights?${query}`);
  return new Float32Array(await response.arrayBuffer());
}

/**
 * The deformed SVG document for `points` (Float64Array x0, y0, …), its viewBox kept as the
 * document's (`viewbox` 'keep') or grown to include the art ('fit'). `deformation` says what
 * deformed the points, so that gradients, patterns, markers, text and images follow it
 * (ExportQuery in crates/splineskin-editor/src/wire.rs): { rig, pose } (a rig's id and one
 * map [a, b, c, d, e, f] per handle) or { defop, q } (an operator rig's id and the handle
 * configuration x0, y0, x1, …); null leaves them at rest.
 */
export async function exportSvg(document, points, viewbox = 'keep', deformation = null) {
  const query = new URLSearchParams({ viewbox });
  let body = points;
  if (deformation) {
    const tail = deformation.rig !== undefined ? deformation.pose.flat() : Array.from(deformation.q);
    query.set(deformation.rig !== undefined ? 'rig' : 'defop', deformation.rig ?? deformation.defop);
    body = new Float64Array(points.length + tail.length);
    body.set(points);
    body.set(tail, points.length);
  }
  const response = await call(`/api/documents/${encodeURIComponent(document)}/export?${query}`, {
    method: 'POST',
    headers: { ...HEADERS, 'content-type': 'application/octet-stream' },
    body,
  });
  return response.text();
}

/**
 * Where the drawing through `points` stands against the document's viewBox:
 * { view_box, fitted, outside: [{ path, element, distance }] } (farthest first; fitted is the
 * viewBox a 'fit' export writes).
 */
export async function outside(document, points) {
  const response = await call(`/api/documents/${encodeURIComponent(document)}/outside`, {
    method: 'POST',
    headers: { ...HEADERS, 'content-type': 'application/octet-stream' },
    body: points,
  });
  return response.json();
}

/** The scene file (JSON text) of `scene`. */
export async function sceneFile(document, scene) {
  return (await postJson(`/api/documents/${encodeURIComponent(document)}/scene`, scene)).text();
}

/**
 * The stage of precomputation `job`: { stage: 'queued' | 'weights' | 'rig' | 'domain' |
 * 'training' | 'join' | null, seconds }, with { done, total, step, steps } while training.
 */
export async function progressOf(job) {
  return (await call(`/api/progress/${encodeURIComponent(job)}`)).json();
}

/**
 * Asks precomputation `job` to stop: a training ends at its next ground-truth solve, and its
 * request fails with status 409. Resolves to whether the job was running (a static build's
 * worker cannot be interrupted: false).
 */
export async function stopJob(job) {
  const response = await send(`/api/progress/${encodeURIComponent(job)}/stop`, { method: 'POST', headers: HEADERS });
  return response.ok && (await response.json()).stopping === true;
}

/**
 * The Lottie animation of `scene`'s timeline on document `id`, as `splineskin animate` writes
 * it: { json (text), report: { keyframes, every_frame_keyframes, bytes, every_frame_bytes,
 * warnings, summary } }.
 */
export async function exportLottie(document, scene) {
  const response = await postJson(`/api/documents/${encodeURIComponent(document)}/lottie`, scene);
  const header = response.headers.get('x-splineskin-lottie');
  return { json: await response.text(), report: header ? JSON.parse(header) : null };
}

/**
 * The animation of `scene`'s timeline on document `id` as `splineskin animate` writes it to
 * an `.svg` (format 'svg'), `.gif` ('gif') or animated `.png` ('apng'), the viewBox kept or
 * fitted to the art of every frame (`viewbox`): { blob, warning (text or null) }.
 */
export async function exportAnimation(document, scene, format, viewbox) {
  const query = new URLSearchParams({ format, viewbox });
  const response = await postJson(`/api/documents/${encodeURIComponent(document)}/animation?${query}`, scene);
  return { blob: await response.blob(), warning: response.headers.get('x-splineskin-warning') };
}

/**
 * The triangulated domain of rig `id`'s weights: { vertices (x0, y0, …), triangles (three
 * indices each), weights (n_handles per vertex), n_handles }. Rejects (status 400) for
 * weights solved without a mesh.
 */
export async function mesh(rig) {
  return (await call(`/api/rigs/${encodeURIComponent(rig)}/mesh`)).json();
}
