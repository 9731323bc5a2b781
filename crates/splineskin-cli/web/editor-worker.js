// The editor's Web Worker for a page without a server (`splineskin serve --static-out DIR`):
// answers the page's requests with splineskin's WebAssembly module (wasm-editor.js) off the
// page's thread, so that the page never freezes while weights are solved. Messages:
//   page → worker  { module, threads } first: the module compiled by the page (a
//                  WebAssembly.Module, shared by every worker: compiled once, and its optimised
//                  code too); with the threaded module, how many threads to compute on
//                  { id, method, path, headers, body (ArrayBuffer) }
//   worker → page  { id, status, contentType, headers, body (ArrayBuffer) }
//                  { progress: job, stage }            while a followed job runs
//                  { ready: true, threads, stop } | { failed: message } once the module is
//                  loaded or not; `stop`: the threaded module's stop flag { memory, address }
//                  (wasm-editor.js), through which the page stops a request mid-computation

import { loadEditor } from './wasm-editor.js';

/** The editor, once the page has sent the module. */
let loading = null;

/** Instantiates the module the page compiled (or, given none, fetches and compiles it). */
function load(module, threads) {
  loading = loadEditor(module ?? new URL('splineskin.wasm', import.meta.url), {
    onProgress: (job, stage) => self.postMessage({ progress: job, stage }),
    threads,
  });
  loading.then(
    (editor) => self.postMessage({ ready: true, threads: editor.threads, stop: editor.stopFlag }),
    (e) => self.postMessage({ failed: `splineskin.wasm: ${e.message}` }),
  );
}

self.onmessage = async ({ data }) => {
  if ('module' in data) {
    load(data.module, data.threads ?? 1);
    return;
  }
  if (!loading) load(null, 1);
  const { id, method, path, headers, body } = data;
  let answer;
  try {
    const editor = await loading;
    const response = editor.request(method, path, { headers, body: new Uint8Array(body) });
    answer = { id, ...response, body: response.body.buffer };
  } catch (e) {
    // A failed load, or a trap in the module (a bug): the page shows the message.
    const message = `internal error in the WebAssembly editor (a bug in splineskin, please report it): ${e.message}`;
    answer = { id, status: 500, contentType: 'application/json', headers: {}, body: new TextEncoder().encode(JSON.stringify({ error: message })).buffer };
  }
  self.postMessage(answer, [answer.body]);
};
