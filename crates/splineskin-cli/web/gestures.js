// Pointer gestures on the drawing: click on the art to add a handle (Alt-click: anywhere;
// on empty canvas: deselect; or change the junction under the pointer), press a handle to
// select it (Shift-click: add it to the selection or take it out), drag on the canvas to select
// the handles in a box (Shift: add them), drag a handle to translate it with every selected
// handle, Shift-drag or the ring to rotate them, Alt-drag or the square to scale them (about
// the handle, or the selection's centre when several are selected); wheel to zoom, Space- or
// middle-drag to pan. What a gesture does to the scene is the editor's business (`actions`).

import * as affine from './affine.js';
import { HANDLE_RADIUS, KNOB_SIZE, RING_RADIUS, posedHandles } from './view.js';

/** Pointer travel, in CSS pixels, below which a press is a click. */
const CLICK_SLOP = 3;
/** Rotation per pixel of horizontal travel of a Shift-drag started on a handle: 0.5°. */
const RADIANS_PER_PIXEL = Math.PI / 360;
/** Horizontal travel that doubles the scale in an Alt-drag started on a handle. */
const PIXELS_PER_DOUBLING = 100;
/** Smallest scale factor a scale drag sets (a map must stay invertible). */
const MIN_SCALE = 0.05;
/** Zoom per unit of wheel travel (a wheel notch of 100 units zooms by about 1.2). */
const ZOOM_PER_WHEEL_UNIT = 0.0018;
/** Pick distances beyond a marker's drawn size, CSS pixels. */
const HANDLE_SLOP = 3;
const KNOB_SLOP = 2;
const RING_HALF_WIDTH = 4;

/**
 * The centre the rotate and scale widgets of a selection turn about: the handle itself, or
 * the mean of the selected handles' posed positions.
 */
export function selectionCentre(scene, selection) {
  const posed = posedHandles(scene);
  const points = selection.map((i) => posed[i]).filter(Boolean);
  if (!points.length) return null;
  const n = points.length;
  return [points.reduce((s, p) => s + p[0], 0) / n, points.reduce((s, p) => s + p[1], 0) / n];
}

/**
 * Listens on `element` (holding `editor.view`'s drawing). `editor.selection` is the selected
 * handles (indices), `editor.selected` the one last pressed (null: none);
 * `editor.translateOnly()` says whether handles only move (an operator's: no rotate or scale).
 * `actions`:
 * - `select(selection, primary)`: the selection changed to `selection`, `primary` in it or null;
 * - `posed(maps)`: a drag gives each handle i of `maps` ([[i, map], …]) its map (called every
 *   pointer move);
 * - `dragged(before, handles)`: a drag of `handles` ended; `before` is the scene as it was when
 *   it started;
 * - `clicked(p, client, altKey)`: a click (no drag) on no handle, at drawing point p, client
 *   point `client`, with Alt held or not;
 * - `boxChanged(box)`: the selection box being dragged, [x0, y0, x1, y1] in drawing units, or
 *   null once it is released;
 * - `viewChanged()`: the shown frame was zoomed or panned.
 */
