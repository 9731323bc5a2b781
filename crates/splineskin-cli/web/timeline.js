// The timeline's ruler: seconds along, the scene's keyframes as diamonds, the playhead. A press
// on the ruler goes to that time (dragging scrubs); a press on a diamond selects its keyframe
// and goes to it, dragging it moves the keyframe in time (between its neighbours). Times snap to
// whole frames of the scene's frame rate. What a gesture does is the editor's (`actions`).

/** Seconds shown when there are no keyframes yet. */
const MIN_SPAN = 2;
/** Room shown after the last keyframe, as a fraction of its time. */
const TAIL = 0.25;
/** Half the width of a keyframe diamond, CSS pixels (its pick distance). */
const DIAMOND = 6;

/** `t` rounded to a whole frame at `fps` frames per second, not below 0. */
export function snapToFrame(t, fps) {
  return Math.max(0, Math.round(t * fps)) / fps;
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
    this.span = MIN_SPAN;
    this.state = { animation: null, time: 0, selectedKey: null, fps: 30 };
    this.ticks = document.createElement('div');
    this.ticks.className = 'ticks';
    this.keys = document.createElement('div');
    this.keys.className = 'keys';
    this.playhead = document.createElement('div');
    this.playhead.className = 'playhead';
    element.append(this.ticks, this.keys, this.playhead);
    this.install();
  }

  /** The time under client x, snapped to a frame. */
  timeAt(clientX) {
    const box = this.element.getBoundingClientRect();
    const f = Math.min(1, Math.max(0, (clientX - box.left) / Math.max(1, box.width)));
    return snapToFrame(f * this.span, this.state.fps);
  }

  /** The client x of time t. */
  clientX(t) {
    const box = this.element.getBoundingClientRect();
    return box.left + (t / this.span) * box.width;
  }

  /** Redraws for `state`: { animation, time, selectedKey, fps }. */
  draw(state) {
    this.state = state;
    const keys = state.animation?.keyframes ?? [];
    const last = keys.length ? keys[keys.length - 1].time : 0;
    if (!this.dragging) this.span = Math.max(MIN_SPAN, last * (1 + TAIL), state.time * 1.05);
    const percent = (t) => `${((100 * t) / this.span).toFixed(4)}%`;
    // Ticks every 0.1, 0.5, 1, 5 … s, whichever gives at most about 12 labels.
    const step = [0.1, 0.25, 0.5, 1, 2, 5, 10, 30, 60].find((s) => this.span / s <= 12) ?? 120;
    const ticks = [];
    for (let t = 0; t <= this.span + 1e-9; t += step) {
      ticks.push(`<span style="left:${percent(t)}">${Number(t.toFixed(2))}</span>`);
    }
    this.ticks.innerHTML = ticks.join('');
    this.keys.replaceChildren(
      ...keys.map((key, k) => {
        const d = document.createElement('span');
        d.className = k === state.selectedKey ? 'key selected' : 'key';
        d.dataset.key = k;
        d.dataset.easing = key.easing;
        d.style.left = percent(key.time);
        d.title = `keyframe at ${key.time.toFixed(3)} s (${key.easing} to the next)`;
        return d;
      }),
    );
    this.playhead.style.left = percent(state.time);
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
  }
}
