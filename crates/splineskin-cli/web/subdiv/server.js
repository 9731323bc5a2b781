// The page's requests to `splineskin serve` (the routes of splineskin-editor's subdiv_routes),
// or, in a static build, to the WebAssembly module in a worker (../backend.js), which answers
// the same routes.

import { send } from '../backend.js';

/** POSTs `body` to the server's `route`, answering the response or throwing its message. */
export async function postRaw(route, body, headers = {}) {
  // The server answers POSTs that carry this header only (its guard against other sites).
  const response = await send(route, { method: 'POST', headers: { 'x-splineskin': '1', ...headers }, body });
  if (!response.ok) {
    const text = await response.text();
    let message = text;
    try {
      message = JSON.parse(text).error ?? text;
    } catch {
      // Not JSON: the text as it came.
    }
    throw new Error(message);
  }
  return response;
}

/** POSTs `body` to `route`, answering its JSON. */
export async function post(route, body, headers = {}) {
  return (await postRaw(route, body, headers)).json();
}
