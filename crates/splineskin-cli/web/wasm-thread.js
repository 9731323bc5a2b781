// One thread of the threaded WebAssembly module's pool (splineskin-threads.wasm, built with
// shared memory for cross-origin-isolated pages; docs/webassembly.md, "Threads"): a Web Worker
// started by the editor's worker (editor-worker.js → wasm-editor.js's startThreads). Messages:
//   creator → thread  { module, memory, builder, stackTop, tls }   (once)
//   thread → creator  { started: true } once it works for the pool | { failed: message }

import { runThread } from './wasm-editor.js';

self.onmessage = ({ data }) => {
  runThread(data, () => self.postMessage({ started: true }))
    .catch((e) => self.postMessage({ failed: e.message }));
};
