// The editor's requests answered by splineskin's WebAssembly module (crates/splineskin-wasm,
// src/editor.rs): the routes `splineskin serve` answers over HTTP, computed where this script
// runs (a Web Worker of the page, Node, any page). No DOM; works wherever WebAssembly does.
//
//   const editor = await loadEditor(bytesOrUrl, { onProgress });
//   // the threaded module (splineskin-threads.wasm), in a worker of a cross-origin-isolated
//   // page or under Node, its pool's threads started in workers (threadStarter)
//   const editor = await loadEditor(threadedModule, { threads: 4 });
//   const { status, contentType, headers, body } = editor.request('POST', '/api/rig', { body, headers });

const encoder = new TextEncoder();
const decoder = new TextDecoder();

/**
 * Instantiates the module from `source` (a URL or a Response to fetch it from, its bytes as an
 * ArrayBuffer or typed array, or a WebAssembly.Module). `onProgress(job, stage)` hears the
 * stages of the requests that name a job (`x-splineskin-job`), as `GET /api/progress/{job}`
 * would tell them. With the threaded module and `threads` more than 1, its pool is started
 * (startThreads), each thread by `startThread(message)` (default: threadStarter's); the
 * single-threaded module ignores both.
 */
export async function loadEditor(source, { onProgress, threads = 1, startThread } = {}) {
  const module = await compile(source);
  const shared = sharedMemoryOf(module);
  let memory = shared;
  /** A threaded module's threads asked for by its pool, not yet started (`spawn_thread`). */
  const builders = [];
  // A shared memory's views cannot be decoded in place: copy first.
  const text = (address, length) => decoder.decode(new Uint8Array(memory.buffer, address, length).slice());
  const imports = {
    splineskin: {
      now: () => performance.now(),
      progress: (job, jobLength, json, jsonLength) => {
        if (onProgress) onProgress(text(job, jobLength), JSON.parse(text(json, jsonLength)));
      },
      spawn_thread: (builder) => builders.push(builder),
    },
  };
  if (shared) imports.env = { memory: shared };
  const instance = await WebAssembly.instantiate(module, imports);
  const m = instance.exports;
  memory ??= m.memory;
  // A page's main thread may not wait on shared memory, which a pool's caller does.
  const mayWait = typeof document === 'undefined';
  if (shared && threads > 1 && !mayWait) console.warn('splineskin: threads run only off a page\'s main thread (in a worker): computing on one');
  const nThreads = shared && threads > 1 && mayWait
    ? await startThreads(module, shared, m, builders, threads, startThread ?? await threadStarter())
    : 1;
  return {
    /** The module's exports (the lower-level calls of crates/splineskin-wasm). */
    exports: m,
    imports,
    /** The threads the module computes on (1 unless a threaded module was given threads). */
    threads: nThreads,
    /**
     * With the threaded module, { memory, address }: the byte in the shared memory that stops
     * the request being answered when 1 is stored there (`Atomics.store`), from any thread
     * (splineskin_stop_flag); null with the one-thread module, whose memory nobody else sees.
     */
    stopFlag: shared ? { memory: shared, address: m.splineskin_stop_flag() } : null,
    /**
     * Answers `method path` (a path under /api/, with `?query` if any) with `body` (bytes or
     * text) and `headers` (an object): `{ status, contentType, headers, body }`, the body a
     * Uint8Array of its own.
     */
    request(method, path, { body = new Uint8Array(0), headers = {} } = {}) {
      const [route, query = ''] = path.split(/\?(.*)/s);
      const head = encoder.encode(JSON.stringify({
        method, path: route, query,
        headers: Object.entries(headers).map(([k, v]) => [k.toLowerCase(), String(v)]),
      }));
      const bytes = typeof body === 'string' ? encoder.encode(body)
        : body instanceof Uint8Array ? body
          : ArrayBuffer.isView(body) ? new Uint8Array(body.buffer, body.byteOffset, body.byteLength)
            : new Uint8Array(body);
      const at = m.splineskin_input(head.length + bytes.length);
      const input = new Uint8Array(memory.buffer, at, head.length + bytes.length);
      input.set(head);
      input.set(bytes, head.length);
      const headLength = m.splineskin_editor_request(head.length, head.length + bytes.length);
      const response = new Uint8Array(memory.buffer, m.splineskin_response(), m.splineskin_response_len());
      const answer = JSON.parse(decoder.decode(response.slice(0, headLength)));
      return {
        status: answer.status,
        contentType: answer.content_type,
        headers: Object.fromEntries(answer.headers),
        body: response.slice(headLength),
      };
    },
  };
}

/** `source` compiled: a WebAssembly.Module as given, or fetched, or from its bytes. */
/**
 * Node's built-in module `name`, imported where Node runs it. The name is not written in the
 * import, so that bundlers building for the browser (Vite, webpack) leave it alone rather than
 * stubbing it with a warning or failing on the `node:` scheme.
 */
