// What every browser test shares: the Debian chromium driven by playwright-core, a static file
// server on 127.0.0.1, the splineskin binary, and a folder for screenshots.
//
// Environment:
//   SPLINESKIN_BIN        the splineskin binary (default: debug/splineskin in CARGO_TARGET_DIR,
//                         else in <repo>/target)
//   CHROMIUM              the browser (default: /usr/bin/chromium, the Debian package)
//   BROWSER_TESTS_OUT     keep screenshots in this folder (default: a temporary folder, removed
//                         when the tests pass and kept, with its path printed, when one fails)

import { execFile, spawn } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { readFile } from 'node:fs/promises';
import { createServer } from 'node:http';
import { tmpdir } from 'node:os';
import { dirname, extname, join, resolve, sep } from 'node:path';
import { test } from 'node:test';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

export const REPO = resolve(dirname(fileURLToPath(import.meta.url)), '..');

/**
 * Flags beyond playwright's own: no sandbox (CI runs as root), software rendering, and none of
 * the background traffic (updates, sync, QUIC probes) that otherwise fills a machine without
 * network access with refused connections.
 */
export const CHROMIUM_ARGS = [
  '--headless',
  '--no-sandbox',
  '--disable-gpu',
  '--disable-quic',
  '--no-first-run',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
];

export function chromiumPath() {
  const path = process.env.CHROMIUM || '/usr/bin/chromium';
  if (!existsSync(path)) {
    throw new Error(`${path}: no chromium (apt-get install -y chromium, or set CHROMIUM)`);
  }
  return path;
}

/**
 * Starts chromium with a fresh profile in a temporary folder. Returns the playwright
 * BrowserContext (open pages with `context.newPage()`) and `close()`, which ends the browser and
 * removes the profile. `viewport` is in CSS pixels, drawn at one device pixel each.
 */
export async function launchBrowser({ viewport = { width: 800, height: 600 } } = {}) {
  const profile = mkdtempSync(join(tmpdir(), 'splineskin-chromium-'));
  let context;
  try {
    context = await chromium.launchPersistentContext(profile, {
      executablePath: chromiumPath(),
      headless: true,
      args: CHROMIUM_ARGS,
      viewport,
      deviceScaleFactor: 1,
      timeout: 60_000,
    });
  } catch (error) {
    rmSync(profile, { recursive: true, force: true });
    throw error;
  }
  return {
    context,
    async close() {
      await context.close();
      rmSync(profile, { recursive: true, force: true });
    },
  };
}

const MIME = {
  '.svg': 'image/svg+xml',
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json',
  '.png': 'image/png',
  '.wasm': 'application/wasm',
};

/**
 * Serves the files under `root` on 127.0.0.1 (a free port). Returns `url(path)` for a path
 * relative to `root` and `close()`. Only GET of existing files under `root`; no listings.
 * `isolated`: with the headers that make a page cross-origin isolated (COOP/COEP), as a static
 * build's `_headers` file asks of its host.
 */
export async function serveFolder(root, { isolated = false } = {}) {
  const base = resolve(root);
  const server = createServer(async (req, res) => {
    const path = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
    const file = resolve(base, `.${path}`);
    if (req.method !== 'GET' || !(file === base || file.startsWith(base + sep))) {
      res.writeHead(req.method === 'GET' ? 403 : 405).end();
      return;
    }
    try {
      const body = await readFile(file);
      res.writeHead(200, {
        'content-type': MIME[extname(file).toLowerCase()] ?? 'application/octet-stream',
        'cache-control': 'no-store',
        // What the static build's _headers file asks of a host: a cross-origin-isolated page.
        ...(isolated ? { 'cross-origin-opener-policy': 'same-origin', 'cross-origin-embedder-policy': 'require-corp' } : {}),
      });
      res.end(body);
    } catch {
      res.writeHead(404).end();
    }
  });
  await new Promise((ok, fail) => server.once('error', fail).listen(0, '127.0.0.1', ok));
  const origin = `http://127.0.0.1:${server.address().port}`;
  return {
    origin,
    url: (path) => `${origin}/${path.split(sep).map(encodeURIComponent).join('/')}`,
    close: () => new Promise((ok) => server.close(ok)),
  };
}

