// The timeline's ruler: seconds along, the scene's keyframes as diamonds, the playhead. A press
// on the ruler goes to that time (dragging scrubs); a press on a diamond selects its keyframe
// and goes to it, dragging it moves the keyframe in time (between its neighbours). Times snap to
// whole frames of the scene's frame rate. The wheel zooms the ruler about the pointer (a
// double-click fits it to the animation again). What a gesture does is the editor's (`actions`).

/** Seconds shown when there are no keyframes yet. */
const MIN_SPAN = 2;
/** Room shown after the last keyframe and after the shown time: a fraction of it, at least a second. */
const TAIL = 0.25;
const MIN_TAIL = 1;
/** Half the width of a keyframe diamond, CSS pixels (its pick distance). */
const DIAMOND = 6;
/** Pixels at each end of the ruler before 0 s and after its last second (room for a diamond). */
const INSET = 8;
/** Zoom per wheel unit (a notch is about 100 units: 1.2 times). */
const ZOOM_PER_WHEEL_UNIT = Math.log(1.2) / 100;
/** The shortest and longest span the wheel zooms to, seconds. */
const ZOOM_LIMITS = [0.2, 3600];

/** `t` rounded to a whole frame at `fps` frames per second, not below 0. */
export function snapToFrame(t, fps) {
  return Math.max(0, Math.round(t * fps)) / fps;
}

/**
 * The span the ruler fits to an animation whose last keyframe is at `last` with the shown time
 * `time`: both, and room after them to click a later time (so a click at the end of a long
 * animation reaches a second further each time).
 */
export function fittedSpan(last, time) {
  const room = (t) => t + Math.max(MIN_TAIL, TAIL * t);
  return Math.max(MIN_SPAN, room(last), time > 0 ? room(time) : 0);
}

export class TimelineRuler {
  /**
   * Draws in `element` (an empty block); `actions`:
   * - `seek(t)`: go to time t (each move of a scrub);
   * - `keyPressed(k)`: keyframe k was pressed (selected, the time goes to it);
   * - `keyMoved(k, t, done)`: keyframe k is dragged to time t; `done` on release.
   */
  constructor(element, actions) {
    this.element = element;
    this.actions = actions;
    /** The seconds shown: from `start`, `span` long; `zoomed` while the wheel chose them; the time last shown. */
    this.window = { start: 0, span: MIN_SPAN, zoomed: false, time: 0 };
    this.state = { animation: null, time: 0, selectedKey: null, fps: 30 };
    this.ticks = document.createElement('div');
    this.ticks.className = 'ticks';
    this.keys = document.createElement('div');
    this.keys.className = 'keys';
    this.playhead = document.createElement('div');
    this.playhead.className = 'playhead';
    element.append(this.ticks, this.keys, this.playhead);
    this.install();
    // Positions are in pixels: a new width (the window resized, the row rewrapped) redraws.
    new ResizeObserver(() => this.draw(this.state)).observe(element);
  }

  /** The ruler's seconds on screen: client x of its first second, pixels per second. */
  scale() {
    const box = this.element.getBoundingClientRect();
    const width = Math.max(1, box.width - 2 * INSET);
    return { left: box.left + INSET, perSecond: width / this.window.span, width };
  }

  /** The time under client x (its ends and beyond: the first and last time shown), snapped to a frame. */
  timeAt(clientX) {
    const { left, width } = this.scale();
    const f = Math.min(1, Math.max(0, (clientX - left) / width));
    return snapToFrame(this.window.start + f * this.window.span, this.state.fps);
  }

  /** The client x of time t. */
  clientX(t) {
    const { left, perSecond } = this.scale();
    return left + (t - this.window.start) * perSecond;
  }

  /**
   * Fits the window to the state's animation and time, unless the wheel chose it; then a new
   * shown time outside it (playback, the frame keys) scrolls it into view.
   */
  fitWindow(last, time) {
    const w = this.window;
    if (!w.zoomed) {
      w.start = 0;
      w.span = fittedSpan(last, time);
    } else if (time !== w.time && (time < w.start || time > w.start + w.span)) {
      w.start = Math.max(0, time - w.span / 2);
    }
    w.time = time;
  }

