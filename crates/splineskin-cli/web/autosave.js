// Autosave: the session (the opened file, the scene, the shown time) in the browser's storage
// after every change, offered back after a reload (main.js recovers it).

import { editor, sceneOfOriginal } from './store.js';

/** Where the session is kept in the browser's storage. */
const AUTOSAVE_KEY = 'splineskin-editor-session';

/** Largest opened file kept with the session, characters (storage holds a few MB). */
const AUTOSAVE_MAX_SOURCE = 2_000_000;

/** Saves the session soon (changes in a burst are saved once). */
export function autosave() {
  if (!editor.info || editor.restoring) return;
  clearTimeout(editor.autosaveTimer);
  editor.autosaveTimer = setTimeout(saveSessionNow, 150);
}

/** Saves the session now (`body[data-autosaved]` says when, for the tests). */
function saveSessionNow() {
  if (!editor.info) return;
  // A refined drawing is saved as the drawing as opened with adaptive control points on: the
  // next drag adds them again.
  const opened = editor.adaptive.original?.info ?? editor.info;
  const session = {
    version: 1,
    name: opened.name,
    // The file opened in this page (the server's own drawing needs none).
    source: editor.source && editor.source.length <= AUTOSAVE_MAX_SOURCE ? editor.source : null,
    svgLength: opened.svg.length,
    scene: sceneOfOriginal(),
    adaptive: editor.adaptive.on ? { tolerance: editor.adaptive.tolerance } : null,
    time: editor.time,
    savedAt: new Date().toISOString(),
  };
  try {
    localStorage.setItem(AUTOSAVE_KEY, JSON.stringify(session));
    document.body.dataset.autosaved = session.savedAt;
  } catch {
    // Storage full or refused: the session is simply not kept.
  }
}

/** The saved session, if any and readable. */
export function savedSession() {
  try {
    const session = JSON.parse(localStorage.getItem(AUTOSAVE_KEY) ?? 'null');
    return session?.version === 1 && session.scene ? session : null;
  } catch {
    return null;
  }
}