export function splineskinBinary() {
  const target = process.env.CARGO_TARGET_DIR ? resolve(REPO, process.env.CARGO_TARGET_DIR) : join(REPO, 'target');
  const path = process.env.SPLINESKIN_BIN || join(target, 'debug', 'splineskin');
  if (!existsSync(path)) {
    throw new Error(`${path}: no splineskin binary (cargo build -p splineskin-cli, or set SPLINESKIN_BIN)`);
  }
  return path;
}

/** Runs `splineskin ARGS…` in `cwd`; resolves to its stderr, rejects with it on failure. */
export function runSplineskin(args, { cwd } = {}) {
  const bin = splineskinBinary();
  return new Promise((ok, fail) => {
    execFile(bin, args, { cwd, maxBuffer: 16 << 20 }, (error, _stdout, stderr) => {
      if (error) {
        fail(new Error(`splineskin ${args.join(' ')} failed (${error.code ?? error.signal}):\n${stderr}`));
      } else {
        ok(stderr);
      }
    });
  });
}

/**
 * A folder for one test file's outputs (screenshots, generated files): BROWSER_TESTS_OUT/name
 * if set (kept), else a temporary folder, removed by `finish()` when nothing failed and kept
 * (its path printed) otherwise.
 *
 * `check(name, [options], body)` declares a test (node:test) whose failure keeps the folder;
 * `failed()` marks a failure outside a test (e.g. in `before`).
 */
export function outputFolder(name) {
  const keep = process.env.BROWSER_TESTS_OUT;
  const path = keep ? resolve(keep, name) : mkdtempSync(join(tmpdir(), `splineskin-${name}-`));
  if (keep) {
    rmSync(path, { recursive: true, force: true });
    mkdirSync(path, { recursive: true });
  }
  let passed = true;
  return {
    path,
    failed() {
      passed = false;
    },
    check(testName, options, body) {
      if (body === undefined) {
        [options, body] = [{}, options];
      }
      test(testName, options, async (t) => {
        try {
          await body(t);
        } catch (error) {
          passed = false;
          throw error;
        }
      });
    },
    finish() {
      if (keep) {
        console.log(`${name}: outputs in ${path}`);
      } else if (passed) {
        rmSync(path, { recursive: true, force: true });
      } else {
        console.log(`${name}: a test failed; outputs kept in ${path}`);
      }
    },
  };
}

/**
 * Starts `splineskin serve --port 0 ARGS…` (the editor) and waits for the URL it prints.
 * Resolves to `{ url, stderr(), close() }`: `stderr()` is what the server wrote so far;
 * `close()` stops it (SIGTERM) and resolves once it has exited.
 */
export function startEditor(args = [], { cwd } = {}) {
  const bin = splineskinBinary();
  const child = spawn(bin, ['serve', '--port', '0', ...args], { cwd, stdio: ['ignore', 'pipe', 'pipe'] });
  let stdout = '';
  let stderr = '';
  child.stderr.on('data', (chunk) => (stderr += chunk));
  const exited = new Promise((ok) => child.once('exit', (code, signal) => ok({ code, signal })));
  return new Promise((ok, fail) => {
    const timer = setTimeout(() => {
      child.kill('SIGTERM');
      fail(new Error(`splineskin serve printed no URL within 60 s:\n${stdout}\n${stderr}`));
    }, 60_000);
    exited.then(({ code, signal }) => {
      clearTimeout(timer);
      fail(new Error(`splineskin serve exited (${code ?? signal}) before printing its URL:\n${stderr}`));
    });
    child.stdout.on('data', (chunk) => {
      stdout += chunk;
      const match = /http:\/\/\S+\//.exec(stdout);
      if (match) {
        clearTimeout(timer);
        ok({
          url: match[0],
          stderr: () => stderr,
          async close() {
            if (child.exitCode === null && child.signalCode === null) child.kill('SIGTERM');
            await exited;
          },
        });
      }
    });
  });
}

