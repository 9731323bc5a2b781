// Autosave of the Catmull–Clark page: the session (the cage's name and OBJ text, the handles and
// bones with their poses, the keys, the weight family, what is shown, the playhead) in the
// browser's IndexedDB after every edit, offered back after a reload (main.js restores it).
// The OBJ text is stored once, in its own record, and written again only when another cage is
// opened. When the browser refuses to store, the page says so once (`notify`) rather than
// losing the session without a word.

import { openDatabase, transact } from '../idb.js';

/** The database, its one object store and the keys of its two records. */
const DB = { name: 'splineskin-subdiv', version: 1, store: 'session' };
const SESSION_KEY = 'session';
const CAGE_KEY = 'cage';
/** Milliseconds an edit waits for the next before the session is written. */
const DELAY_MS = 150;

/** What is known of the stored state: the OBJ text last written, the failure said, the pending write. */
const stored = { cage: undefined, failureSaid: false, writing: Promise.resolve(), timer: 0 };

/**
 * The session record of `page` (the page's state, main.js) with its OBJ text apart:
 * `{ version, name, level, handles, keys, family, method, selected, time, savedAt }`.
 */
function sessionOf(page) {
  return {
    version: 1,
    name: page.cage.name,
    level: page.cage.surface.level,
    handles: page.handles,
    keys: page.keys,
    family: page.family,
    method: page.method,
    selected: page.selected,
    time: page.time,
    savedAt: new Date().toISOString(),
  };
}

/**
 * Saves `page`'s session soon (edits in a burst are saved once); `notify(message)` says when
 * the browser refuses. `body[data-autosaved]` says when the last save landed, for the tests.
 */
export function autosave(page, notify) {
  if (!page.cage) return;
  clearTimeout(stored.timer);
  stored.timer = setTimeout(() => saveNow(page, notify), DELAY_MS);
}

function saveNow(page, notify) {
  if (!page.cage) return;
  const session = structuredClone(sessionOf(page));
  const cage = page.objText;
  stored.writing = stored.writing.then(async () => {
    try {
      const db = await openDatabase(DB);
      const writes = [[SESSION_KEY, session]];
      if (cage !== stored.cage) writes.push([CAGE_KEY, cage]);
      await transact(db, DB.store, 'readwrite', (store) => writes.forEach(([key, value]) => store.put(value, key)));
      db.close();
      stored.cage = cage;
      document.body.dataset.autosaved = session.savedAt;
    } catch (e) {
      stored.cage = undefined; // write the cage again on the next try
      if (!stored.failureSaid) {
        stored.failureSaid = true;
        notify(`autosave failed (${e?.message ?? e}): this session will not come back after a reload; export the scene to keep it`);
      }
    }
  });
}

/** The saved session with its OBJ text (`obj`), or null when there is none or it cannot be read. */
export async function savedSession() {
  try {
    const db = await openDatabase(DB);
    const [session, cage] = await transact(db, DB.store, 'readonly', (store) => [store.get(SESSION_KEY), store.get(CAGE_KEY)]);
    db.close();
    if (session?.version !== 1 || typeof cage !== 'string') return null;
    stored.cage = cage;
    return { ...session, obj: cage };
  } catch {
    return null;
  }
}
