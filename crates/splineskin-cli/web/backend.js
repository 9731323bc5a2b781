// Where the page's requests go. Served by `splineskin serve`: to the server, by fetch. Opened
// from a static build (`splineskin serve --static-out DIR`, whose index.html says
// data-backend="wasm"): to Web Workers running splineskin's WebAssembly module
// (editor-worker.js), which answer the same routes; the answers come back as fetch Responses,
// so api.js reads them alike.
//
// A worker runs one request at a time and cannot be interrupted, so the static build keeps
// three kinds:
//   - the main worker opens the drawings and answers everything not below;
//   - the preview worker makes the coarse stand-in rigs of the mesh families (`weights.coarse`),
//     so that a stand-in never waits behind exact weights;
//   - the solver worker makes the exact rigs (POST /api/rig). When the page gives up the
//     request it is working on (a newer click superseded it) and asks for another, the solver
//     is stopped (`Worker.terminate`) and a new one takes over: a superseded solve does not
//     delay the next.
//   - the solver's helpers: a module runs on one thread, so the bounded biharmonic columns of
//     an exact rig (one program per pin) are spread over the solver and up to
//     `navigator.hardwareConcurrency - 1` helper workers (POST /api/weights/columns, pins
//     dealt round-robin), and the solver then builds the rig with all of them given (POST
//     /api/rig with `solved`): the same weights, bit for bit, on every core. Helpers are
//     stopped with the solver they help when superseded.
//   - the trainer worker trains the deformation operators (POST /api/defop) and answers for
//     them (their deformations, following, exports): "Stop training" stops it (a worker cannot
//     be interrupted mid-request, so it is terminated and a new one trains next), and a
//     training the page gave up is stopped before the next request.
//   - on a cross-origin-isolated page (its server sends COOP/COEP, docs/webassembly.md) with
//     the threaded module beside the page (splineskin-threads.wasm), the solver instead runs
//     that module on one thread per core (up to 8; wasm-thread.js): its exact rigs are
//     parallel inside, as natively (columns, the fit), and need no helpers.
// The preview and solver workers open each drawing the page opened (the same POST /api/open or
// GET /api/initial, replayed on first use). The ids of the documents and rigs they make reach
// the page tagged with the worker (`p-r3`, `s2-r5`); a request naming a tagged id goes to that
// worker, ids translated. The ids of a stopped solver answer 404 ("no longer kept"), which the
// page meets by precomputing again; a solver holding refined drawings is never stopped.

const STATIC = document.documentElement.dataset.backend === 'wasm';

/** The latest stage each followed job reported: { stage, since (ms) }. */
const stages = new Map();

/** The modules compiled by the page, by file name (each once; null where one cannot be). */
const compiled = new Map();

/**
 * The module in file `name` beside the page, compiled once (a WebAssembly.Module), or null
 * where the page cannot fetch or compile it. Workers given the same Module share its code, so
 * a new worker (a solver replacing a superseded one, a helper) neither compiles it again nor
 * starts from unoptimised code.
 */
function compiledFile(name) {
  if (!compiled.has(name)) {
    compiled.set(name, (async () => {
      const response = await fetch(new URL(name, import.meta.url));
      if (!response.ok) return null;
      // Streaming needs the server to say application/wasm; any other type is compiled whole.
      if (/wasm/.test(response.headers.get('content-type') ?? '')) return WebAssembly.compileStreaming(response);
      return WebAssembly.compile(await response.arrayBuffer());
    })().catch(() => null));
  }
  return compiled.get(name);
}

/** The one-thread module (the workers fetch and compile it themselves where this is null). */
function compiledModule() {
  return compiledFile('splineskin.wasm');
}

/**
 * The threaded module (built with shared memory), or null where it cannot run (the page is
 * not cross-origin isolated, so it has no shared memory) or is not beside the page (a static
 * build made without it).
 */
function threadedModule() {
  return self.crossOriginIsolated ? compiledFile('splineskin-threads.wasm') : Promise.resolve(null);
}

