// Pointer gestures on the drawing: click on the art to add a handle (Alt-click: anywhere;
// on empty canvas: deselect; or change the junction under the pointer), press a handle to select it, drag it to translate, Shift-drag or its ring to rotate
// about it, Alt-drag or its square to scale about it; wheel to zoom, Space- or middle-drag to
// pan. What a gesture does to the scene is the editor's business (`actions`).

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
 * Listens on `element` (holding `editor.view`'s drawing); `editor.translateOnly()` says whether
 * handles only move (an operator's: no rotate or scale). `actions`:
 * - `selected(i)`: handle i was pressed and is now the selected one;
 * - `posed(i, map)`: a drag gives handle i the map `map` (called every pointer move);
 * - `dragged(before)`: a drag ended; `before` is the scene as it was when it started;
 * - `clicked(p, client, altKey)`: a click (no drag) on no handle, at drawing point p, client
 *   point `client`, with Alt held or not;
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

  /** 'knob', 'ring' or null: the widgets of the selected handle under p. */
  const hitWidget = (p) => {
    if (editor.selected === null || editor.translateOnly()) return null;
    const u = editor.view.unitsPerPixel();
    const [cx, cy] = posedHandles(editor.scene)[editor.selected];
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
    gesture = { start: p, client: [event.clientX, event.clientY], moved: false, handle };
    if (handle !== null) {
      if (editor.translateOnly()) gesture.mode = 'translate';
      else if (widget === 'knob' || (!widget && (event.altKey || event.ctrlKey))) gesture.mode = 'scale';
      else if (widget === 'ring' || event.shiftKey) gesture.mode = 'rotate';
      else gesture.mode = 'translate';
      gesture.before = structuredClone(editor.scene);
      gesture.map = [...editor.scene.pose[handle]];
      gesture.centre = affine.apply(gesture.map, editor.scene.handles[handle]);
      if (editor.selected !== handle) actions.selected(handle);
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
    if (gesture.handle === null || !gesture.moved) return;
    const p = editor.view.toUser(event.clientX, event.clientY);
    const s = gesture.start;
    const c = gesture.centre;
    // A rotation or scale that starts on the handle itself has no lever: horizontal travel
    // sets it. One that starts away from it (the ring, the square) follows the pointer about it.
    const pixels = 1 / editor.view.unitsPerPixel();
    const onHandle = Math.hypot(s[0] - c[0], s[1] - c[1]) * pixels <= HANDLE_RADIUS + HANDLE_SLOP;
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
    actions.posed(gesture.handle, affine.compose(M, gesture.map));
  });

  element.addEventListener('pointerup', (event) => {
    if (!gesture) return;
    const g = gesture;
    gesture = null;
    if (g.pan) return;
    if (g.handle !== null) {
      if (g.moved) actions.dragged(g.before);
      return;
    }
    if (!g.moved) {
      actions.clicked(editor.view.toUser(event.clientX, event.clientY), [event.clientX, event.clientY], event.altKey);
    }
  });

  element.addEventListener('pointercancel', () => (gesture = null));

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
    if (event.key === ' ' && !(event.target instanceof HTMLInputElement || event.target instanceof HTMLSelectElement)) {
      spaceHeld = true;
      event.preventDefault();
    }
  });
  window.addEventListener('keyup', (event) => {
    if (event.key === ' ') spaceHeld = false;
  });
}
