// What the pointer does on the 3D view: a press on the selected handle's gizmo moves it along
// an axis or turns it about one; on a handle, selects it and drags it (moved in the view's
// plane or turned about the view's axis, by the "Drag" menu); Alt-drag on the surface adds a
// bone between the two points; a click on the surface adds a point handle; otherwise a drag
// orbits (Shift or the right button: pans) and the wheel zooms. The page's state and actions
// are main.js's, passed in (`page`, `actions`); this module holds none.

import { dragInView, orbit, pan, viewAxes, zoom } from './camera.js';
import { axisOf, axisMove, pickGizmo, ringTurn } from './gizmo.js';
import { pickPoint, pickSurface } from './pick.js';
import { turned } from './rig.js';
import { pivots } from './handles.js';

/** Pixels a press may move and still be a click. */
const CLICK_SLOP = 4;
/** Pixels from a handle's dot that pick it. */
const HANDLE_RADIUS = 10;
/** Radians a handle turns per pixel dragged sideways. */
const TURN_PER_PIXEL = 0.01;

/**
 * Installs the gestures on `canvas`. `actions`: `matrix()` (the view's), `size()` ({ width,
 * height } of the canvas), `frame()` (the cage and surface again, drawn), `draw()`,
 * `beforeEdit()`, `select(i)`, `addPoint(p)`, `addBone(a, b)`, `edited(message)` (after a
 * gesture changed the handles), `say(message, options)`.
 */
export function installGestures(canvas, page, actions) {
  const local = (event) => {
    const r = canvas.getBoundingClientRect();
    return [event.clientX - r.left, event.clientY - r.top];
  };
  const size = () => ({ ...actions.size(), radius: HANDLE_RADIUS });

  canvas.addEventListener('pointerdown', (event) => {
    if (!page.cage) return;
    canvas.setPointerCapture(event.pointerId);
    const at = local(event);
    const drag = { x: at[0], y: at[1], startX: at[0], startY: at[1], handle: null, gizmo: null, boneFrom: null };
    drag.panning = event.shiftKey || event.button === 2;
    // A handle's dot first (the gizmo's arrows start under the selected one's), then the gizmo.
    const dot = page.rig ? pickPoint(actions.matrix(), pivots(page.handles), at, size()) : null;
    const part = dot == null && page.rig && page.gizmo ? pickGizmo(actions.matrix(), page.gizmo, at, size()) : null;
    const handle = part ? page.selected : dot;
    if (handle != null) {
      actions.beforeEdit();
      // Edits replace the handles rather than change them, so snapshots stay as they were.
      page.handles = page.handles.map((h) => ({ ...h }));
      Object.assign(drag, { handle, gizmo: part });
      if (!part) actions.select(handle);
    } else if (event.altKey) {
      drag.boneFrom = pickSurface(actions.matrix(), page.positions, page.cage.surface.triangles, at, size());
    }
    page.drag = drag;
  });

  canvas.addEventListener('pointermove', (event) => {
    const drag = page.drag;
    if (!drag) return;
    const at = local(event);
    const from = [drag.x, drag.y];
    [drag.x, drag.y] = at;
    if (drag.boneFrom) return;
    if (drag.handle != null) {
      dragHandle(page.handles[drag.handle], drag.gizmo, from, at);
      actions.frame();
      return;
    }
    if (drag.panning) pan(page.camera, at[0] - from[0], at[1] - from[1], canvas.clientHeight);
    else orbit(page.camera, at[0] - from[0], at[1] - from[1]);
    actions.draw();
  });

  /** Moves or turns handle `h` by a drag from screen point `from` to `to` (on gizmo `part`, if any). */
  function dragHandle(h, part, from, to) {
    const centre = h.rest.map((r, k) => r + h.offset[k]);
    const s = size();
    if (part?.kind === 'move') {
      const move = axisMove(actions.matrix(), centre, page.gizmoSize, part.axis, from, to, s);
      h.offset = h.offset.map((o, k) => o + move[k]);
    } else if (part?.kind === 'turn') {
      const forward = viewAxes(page.camera)[2];
      const angle = ringTurn(actions.matrix(), centre, part.axis, forward, from, to, s);
      h.rotation = turned(h.rotation, axisOf(part.axis), angle);
    } else if (page.mode === 'turn') {
      h.rotation = turned(h.rotation, viewAxes(page.camera)[2], -TURN_PER_PIXEL * (to[0] - from[0]));
    } else {
      const move = dragInView(page.camera, centre, to[0] - from[0], to[1] - from[1], canvas.clientHeight);
      h.offset = h.offset.map((o, k) => o + move[k]);
    }
  }

  canvas.addEventListener('pointerup', (event) => {
    const drag = page.drag;
    page.drag = null;
    if (!drag) return;
    const at = local(event);
    const still = Math.hypot(at[0] - drag.startX, at[1] - drag.startY) < CLICK_SLOP;
    if (drag.boneFrom && !still) {
      const end = pickSurface(actions.matrix(), page.positions, page.cage.surface.triangles, at, size());
      if (end) actions.addBone(drag.boneFrom, end);
      else actions.say('A bone ends on the surface: release the drag over it.', { error: true });
    } else if (drag.handle != null && !still) {
      const how = drag.gizmo ? (drag.gizmo.kind === 'move' ? `moved along ${'xyz'[drag.gizmo.axis]}` : `turned about ${'xyz'[drag.gizmo.axis]}`) : page.mode === 'turn' ? 'turned' : 'moved';
      actions.edited(`handle ${drag.handle + 1} ${how}`);
    } else if (still && !drag.panning) {
      click(at);
    }
  });

  /** A click at `at`: picks a handle, or adds a point handle where the surface is. */
  function click(at) {
    const hit = pickPoint(actions.matrix(), pivots(page.handles), at, size());
    if (hit != null) {
      actions.select(hit);
      return;
    }
    const point = pickSurface(actions.matrix(), page.positions, page.cage.surface.triangles, at, size());
    if (point) actions.addPoint(point);
  }

  canvas.addEventListener('pointercancel', () => {
    page.drag = null;
  });
  canvas.addEventListener('contextmenu', (event) => event.preventDefault());
  canvas.addEventListener('wheel', (event) => {
    if (!page.cage) return;
    event.preventDefault();
    zoom(page.camera, event.deltaY);
    actions.draw();
  }, { passive: false });
}
