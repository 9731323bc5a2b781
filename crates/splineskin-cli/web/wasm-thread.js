// One thread of the threaded WebAssembly module's pool (splineskin-threads.wasm, built with
// shared memory; docs/webassembly.md, "Threads"): a Web Worker, or a Node worker thread,
// started by wasm-editor.js's threadStarter. Messages:
//   creator → thread  { module, memory, builder, stackTop, tls }   (once)
//   thread → creator  { started: true } once it works for the pool | { failed: message }

import { nodeModule, runThread } from './wasm-editor.js';

/** Where messages come from: the worker's global scope, or Node's parent port. */
const port = globalThis.self ?? (await nodeModule('node:worker_threads')).parentPort;

port.addEventListener('message', ({ data }) => {
  runThread(data, () => port.postMessage({ started: true }))
    .catch((e) => port.postMessage({ failed: e.message }));
}, { once: true });
