// Where the page's requests go. Served by `splineskin serve`: to the server, by fetch. Opened
// from a static build (`splineskin serve --static-out DIR`, whose index.html says
// data-backend="wasm"): to a Web Worker running splineskin's WebAssembly module
// (editor-worker.js), which answers the same routes; the answers come back as fetch Responses,
// so api.js reads them alike.

const STATIC = document.documentElement.dataset.backend === 'wasm';

let worker = null;
let nextId = 0;
const pending = new Map();
/** The latest stage each followed job reported: { stage, since (ms) }. */
const stages = new Map();

function startWorker() {
  worker = new Worker(new URL('editor-worker.js', import.meta.url), { type: 'module' });
  worker.onmessage = ({ data }) => {
    if (data.progress !== undefined) {
      stages.set(data.progress, { ...data.stage, at: performance.now() });
      return;
    }
    if (data.ready || data.failed) return;
    const resolve = pending.get(data.id);
    pending.delete(data.id);
    if (resolve) resolve(data);
  };
  worker.onerror = (e) => {
    for (const resolve of pending.values()) {
      resolve({ status: 500, contentType: 'application/json', headers: {}, body: new TextEncoder().encode(JSON.stringify({ error: `the WebAssembly editor stopped: ${e.message}` })).buffer });
    }
    pending.clear();
  };
}

/** Whether the page runs without a server. */
export const isStatic = STATIC;

/** `fetch(path, options)`, or its answer by the worker in a static build. */
export async function send(path, options = {}) {
  if (!STATIC) return fetch(path, options);
  const job = /^\/api\/progress\/([^/?]+)$/.exec(path);
  if (job) return progressOf(decodeURIComponent(job[1]));
  if (/^\/api\/progress\/[^/?]+\/stop$/.test(path)) {
    // The worker runs one job at a time and cannot be interrupted: nothing to ask.
    return new Response(JSON.stringify({ stopping: false }), { headers: { 'content-type': 'application/json' } });
  }
  if (!worker) startWorker();
  const body = options.body === undefined ? new ArrayBuffer(0) : await new Response(options.body).arrayBuffer();
  const headers = Object.fromEntries(new Headers(options.headers ?? {}).entries());
  const id = nextId++;
  const followed = headers['x-splineskin-job'];
  if (followed) stages.set(followed, { stage: 'queued', seconds: 0, at: performance.now() });
  const answer = new Promise((resolve) => pending.set(id, resolve));
  worker.postMessage({ id, method: options.method ?? 'GET', path, headers, body }, [body]);
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

/** What `GET /api/progress/{job}` answers, from the stages the worker reported. */
function progressOf(job) {
  const entry = stages.get(job);
  const report = entry
    ? { ...entry, seconds: entry.seconds + (performance.now() - entry.at) / 1000 }
    : { stage: null };
  delete report.at;
  return new Response(JSON.stringify(report), { headers: { 'content-type': 'application/json' } });
}