export function nodeModule(name) {
  return import(/* @vite-ignore */ /* webpackIgnore: true */ name);
}

async function compile(source) {
  if (source instanceof WebAssembly.Module) return source;
  if (source instanceof ArrayBuffer || ArrayBuffer.isView(source)) return WebAssembly.compile(source);
  // Node's fetch does not read files: a file: URL (the default beside the module, under Node)
  // is read from disk.
  if (String(source).startsWith('file:')) {
    const { readFile } = await nodeModule('node:fs/promises');
    return WebAssembly.compile(await readFile(new URL(source)));
  }
  const response = source instanceof Response ? source : await fetch(source);
  if (!response.ok) throw new Error(`${response.url}: ${response.status} ${response.statusText}`);
  if (WebAssembly.compileStreaming && /wasm/.test(response.headers.get('content-type') ?? '')) {
    return WebAssembly.compileStreaming(response);
  }
  return WebAssembly.compile(await response.arrayBuffer());
}

/** Bytes of stack each of a threaded module's threads gets. */
const THREAD_STACK = 2 << 20;

/**
 * A new shared memory for `module` if it is the threaded build (it imports `env.memory`: built
 * with `+atomics`, every thread's instance runs on the same memory), else null. It starts at
 * 16 MiB, more than the module's data and main stack (about 1.3 MiB), and may grow to the 4 GiB
 * the module declares (tools/build-wasm links it with --max-memory=4294967296).
 */
function sharedMemoryOf(module) {
  if (!WebAssembly.Module.imports(module).some((i) => i.module === 'env' && i.name === 'memory')) return null;
  return new WebAssembly.Memory({ initial: 256, maximum: 65536, shared: true });
}

/**
 * Starts a threaded module's pool: `threads` threads, the caller's instance `m` and
 * `threads - 1` more, each started by `startThread(message)` (in a Web Worker of its own, which
 * calls runThread with the message) and resolving once it runs. Returns the pool's size.
 */
async function startThreads(module, memory, m, builders, threads, startThread) {
  const size = m.splineskin_threads_start(threads);
  if (size === 0) return 1;
  const tlsSize = m.__tls_size.value;
  const tlsAlign = m.__tls_align.value;
  await Promise.all(builders.splice(0).map((builder) => {
    const stackTop = m.splineskin_thread_memory(THREAD_STACK, tlsSize, tlsAlign);
    const tls = new Float64Array(memory.buffer, m.splineskin_output(), 1)[0];
    return startThread({ module, memory, builder, stackTop, tls });
  }));
  return size;
}

/** How long a pool thread may take to start before the pool goes on without it. */
const THREAD_START_MS = 10000;

/**
 * A `startThread` for loadEditor where this script runs: it starts a Web Worker (in a worker
 * of a cross-origin-isolated page) or a Node worker thread running wasm-thread.js, and
 * resolves once the thread works for the pool, or fails to start, or after THREAD_START_MS: a
 * thread that did not start leaves its share to the others (the pool's loops are
 * work-stealing), and the console says why. Node threads do not keep the process alive.
 */
export async function threadStarter() {
  const url = new URL('wasm-thread.js', import.meta.url);
  const node = typeof Worker === 'undefined' ? await nodeModule('node:worker_threads') : null;
  return (message) => new Promise((resolve) => {
    const thread = node ? new node.Worker(url) : new Worker(url, { type: 'module' });
    const done = (failure) => {
      clearTimeout(timer);
      if (failure) console.warn(`splineskin: a WebAssembly thread did not start: ${failure}`);
      thread.unref?.();
      resolve();
    };
    const timer = setTimeout(() => done(`no answer in ${THREAD_START_MS / 1000} s`), THREAD_START_MS);
    thread.addEventListener?.('message', ({ data }) => done(data.failed));
    thread.addEventListener?.('error', (e) => done(e.message));
    thread.on?.('message', (data) => done(data.failed));
    thread.on?.('error', (e) => done(e.message));
    thread.postMessage(message);
  });
}

/**
 * Runs one of a threaded module's pool threads where it is called (a Web Worker started for
 * it): instantiates `module` on the shared `memory` with the stack and thread-local block the
 * pool allocated, calls `started()`, then works for the pool; never returns.
 */
export async function runThread({ module, memory, builder, stackTop, tls }, started) {
  const refuse = () => { throw new Error('a pool thread cannot start threads'); };
  const imports = {
    env: { memory },
    splineskin: { now: () => performance.now(), progress: () => {}, spawn_thread: refuse },
  };
  const instance = await WebAssembly.instantiate(module, imports);
  const m = instance.exports;
  m.__stack_pointer.value = stackTop;
  m.__wasm_init_tls(tls);
  started();
  m.splineskin_thread_run(builder);
}