  /** Zooms by `factor` about client x (the time under it stays put). */
  zoom(factor, clientX) {
    const w = this.window;
    const t = this.window.start + ((clientX - this.scale().left) / this.scale().width) * w.span;
    const span = Math.min(ZOOM_LIMITS[1], Math.max(ZOOM_LIMITS[0], w.span * factor));
    w.start = Math.max(0, t - (t - w.start) * (span / w.span));
    w.span = span;
    w.zoomed = true;
    this.draw(this.state);
  }

  /** Redraws for `state`: { animation, time, selectedKey, fps }. */
  draw(state) {
    this.state = state;
    const keys = state.animation?.keyframes ?? [];
    if (!this.dragging) this.fitWindow(keys.length ? keys[keys.length - 1].time : 0, state.time);
    const { start, span } = this.window;
    const { perSecond } = this.scale();
    const left = (t) => `${(INSET + (t - start) * perSecond).toFixed(2)}px`;
    const shown = (t) => t >= start - 1e-9 && t <= start + span + 1e-9;
    this.ticks.replaceChildren(...this.tickTimes().map((t) => {
      const tick = document.createElement('span');
      tick.style.left = left(t);
      tick.textContent = String(Number(t.toFixed(2)));
      return tick;
    }));
    this.keys.replaceChildren(
      ...keys.flatMap((key, k) => {
        if (!shown(key.time)) return [];
        const d = document.createElement('span');
        d.className = k === state.selectedKey ? 'key selected' : 'key';
        d.dataset.key = k;
        d.dataset.easing = key.easing;
        d.style.left = left(key.time);
        d.title = `keyframe at ${key.time.toFixed(3)} s (${key.easing} to the next)`;
        return [d];
      }),
    );
    this.playhead.hidden = !shown(state.time);
    this.playhead.style.left = left(state.time);
  }

  /** The labelled times: every 0.1, 0.5, 1, 5 … s, whichever gives about 8 labels per 300 px. */
  tickTimes() {
    const { start, span } = this.window;
    const labels = Math.max(4, Math.min(40, (8 * this.scale().width) / 300));
    const step = [0.1, 0.25, 0.5, 1, 2, 5, 10, 30, 60, 120, 300, 600].find((s) => span / s <= labels) ?? 1200;
    const times = [];
    for (let t = Math.ceil(start / step - 1e-9) * step; t <= start + span - 0.4 * step; t += step) times.push(t);
    return times;
  }

  install() {
    let gesture = null;
    this.element.addEventListener('pointerdown', (event) => {
      if (event.button !== 0) return;
      const keys = this.state.animation?.keyframes ?? [];
      // The diamond under the pointer, if any (the nearest within its half-width).
      let key = null;
      let best = DIAMOND + 1;
      keys.forEach((k, i) => {
        const d = Math.abs(this.clientX(k.time) - event.clientX);
        if (d < best) {
          key = i;
          best = d;
        }
      });
      this.element.setPointerCapture(event.pointerId);
      event.preventDefault();
      if (key !== null) {
        gesture = { key, x: event.clientX, moved: false };
        this.actions.keyPressed(key);
      } else {
        gesture = { scrub: true };
        this.actions.seek(this.timeAt(event.clientX));
      }
      this.dragging = true;
    });
    this.element.addEventListener('pointermove', (event) => {
      if (!gesture) return;
      if (gesture.scrub) {
        this.actions.seek(this.timeAt(event.clientX));
        return;
      }
      if (Math.abs(event.clientX - gesture.x) > 2) gesture.moved = true;
      if (gesture.moved) this.actions.keyMoved(gesture.key, this.timeAt(event.clientX), false);
    });
    const end = (event) => {
      if (!gesture) return;
      const g = gesture;
      gesture = null;
      this.dragging = false;
      if (g.key !== undefined && g.moved) this.actions.keyMoved(g.key, this.timeAt(event.clientX), true);
      this.draw(this.state);
    };
    this.element.addEventListener('pointerup', end);
    this.element.addEventListener('pointercancel', end);
    this.element.addEventListener(
      'wheel',
      (event) => {
        event.preventDefault();
        this.zoom(Math.exp(event.deltaY * ZOOM_PER_WHEEL_UNIT), event.clientX);
      },
      { passive: false },
    );
    this.element.addEventListener('dblclick', () => {
      this.window.zoomed = false;
      this.draw(this.state);
    });
  }
}