/** The cores a computation may spread over: the browser's count, at most 8. */
function cores() {
  return Math.max(1, Math.min(navigator.hardwareConcurrency || 1, MAX_COLUMN_WORKERS));
}

/** A Web Worker running the module, answering requests in the order sent. */
class ModuleWorker {
  /**
   * `tag`: '' for the main worker, else what its ids are prefixed with (before a '-');
   * `threads`: more than 1 to run the threaded module on that many threads where it can run.
   */
  constructor(tag, { threads = 1 } = {}) {
    this.tag = tag;
    /** The threads it computes on, once loaded (1 with the one-thread module). */
    this.threads = 1;
    /** The threaded module's stop flag { memory, address } (editor-worker.js), else null. */
    this.stopFlag = null;
    /** Requests sent and not answered, oldest first: id → { resolve, signal }. */
    this.pending = new Map();
    this.nextId = 0;
    /** The main worker's document ids → Promise of this worker's id (null: not opened). */
    this.documents = new Map();
    /** Whether it made a drawing of its own (refined by "add points"). */
    this.holdsDocuments = false;
    /** A solver's helper workers (splitRig). */
    this.helpers = [];
    this.worker = new Worker(new URL('editor-worker.js', import.meta.url), { type: 'module' });
    /** Resolves once the worker has been sent the module: requests are posted after it. */
    this.started = (threads > 1 ? threadedModule() : Promise.resolve(null)).then(async (threaded) => {
      if (threaded) this.worker.postMessage({ module: threaded, threads });
      else this.worker.postMessage({ module: await compiledModule() });
    });
    this.worker.onmessage = ({ data }) => {
      if (data.progress !== undefined) {
        stages.set(data.progress, { ...data.stage, at: performance.now() });
        return;
      }
      if (data.ready) {
        this.threads = data.threads ?? 1;
        this.stopFlag = data.stop ?? null;
      }
      if (data.ready || data.failed) return;
      const entry = this.pending.get(data.id);
      this.pending.delete(data.id);
      if (entry) entry.resolve(data);
    };
    this.worker.onerror = (e) => this.stop(500, `the WebAssembly editor stopped: ${e.message}`);
  }

  /**
   * The worker's answer { status, contentType, headers, body } to a request (`body` is
   * transferred); `signal`: the page's AbortSignal, if any.
   */
  request(method, path, headers, body, signal) {
    const id = this.nextId++;
    let resolve;
    const answer = new Promise((r) => { resolve = r; });
    this.pending.set(id, { resolve, signal, answer });
    this.started.then(() => this.worker.postMessage({ id, method, path, headers, body }, [body]));
    return answer;
  }

  /** Resolves once every request sent so far is answered. */
  idle() {
    return Promise.all([...this.pending.values()].map((entry) => entry.answer));
  }

  /**
   * Whether all the worker has to do is for requests the page gave up: every pending request
   * the page can give up (those with a signal) was, and there is one. What has no signal (a
   * drawing opened for a rig) serves those requests: a worker opening the drawing for a rig
   * the page no longer wants works for nothing.
   */
  workingOnAbandoned() {
    const signals = [...this.pending.values()].map((entry) => entry.signal).filter(Boolean);
    return signals.length > 0 && signals.every((signal) => signal.aborted);
  }

  /**
   * Stops the worker; what it had not answered gets `status` and `message`. A worker busy in
   * the module goes on until it returns (browsers let a terminated worker finish its task, for
   * up to about 2 s in Chromium, taking a core from the next rig), so the threaded module's
   * stop flag is raised first: its bounded biharmonic weights stop at their next iteration.
   */
  stop(status, message) {
    this.stopped = { status, message };
    if (this.stopFlag) Atomics.store(new Uint8Array(this.stopFlag.memory.buffer), this.stopFlag.address, 1);
    this.worker.terminate();
    for (const { resolve } of this.pending.values()) resolve(failure(status, message));
    this.pending.clear();
  }
}

/** An answer with status `status` and the error message `message`. */
function failure(status, message) {
  return { status, contentType: 'application/json', headers: {}, body: new TextEncoder().encode(JSON.stringify({ error: message })).buffer };
}

