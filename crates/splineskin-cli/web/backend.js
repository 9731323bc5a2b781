// Where the page's requests go. Served by `splineskin serve`: to the server, by fetch. Opened
// from a static build (`splineskin serve --static-out DIR`, whose index.html says
// data-backend="wasm"): to Web Workers running splineskin's WebAssembly module
// (editor-worker.js), which answer the same routes; the answers come back as fetch Responses,
// so api.js reads them alike.
//
// A worker runs one request at a time and cannot be interrupted, so the static build keeps two:
// the main one answers everything, except the coarse stand-in rigs of the mesh families
// (`weights.coarse`), which the preview worker answers, so that a stand-in never waits behind
// the exact weights of an earlier click. The preview worker opens each document the page opened
// (the same POST /api/open or GET /api/initial, replayed on first use); its rigs reach the page with ids prefixed
// PREVIEW_RIG, and every request naming one is sent to it, ids translated.

const STATIC = document.documentElement.dataset.backend === 'wasm';

/** Prefix of the ids of rigs made by the preview worker. */
const PREVIEW_RIG = 'p-';

/** The latest stage each followed job reported: { stage, since (ms) }. */
const stages = new Map();

/** A Web Worker running the module, answering requests in the order sent. */
class ModuleWorker {
  constructor() {
    this.pending = new Map();
    this.nextId = 0;
    this.worker = new Worker(new URL('editor-worker.js', import.meta.url), { type: 'module' });
    this.worker.onmessage = ({ data }) => {
      if (data.progress !== undefined) {
        stages.set(data.progress, { ...data.stage, at: performance.now() });
        return;
      }
      if (data.ready || data.failed) return;
      const resolve = this.pending.get(data.id);
      this.pending.delete(data.id);
      if (resolve) resolve(data);
    };
    this.worker.onerror = (e) => {
      for (const resolve of this.pending.values()) {
        resolve(failure(500, `the WebAssembly editor stopped: ${e.message}`));
      }
      this.pending.clear();
    };
  }

  /** The worker's answer { status, contentType, headers, body } to a request (`body` is transferred). */
  request(method, path, headers, body) {
    const id = this.nextId++;
    const answer = new Promise((resolve) => this.pending.set(id, resolve));
    this.worker.postMessage({ id, method, path, headers, body }, [body]);
    return answer;
  }
}

/** An answer with status `status` and the error message `message`. */
function failure(status, message) {
  return { status, contentType: 'application/json', headers: {}, body: new TextEncoder().encode(JSON.stringify({ error: message })).buffer };
}

let main = null;
let preview = null;
/** Documents the page opened on the main worker: id → the request that opened it (POST /api/open or GET /api/initial). */
const opened = new Map();
/** The preview worker's id of each document opened there: main id → Promise of its id (null: failed). */
const previewDocuments = new Map();

/** Whether the page runs without a server. */
export const isStatic = STATIC;

/** `fetch(path, options)`, or its answer by a worker in a static build. */
export async function send(path, options = {}) {
  if (!STATIC) return fetch(path, options);
  const job = /^\/api\/progress\/([^/?]+)$/.exec(path);
  if (job) return progressOf(decodeURIComponent(job[1]));
  if (/^\/api\/progress\/[^/?]+\/stop$/.test(path)) {
    // The workers run one job at a time and cannot be interrupted: nothing to ask.
    return new Response(JSON.stringify({ stopping: false }), { headers: { 'content-type': 'application/json' } });
  }
  main ??= new ModuleWorker();
  const method = options.method ?? 'GET';
  const body = options.body === undefined ? new ArrayBuffer(0) : await new Response(options.body).arrayBuffer();
  const headers = Object.fromEntries(new Headers(options.headers ?? {}).entries());
  const followed = headers['x-splineskin-job'];
  if (followed) stages.set(followed, { stage: 'queued', seconds: 0, at: performance.now() });
  const answer = route(method, path, headers, body);
  const abort = options.signal && new Promise((_, reject) => {
    // The worker finishes the job (it cannot be interrupted); the page stops waiting for it.
    const stop = () => reject(new DOMException('The request was aborted', 'AbortError'));
    if (options.signal.aborted) stop();
    options.signal.addEventListener('abort', stop, { once: true });
  });
  try {
    const data = await (abort ? Promise.race([answer, abort]) : answer);
    return new Response(data.body, { status: data.status, headers: { 'content-type': data.contentType, ...data.headers } });
  } finally {
    if (followed) stages.delete(followed);
  }
}

/** Sends a request to the worker that answers it (module documentation). */
async function route(method, path, headers, body) {
  if ((method === 'POST' && path === '/api/open') || (method === 'GET' && path === '/api/initial')) {
    const request = { method, path, headers, body: body.slice(0) };
    const data = await main.request(method, path, headers, body);
    if (data.status === 200) opened.set(JSON.parse(new TextDecoder().decode(data.body)).id, request);
    return data;
  }
  if (method === 'POST' && path === '/api/rig') {
    const request = JSON.parse(new TextDecoder().decode(body));
    const document = request.scene?.weights?.coarse ? await previewDocument(request.document) : null;
    if (document === null) return main.request(method, path, headers, body);
    request.document = document;
    const data = await preview.request(method, path, headers, new TextEncoder().encode(JSON.stringify(request)).buffer);
    if (data.headers['x-splineskin-rig']) data.headers['x-splineskin-rig'] = PREVIEW_RIG + data.headers['x-splineskin-rig'];
    return data;
  }
  const rig = new RegExp(`^/api/rigs/${PREVIEW_RIG}([^/?]+)(.*)$`).exec(path);
  if (rig) return preview.request(method, `/api/rigs/${rig[1]}${rig[2]}`, headers, body);
  // An export with a preview rig's pose: the preview worker's document and rig.
  const exported = new RegExp(`^/api/documents/([^/?]+)(/export\\?.*)rig=${PREVIEW_RIG}(.*)$`).exec(path);
  if (exported) {
    const document = await previewDocument(decodeURIComponent(exported[1]));
    if (document === null) return failure(404, 'the stand-in rig is gone: wait for the exact weights');
    return preview.request(method, `/api/documents/${encodeURIComponent(document)}${exported[2]}rig=${exported[3]}`, headers, body);
  }
  return main.request(method, path, headers, body);
}

/**
 * The preview worker's id of the main worker's document `id`, opening it there first; null
 * when the page did not open it itself (a refined drawing: its stand-ins are answered by the
 * main worker) or it fails to open.
 */
function previewDocument(id) {
  const request = opened.get(id);
  if (!request) return Promise.resolve(null);
  if (!previewDocuments.has(id)) {
    preview ??= new ModuleWorker();
    const answer = preview.request(request.method, request.path, request.headers, request.body.slice(0));
    previewDocuments.set(
      id,
      answer.then((data) => (data.status === 200 ? JSON.parse(new TextDecoder().decode(data.body)).id : null)),
    );
  }
  return previewDocuments.get(id);
}

/** What `GET /api/progress/{job}` answers, from the stages the workers reported. */
function progressOf(job) {
  const entry = stages.get(job);
  const report = entry
    ? { ...entry, seconds: entry.seconds + (performance.now() - entry.at) / 1000 }
    : { stage: null };
  delete report.at;
  return new Response(JSON.stringify(report), { headers: { 'content-type': 'application/json' } });
}
