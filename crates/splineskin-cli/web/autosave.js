// Autosave: the session (the opened file, the scene, the shown time) in the browser's
// IndexedDB after every change, offered back after a reload (main.js recovers it).
//
// The opened file is stored once, in its own record, and written again only when another file
// is opened: a drag saves the scene alone, however large the drawing. When the browser refuses
// to store (no IndexedDB, storage full, a private window's limits), the page says so once in
// the notice box instead of losing the session without a word.

import { openDatabase as openStore, transact as transactIn } from './idb.js';
import { editor, sceneOfOriginal } from './store.js';
import { showNotice } from './messages.js';

/** The database, its one object store, and the keys of its two records. */
const DB = { name: 'splineskin-editor', version: 1, store: 'session' };
const SESSION_KEY = 'session';
const SOURCE_KEY = 'source';

/** Where sessions were kept before IndexedDB (read once, then removed). */
const LEGACY_KEY = 'splineskin-editor-session';

/** What this module knows of the stored state: the source last written and the failure shown. */
const stored = { source: undefined, failureShown: false, writing: Promise.resolve() };

/** Saves the session soon (changes in a burst are saved once). */
export function autosave() {
  if (!editor.info || editor.restoring) return;
  clearTimeout(editor.autosaveTimer);
  editor.autosaveTimer = setTimeout(saveSessionNow, 150);
}

/** The session record as saved now (the opened file apart). */
function sessionRecord() {
  // A refined drawing is saved as the drawing as opened with adaptive control points on: the
  // next drag adds them again.
  const opened = editor.adaptive.original?.info ?? editor.info;
  return {
    version: 2,
    name: opened.name,
    // Whether the file opened in this page is stored (the server's own drawing needs none).
    hasSource: editor.source != null,
    svgLength: opened.svg.length,
    scene: sceneOfOriginal(),
    adaptive: editor.adaptive.on ? { tolerance: editor.adaptive.tolerance } : null,
    time: editor.time,
    savedAt: new Date().toISOString(),
  };
}

/** Saves the session now (`body[data-autosaved]` says when, for the tests). */
function saveSessionNow() {
  if (!editor.info) return;
  const session = sessionRecord();
  const source = editor.source ?? null;
  stored.writing = stored.writing.then(async () => {
    try {
      const db = await openDatabase();
      const writes = [[SESSION_KEY, session]];
      if (source !== stored.source) writes.push([SOURCE_KEY, source]);
      await transact(db, 'readwrite', (store) => writes.forEach(([key, value]) => store.put(value, key)));
      db.close();
      stored.source = source;
      document.body.dataset.autosaved = session.savedAt;
      delete document.body.dataset.autosaveFailed;
    } catch (e) {
      saveFailed(e);
    }
  });
}

/** Says once that the session is not being kept (and why), until a save succeeds again. */
function saveFailed(error) {
  document.body.dataset.autosaveFailed = '1';
  stored.source = undefined; // write the file again on the next try
  if (stored.failureShown) return;
  stored.failureShown = true;
  const why = error?.message ?? String(error);
  showNotice(`autosave failed (${why}): this session will not come back after a reload; use Save scene to keep it`);
}

/** The saved session with its opened file (`session.source`), if any and readable. */
export async function savedSession() {
  const legacy = legacySession();
  try {
    const db = await openDatabase();
    const [session, source] = await transact(db, 'readonly', (store) => [store.get(SESSION_KEY), store.get(SOURCE_KEY)]);
    db.close();
    if (session?.version === 2 && session.scene) {
      stored.source = source ?? null;
      return { ...session, source: session.hasSource ? (source ?? null) : null };
    }
  } catch {
    // No IndexedDB here: the first save says so.
  }
  return legacy;
}

/** A session saved by an earlier version of the page in localStorage (removed once read). */
function legacySession() {
  try {
    const session = JSON.parse(localStorage.getItem(LEGACY_KEY) ?? 'null');
    localStorage.removeItem(LEGACY_KEY);
    return session?.version === 1 && session.scene ? session : null;
  } catch {
    return null;
  }
}

/** Opens (creating on first use) the editor's database. */
const openDatabase = () => openStore(DB);

/** One transaction on the editor's store (idb.js `transact`). */
const transact = (db, mode, body) => transactIn(db, DB.store, mode, body);
