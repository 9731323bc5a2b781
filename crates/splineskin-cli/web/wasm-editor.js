// The editor's requests answered by splineskin's WebAssembly module (crates/splineskin-wasm,
// src/editor.rs): the routes `splineskin serve` answers over HTTP, computed where this script
// runs (a Web Worker of the page, Node, any page). No DOM; works wherever WebAssembly does.
//
//   const editor = await loadEditor(bytesOrUrl, { onProgress });
//   const { status, contentType, headers, body } = editor.request('POST', '/api/rig', { body, headers });

const encoder = new TextEncoder();
const decoder = new TextDecoder();

/**
 * Instantiates the module from `source` (a URL or a Response to fetch it from, or its bytes as
 * an ArrayBuffer or typed array). `onProgress(job, stage)` hears the stages of the requests
 * that name a job (`x-splineskin-job`), as `GET /api/progress/{job}` would tell them.
 */
export async function loadEditor(source, { onProgress } = {}) {
  let memory = null;
  const text = (address, length) => decoder.decode(new Uint8Array(memory.buffer, address, length));
  const imports = {
    splineskin: {
      now: () => performance.now(),
      progress: (job, jobLength, json, jsonLength) => {
        if (onProgress) onProgress(text(job, jobLength), JSON.parse(text(json, jsonLength)));
      },
    },
  };
  const { instance } = await instantiate(source, imports);
  const m = instance.exports;
  memory = m.memory;
  return {
    /** The module's exports (the lower-level calls of crates/splineskin-wasm). */
    exports: m,
    imports,
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
      const answer = JSON.parse(decoder.decode(response.subarray(0, headLength)));
      return {
        status: answer.status,
        contentType: answer.content_type,
        headers: Object.fromEntries(answer.headers),
        body: response.slice(headLength),
      };
    },
  };
}

async function instantiate(source, imports) {
  if (source instanceof WebAssembly.Module) {
    return { instance: await WebAssembly.instantiate(source, imports) };
  }
  if (source instanceof ArrayBuffer || ArrayBuffer.isView(source)) {
    return WebAssembly.instantiate(source, imports);
  }
  const response = source instanceof Response ? source : await fetch(source);
  if (!response.ok) throw new Error(`${response.url}: ${response.status} ${response.statusText}`);
  if (WebAssembly.instantiateStreaming && /wasm/.test(response.headers.get('content-type') ?? '')) {
    return WebAssembly.instantiateStreaming(response, imports);
  }
  return WebAssembly.instantiate(await response.arrayBuffer(), imports);
}