export function installGestures(element, editor, actions) {
  let gesture = null;
  let spaceHeld = false;

  const hitHandle = (p) => {
    const u = editor.view.unitsPerPixel();
    let best = null;
    let bestDistance = (HANDLE_RADIUS + HANDLE_SLOP) * u;
    posedHandles(editor.scene).forEach(([x, y], i) => {
      const d = Math.hypot(x - p[0], y - p[1]);
      if (d <= bestDistance) {
        best = i;
        bestDistance = d;
      }
    });
    return best;
  };

  /** 'knob', 'ring' or null: the widgets of the selection under p. */
  const hitWidget = (p) => {
    if (editor.selected === null || editor.translateOnly()) return null;
    const centre = selectionCentre(editor.scene, editor.selection);
    if (!centre) return null;
    const u = editor.view.unitsPerPixel();
    const [cx, cy] = centre;
    const knob = Math.max(Math.abs(p[0] - (cx + RING_RADIUS * u)), Math.abs(p[1] - cy));
    if (knob <= (KNOB_SIZE / 2 + KNOB_SLOP) * u) return 'knob';
    if (Math.abs(Math.hypot(p[0] - cx, p[1] - cy) - RING_RADIUS * u) <= RING_HALF_WIDTH * u) return 'ring';
    return null;
  };

  element.addEventListener('pointerdown', (event) => {
    if (!editor.view) return;
    if (event.button === 1 || (event.button === 0 && spaceHeld)) {
      gesture = { pan: [event.clientX, event.clientY] };
      editor.view.root.setPointerCapture(event.pointerId);
      event.preventDefault();
      return;
    }
    if (event.button !== 0) return;
    const p = editor.view.toUser(event.clientX, event.clientY);
    const widget = hitWidget(p);
    const handle = widget ? editor.selected : hitHandle(p);
    gesture = { start: p, client: [event.clientX, event.clientY], moved: false, handle, widget, shift: event.shiftKey };
    if (handle !== null) {
      if (editor.translateOnly()) gesture.mode = 'translate';
      else if (widget === 'knob' || (!widget && (event.altKey || event.ctrlKey))) gesture.mode = 'scale';
      else if (widget === 'ring' || event.shiftKey) gesture.mode = 'rotate';
      else gesture.mode = 'translate';
      gesture.before = structuredClone(editor.scene);
      // A handle of the selection moves the selection with it; another one moves alone (and
      // becomes the selection, unless Shift is held: a Shift-click adds it on release).
      const inSelection = editor.selection.includes(handle);
      gesture.handles = inSelection ? [...editor.selection] : [handle];
      gesture.maps = gesture.handles.map((i) => [...editor.scene.pose[i]]);
      const own = affine.apply(editor.scene.pose[handle], editor.scene.handles[handle]);
      gesture.centre = gesture.handles.length > 1 ? selectionCentre(editor.scene, gesture.handles) : own;
      gesture.own = own;
      if (!inSelection && !event.shiftKey) actions.select([handle], handle);
      else if (inSelection && editor.selected !== handle && !widget) actions.select(editor.selection, handle);
    }
    editor.view.root.setPointerCapture(event.pointerId);
    event.preventDefault();
  });

  element.addEventListener('pointermove', (event) => {
    if (!gesture) return;
    if (gesture.pan) {
      editor.view.pan(event.clientX - gesture.pan[0], event.clientY - gesture.pan[1]);
      gesture.pan = [event.clientX, event.clientY];
      actions.viewChanged();
      return;
    }
    const [cx0, cy0] = gesture.client;
    if (Math.hypot(event.clientX - cx0, event.clientY - cy0) > CLICK_SLOP) gesture.moved = true;
    if (!gesture.moved) return;
    const p = editor.view.toUser(event.clientX, event.clientY);
    const s = gesture.start;
    if (gesture.handle === null) {
      // A drag on the canvas: the selection box.
      gesture.box = [Math.min(s[0], p[0]), Math.min(s[1], p[1]), Math.max(s[0], p[0]), Math.max(s[1], p[1])];
      actions.boxChanged(gesture.box);
      return;
    }
    // A Shift-drag (a rotation) of a handle outside the selection selects it.
    if (!editor.selection.includes(gesture.handle)) actions.select([gesture.handle], gesture.handle);
    const c = gesture.centre;
    // A rotation or scale that starts on a handle has no lever: horizontal travel sets it. One
    // that starts away from it (the ring, the square) follows the pointer about the centre.
    const pixels = 1 / editor.view.unitsPerPixel();
    const o = gesture.own;
    const onHandle = Math.hypot(s[0] - o[0], s[1] - o[1]) * pixels <= HANDLE_RADIUS + HANDLE_SLOP;
    const travel = event.clientX - cx0;
    let M;
    if (gesture.mode === 'translate') {
      M = affine.translation(p[0] - s[0], p[1] - s[1]);
    } else if (gesture.mode === 'rotate') {
      const angle = onHandle
        ? travel * RADIANS_PER_PIXEL
        : Math.atan2(p[1] - c[1], p[0] - c[0]) - Math.atan2(s[1] - c[1], s[0] - c[0]);
      M = affine.rotationAbout(angle, c);
    } else {
      const d0 = Math.hypot(s[0] - c[0], s[1] - c[1]);
      const factor = onHandle ? 2 ** (travel / PIXELS_PER_DOUBLING) : Math.hypot(p[0] - c[0], p[1] - c[1]) / d0;
      M = affine.scaleAbout(Math.max(MIN_SCALE, factor), c);
    }
    actions.posed(gesture.handles.map((i, k) => [i, affine.compose(M, gesture.maps[k])]));
  });

  element.addEventListener('pointerup', (event) => {
    if (!gesture) return;
    const g = gesture;
    gesture = null;
    if (g.pan) return;
    if (g.handle !== null) {
      if (g.moved) {
        actions.dragged(g.before, g.handles);
      } else if (g.shift && !g.widget) {
        // Shift-click: the handle joins the selection, or leaves it.
        const has = editor.selection.includes(g.handle);
        const selection = has ? editor.selection.filter((i) => i !== g.handle) : [...editor.selection, g.handle];
        actions.select(selection, has ? (selection.length ? selection[selection.length - 1] : null) : g.handle);
      } else if (!g.widget && editor.selection.length > 1) {
        // A click on one handle of several selected selects it alone.
        actions.select([g.handle], g.handle);
      }
      return;
    }
    if (g.box) {
      actions.boxChanged(null);
      const [x0, y0, x1, y1] = g.box;
      const inside = [];
      posedHandles(editor.scene).forEach(([x, y], i) => {
        if (x >= x0 && x <= x1 && y >= y0 && y <= y1) inside.push(i);
      });
      const selection = g.shift ? [...new Set([...editor.selection, ...inside])] : inside;
      actions.select(selection, selection.length ? selection[selection.length - 1] : null);
      return;
    }
    if (!g.moved) {
      actions.clicked(editor.view.toUser(event.clientX, event.clientY), [event.clientX, event.clientY], event.altKey);
    }
  });

  element.addEventListener('pointercancel', () => {
    if (gesture?.box) actions.boxChanged(null);
    gesture = null;
  });

  element.addEventListener(
    'wheel',
    (event) => {
      if (!editor.view) return;
      event.preventDefault();
      editor.view.zoom(Math.exp(-event.deltaY * ZOOM_PER_WHEEL_UNIT), event.clientX, event.clientY);
      actions.viewChanged();
    },
    { passive: false },
  );

  window.addEventListener('keydown', (event) => {
    // Space pans whatever has the focus (a menu included), except a field that types text.
    if (event.key === ' ' && !(event.target instanceof HTMLInputElement && event.target.type !== 'checkbox')) {
      spaceHeld = true;
      event.preventDefault();
    }
  });
  window.addEventListener('keyup', (event) => {
    if (event.key === ' ') spaceHeld = false;
  });
}
