// The keyboard: the canvas's shortcuts (undo, delete, select all, key, frame steps, arrow
// nudges), which work whatever has the focus except a text field, and the keyboard given back
// by the menus after a choice made with the mouse.

import * as edits from './edits.js';
import { seek } from './playback.js';
import { editor, fps } from './store.js';

/** Arrow keys and the move each gives a selected pin, in screen pixels (Shift: ten times). */
const NUDGES = { arrowleft: [-1, 0], arrowright: [1, 0], arrowup: [0, -1], arrowdown: [0, 1] };

/**
 * The keyboard shortcuts, and the keyboard given back by the menus: after a choice made with
 * the mouse a menu lets go of the focus, and a menu with the focus never takes the canvas's
 * keys (arrows, letters), so a key never changes a setting silently.
 */
export function wireKeys() {
  let pointer = false;
  window.addEventListener('pointerdown', () => (pointer = true), true);
  window.addEventListener('keydown', () => (pointer = false), true);
  // A menu chosen with the mouse lets go of the focus (the shortcuts reach the page from any
  // other control already, and a checkbox keeps it for keyboard users).
  for (const menu of document.querySelectorAll('select')) {
    menu.addEventListener('change', () => pointer && menu.blur());
  }
  window.addEventListener('keydown', shortcut, true);
}

/** What a key does on the canvas, whatever has the focus except a text field. */
function shortcut(event) {
  if (isTextField(event.target)) return;
  const key = event.key.toLowerCase();
  // A closed menu would step its entry (arrows, Home, End, a letter): the canvas takes those
  // keys. Alt+arrow, Enter and Space still open it.
  const menuStep = event.target instanceof HTMLSelectElement && !event.altKey && (key in NUDGES || ['home', 'end', 'pageup', 'pagedown'].includes(key) || key.length === 1);
  if (menuStep && key !== ' ') event.preventDefault();
  if (key in NUDGES && !event.altKey && !event.ctrlKey && !event.metaKey) {
    if (!editor.view || !editor.selection.length) return;
    event.preventDefault();
    const step = (event.shiftKey ? 10 : 1) * editor.view.unitsPerPixel();
    edits.nudge(NUDGES[key].map((v) => v * step));
  } else if ((event.ctrlKey || event.metaKey) && key === 'z') {
    event.preventDefault();
    event.shiftKey ? edits.redo() : edits.undo();
  } else if ((event.ctrlKey || event.metaKey) && key === 'y') {
    event.preventDefault();
    edits.redo();
  } else if (key === 'delete' || key === 'backspace') {
    event.preventDefault();
    if (editor.selection.length) edits.deleteHandles();
    else if (editor.selectedKey !== null) edits.deleteKey();
  } else if (key === 'escape') {
    edits.deselect();
  } else if ((event.ctrlKey || event.metaKey) && key === 'a') {
    event.preventDefault();
    const all = editor.scene.handles.map((_, i) => i);
    edits.select(all, all.length ? all[all.length - 1] : null);
  } else if (key === 'k' && !event.ctrlKey && !event.metaKey) {
    edits.keyShortcut();
  } else if ((key === ',' || key === '.') && !event.ctrlKey && !event.metaKey) {
    seek(Math.max(0, Math.round(editor.time * fps() + (key === '.' ? 1 : -1)) / fps()));
  }
}

/** Whether keys pressed in `target` type text (so shortcuts leave them alone). */
function isTextField(target) {
  if (target instanceof HTMLTextAreaElement || target?.isContentEditable) return true;
  if (!(target instanceof HTMLInputElement)) return false;
  return ['text', 'search', 'email', 'url', 'password', 'tel', 'number'].includes(target.type);
}