const decode = (buffer) => JSON.parse(new TextDecoder().decode(buffer));
const encode = (value) => new TextEncoder().encode(JSON.stringify(value)).buffer;

let main = null;
let preview = null;
let solver = null;
let solverGeneration = 0;
let trainer = null;
let trainerGeneration = 0;
/** Every worker that tags ids, by tag (stopped solvers stay out). */
const tagged = new Map();
/** Documents the page opened on the main worker: id → the request that opened it. */
const opened = new Map();

/** Whether the page runs without a server. */
export const isStatic = STATIC;

/** `fetch(path, options)`, or its answer by a worker in a static build. */
export async function send(path, options = {}) {
  if (!STATIC) return fetch(path, options);
  const job = /^\/api\/progress\/([^/?]+)$/.exec(path);
  if (job) return progressOf(decodeURIComponent(job[1]));
  const stopped = /^\/api\/progress\/([^/?]+)\/stop$/.exec(path);
  if (stopped) {
    // A training is stopped with its worker; nothing else is (a superseded exact rig is
    // stopped when the next one is asked for, see route).
    const stopping = stopTraining(decodeURIComponent(stopped[1]));
    return new Response(JSON.stringify({ stopping }), { headers: { 'content-type': 'application/json' } });
  }
  main ??= new ModuleWorker('');
  const method = options.method ?? 'GET';
  const body = options.body === undefined ? new ArrayBuffer(0) : await new Response(options.body).arrayBuffer();
  const headers = Object.fromEntries(new Headers(options.headers ?? {}).entries());
  const followed = headers['x-splineskin-job'];
  if (followed) stages.set(followed, { stage: 'queued', seconds: 0, at: performance.now() });
  const answer = route(method, path, headers, body, options.signal);
  const abort = options.signal && new Promise((_, reject) => {
    // The page stops waiting; the worker is stopped if the next request needs it (route).
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

/** The routes whose path names a document, a rig or an operator: [prefix, id, rest]. */
const NAMED = /^(\/api\/(?:documents|rigs|defops)\/)([^/?]+)(.*)$/;

/** Sends a request to the worker that answers it (module documentation). */
async function route(method, path, headers, body, signal) {
  if ((method === 'POST' && path === '/api/open') || (method === 'GET' && path === '/api/initial')) {
    const request = { method, path, headers, body: body.slice(0) };
    const data = await main.request(method, path, headers, body, signal);
    if (data.status === 200) opened.set(decode(data.body).id, request);
    return data;
  }
  dropAbandonedTrainer();
  // The ids the request names: in its path, its query (rig, defop) and a scene request's body.
  let [, prefix, named, rest] = NAMED.exec(path) ?? [null, null, null, null];
  const query = rest === null ? null : new URLSearchParams(rest.split('?')[1] ?? '');
  const scene = method === 'POST' && (path === '/api/rig' || path === '/api/defop') ? decode(body) : null;
  const ids = [named && decodeURIComponent(named), query?.get('rig'), query?.get('defop'), scene?.document].filter(Boolean);
  const tags = new Set(ids.map(tagOf).filter((t) => t !== ''));
  let worker;
  if (tags.size > 1) return failure(400, `ids of different workers in one request: ${ids.join(', ')}`);
  if (tags.size === 1) {
    const [tag] = tags;
    worker = tagged.get(tag);
    if (!worker) return failure(404, `${ids.join(', ')}: no longer kept (a newer precomputation replaced it): precompute again`);
  } else if (path === '/api/defop' && method === 'POST') {
    worker = (trainer ??= tag(new ModuleWorker(`t${++trainerGeneration}`)));
    if (headers['x-splineskin-job']) trainer.job = headers['x-splineskin-job'];
  } else if (path === '/api/rig' && method === 'POST') {
    if (!scene.scene?.weights?.coarse) {
      const solver = exactSolver();
      const threaded = (await threadedModule()) !== null;
      if (threaded) nThreadedRigs += 1;
      if (!threaded && scene.scene?.weights?.family === 'bbw' && columnWorkers(scene) > 1 && opened.has(scene.document)) {
        return splitRig(solver, headers, scene, signal);
      }
      worker = solver;
    } else {
      dropAbandonedSolver();
      worker = (preview ??= tag(new ModuleWorker('p')));
    }
  } else {
    return main.request(method, path, headers, body, signal);
  }
  // The ids in the chosen worker's terms: its own untagged, the main worker's documents opened there.
  const local = async (id) => {
    if (tagOf(id) === worker.tag) return id.slice(worker.tag.length + 1);
    return documentIn(worker, id);
  };
  const translated = new Map();
  for (const id of ids) translated.set(id, await local(id));
  // Stopped while it opened the drawing (Stop training): the request ends as the worker did.
  if (worker.stopped) return failure(worker.stopped.status, worker.stopped.message);
  if ([...translated.values()].includes(null)) {
    // A document the page did not open itself (a refined drawing): the main worker has it.
    if (tags.size === 0) return main.request(method, path, headers, body, signal);
    return failure(404, `${ids.join(', ')}: not available in the same worker: precompute again`);
  }
  if (named) path = prefix + encodeURIComponent(translated.get(decodeURIComponent(named))) + rest.split('?')[0];
  if (query) {
    for (const key of ['rig', 'defop']) if (query.get(key)) query.set(key, translated.get(query.get(key)));
    if ([...query.keys()].length) path += `?${query}`;
  }
  if (scene) {
    scene.document = translated.get(scene.document);
    body = encode(scene);
  }
  return tagAnswer(worker, await worker.request(method, path, headers, body, signal), path);
}

/** The solver worker, a new one if the current one was dropped ([`dropAbandonedSolver`]). */
function exactSolver() {
  dropAbandonedSolver();
  if (!solver) solver = tag(new ModuleWorker(`s${++solverGeneration}`, { threads: cores() }));
  return solver;
}

/**
 * Stops the solver and its helpers if one of them works on a request the page gave up (a newer
 * click superseded it), before the next rig or stand-in is asked for, so that they do not take
 * its cores. A solver that holds drawings refined by "add points" (the page may come back to
 * them) is left to finish and keeps answering for them; its helpers are stopped all the same.
 */
function dropAbandonedSolver() {
  if (!solver || ![solver, ...solver.helpers].some((w) => w.workingOnAbandoned())) return;
  for (const helper of solver.helpers) helper.stop(404, 'superseded: the editor asked for another rig');
  solver.helpers = [];
  if (!solver.holdsDocuments) {
    tagged.delete(solver.tag);
    solver.stop(404, 'superseded: the editor asked for another rig');
  }
  solver = null;
}

/**
 * Stops the training of job `job`, if the trainer runs it: the worker is terminated (its
 * operators go with it) and the request answers 409, as the server's stopped training does.
 */
function stopTraining(job) {
  if (!trainer || trainer.job !== job || trainer.pending.size === 0) return false;
  tagged.delete(trainer.tag);
  trainer.stop(409, 'training stopped as asked');
  trainer = null;
  return true;
}

/** Stops the trainer when all it works on is a training the page gave up (another family chosen). */
function dropAbandonedTrainer() {
  if (!trainer?.workingOnAbandoned()) return;
  tagged.delete(trainer.tag);
  trainer.stop(404, 'superseded: the editor asked for something else');
  trainer = null;
}

/** Exact rigs made so far with their columns spread over workers (for tests: splitRigs). */
let nSplitRigs = 0;

/** How many exact rigs had their columns spread over several workers (static build). */
export function splitRigs() {
  return nSplitRigs;
}

/** Exact rigs asked of a solver running the threaded module (for tests: threadedRigs). */
let nThreadedRigs = 0;

/**
 * How many exact rigs went to a solver running the threaded module (a cross-origin-isolated
 * page with splineskin-threads.wasm), and the threads the current solver computes on.
 */
export function threadedRigs() {
  return { rigs: nThreadedRigs, threads: solver?.threads ?? 0 };
}

/** Workers at most over which one computation is spread (the solver and its helpers, or threads). */
const MAX_COLUMN_WORKERS = 8;

/** How many workers the columns of `request`'s exact rig are spread over: one per core, per pin. */
function columnWorkers(request) {
  return Math.min(cores(), request.scene?.handles?.length ?? 0);
}

/**
 * An exact bounded biharmonic rig of a document the page opened (`request`: POST /api/rig's
 * body, document in the main worker's terms), its columns solved by `solver` and its helpers
 * at once, then built by `solver` with all of them given.
 */
async function splitRig(solver, headers, request, signal) {
  const n = columnWorkers(request);
  while (solver.helpers.length < n - 1) solver.helpers.push(new ModuleWorker(`${solver.tag}h${solver.helpers.length + 1}`));
  const workers = [solver, ...solver.helpers.slice(0, n - 1)];
  const h = request.scene.handles.length;
  const parts = await Promise.all(workers.map(async (worker, k) => {
    // A helper waits for the stand-in being made, if any: it is what the user sees first, and
    // on few cores a helper would take its core.
    if (k > 0) await preview?.idle();
    const document = await documentIn(worker, request.document);
    if (document === null) return failure(404, `${request.document}: not available in the solver: precompute again`);
    const columns = [...Array(h).keys()].filter((j) => j % n === k);
    const body = encode({ document, scene: request.scene, columns });
    return worker.request('POST', '/api/weights/columns', headers, body, signal);
  }));
  const failed = parts.find((p) => p.status !== 200);
  if (failed) return failed;
  if (signal?.aborted) return failure(409, 'superseded: the editor asked for another rig');
  const solved = parts.map((p) => decode(p.body));
  const merged = {
    n_vertices: solved[0].n_vertices,
    columns: solved.flatMap((s) => s.columns),
    values: solved.flatMap((s) => s.values),
  };
  const document = await documentIn(solver, request.document);
  const body = encode({ document, scene: request.scene, solved: merged });
  nSplitRigs += 1;
  return tagAnswer(solver, await solver.request('POST', '/api/rig', headers, body, signal), '/api/rig');
}

/** Registers `worker` by its tag; returns it. */
function tag(worker) {
  tagged.set(worker.tag, worker);
  return worker;
}

/** The tag of id `id` ('' for the main worker's). */
function tagOf(id) {
  const dash = String(id).indexOf('-');
  return dash < 0 ? '' : String(id).slice(0, dash);
}

/**
 * The answer of `worker` with the ids it made tagged: a new rig's header, a new operator's
 * (its x-splineskin-defop description), a refined drawing's.
 */
function tagAnswer(worker, data, path) {
  const mark = (id) => `${worker.tag}-${id}`;
  if (data.headers['x-splineskin-rig']) data.headers['x-splineskin-rig'] = mark(data.headers['x-splineskin-rig']);
  if (data.headers['x-splineskin-defop']) {
    const info = JSON.parse(data.headers['x-splineskin-defop']);
    info.id = mark(info.id);
    data.headers['x-splineskin-defop'] = JSON.stringify(info);
  }
  if (data.status === 200 && /^\/api\/rigs\/[^/]+\/refine$/.test(path)) {
    const answer = decode(data.body);
    if (answer.document) {
      answer.document.id = mark(answer.document.id);
      worker.holdsDocuments = true;
    }
    if (answer.rig) answer.rig = mark(answer.rig);
    data.body = encode(answer);
  }
  return data;
}

/**
 * `worker`'s id of the main worker's document `id`, opening it there first; null when the
 * page did not open it itself (a refined drawing) or it fails to open.
 */
function documentIn(worker, id) {
  const request = opened.get(id);
  if (!request) return Promise.resolve(null);
  if (!worker.documents.has(id)) {
    const answer = worker.request(request.method, request.path, request.headers, request.body.slice(0));
    worker.documents.set(id, answer.then((data) => (data.status === 200 ? decode(data.body).id : null)));
  }
  return worker.documents.get(id);
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