/** Runs `splineskin ARGS…`; resolves to its stdout, rejects with its stderr on failure. */
export function splineskinOutput(args, { cwd } = {}) {
  const bin = splineskinBinary();
  return new Promise((ok, fail) => {
    execFile(bin, args, { cwd, maxBuffer: 64 << 20 }, (error, stdout, stderr) => {
      if (error) {
        fail(new Error(`splineskin ${args.join(' ')} failed (${error.code ?? error.signal}):\n${stderr}`));
      } else {
        ok(stdout);
      }
    });
  });
}

/** The numbers of the `d` of every <path> with an id in SVG text `svg`, by id. */
export function pathNumbersById(svg) {
  const result = {};
  for (const [tag] of svg.matchAll(/<path\b[^>]*>/g)) {
    const id = /\sid="([^"]+)"/.exec(tag)?.[1];
    const d = /\sd="([^"]+)"/.exec(tag)?.[1];
    if (id && d) result[id] = (d.match(/[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?/gi) ?? []).map(Number);
  }
  return result;
}

/** The numbers of the `d` of every <path> of SVG text `svg`, in document order. */
export function pathNumbers(svg) {
  return [...svg.matchAll(/<path\b[^>]*\sd="([^"]*)"/g)].map(([, d]) =>
    (d.match(/[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?/gi) ?? []).map(Number));
}

/**
 * The largest difference between the path data of SVG documents `a` and `b` (path by path, in
 * document order), relative to the diagonal of `a`'s path points; throws if their paths do not
 * pair up. `{ paths, relative }`.
 */
export function pathDifference(a, b, name = 'svg') {
  const [pa, pb] = [pathNumbers(a), pathNumbers(b)];
  if (pa.length !== pb.length || pa.length === 0) throw new Error(`${name}: ${pa.length} paths against ${pb.length}`);
  const lo = [Infinity, Infinity];
  const hi = [-Infinity, -Infinity];
  let worst = 0;
  pa.forEach((numbers, p) => {
    if (numbers.length !== pb[p].length) throw new Error(`${name}: path ${p}: ${numbers.length} numbers against ${pb[p].length}`);
    numbers.forEach((v, k) => {
      worst = Math.max(worst, Math.abs(v - pb[p][k]));
      lo[k % 2] = Math.min(lo[k % 2], v);
      hi[k % 2] = Math.max(hi[k % 2], v);
    });
  });
  return { paths: pa.length, relative: worst / Math.hypot(hi[0] - lo[0], hi[1] - lo[1]) };
}

/**
 * Documents `a` and `b` compared whole: the same text once every number is taken out, and the
 * largest difference of their numbers, relative to `size` (a length of the drawing: every
 * number of an SVG is a coordinate, a length or a coefficient of at most that magnitude's
 * order). Throws naming the first place where the text differs.
 */
export function documentDifference(a, b, size, name = 'svg') {
  const NUMBER = /[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?/gi;
  const [ta, tb] = [a.replace(NUMBER, '#'), b.replace(NUMBER, '#')];
  if (ta !== tb) {
    let k = 0;
    while (ta[k] === tb[k]) k++;
    throw new Error(`${name}: the documents differ beyond their numbers at "${ta.slice(Math.max(0, k - 40), k + 40)}" against "${tb.slice(Math.max(0, k - 40), k + 40)}"`);
  }
  const [na, nb] = [a.match(NUMBER) ?? [], b.match(NUMBER) ?? []].map((m) => m.map(Number));
  let worst = 0;
  na.forEach((v, k) => (worst = Math.max(worst, Math.abs(v - nb[k]))));
  return worst / size;
}
