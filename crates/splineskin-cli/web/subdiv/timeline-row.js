// The page's timeline row: Play, the time, the ruler (../timeline.js: seconds, the keys as
// diamonds, the playhead; a click goes to a time, a drag scrubs, a key dragged moves in time),
// "Key pose" at the playhead, the selected key's easing, Delete key and Clear keys. The
// page's state and actions are main.js's, passed in; this module holds none of its own.

import { TimelineRuler, snapToFrame } from '../timeline.js';
import { ANIMATION_FPS } from './exports.js';
import { keyOf, lastTime, poseAt, withKey } from './keys.js';

const $ = (id) => document.getElementById(id);

/**
 * Installs the row. `actions`: `frame()` (the cage and surface for the handles now, drawn),
 * `beforeEdit()`, `edited(message)` (after an edit of the keys), `say(message, options)`.
 * Answers `{ show() }`: redraws the row from `page` (after undo, a restore, a new cage).
 */
export function installTimeline(page, actions) {
  /** Goes to time `t`: the handles take the keys' pose there. */
  const seek = (t) => {
    page.time = t;
    if (page.keys.length > 0) {
      poseAt(page.keys, t, page.handles);
      actions.frame();
    }
    show();
  };
  let moving = false;
  const ruler = new TimelineRuler($('ruler'), {
    seek: (t) => {
      page.selectedKey = null;
      seek(t);
    },
    keyPressed(k) {
      page.selectedKey = k;
      seek(page.keys[k].time);
    },
    keyMoved(k, t, done) {
      if (!moving) {
        actions.beforeEdit();
        page.keys = structuredClone(page.keys);
        moving = true;
      }
      // Between its neighbours, a frame from each.
      const frame = 1 / ANIMATION_FPS;
      const low = k > 0 ? page.keys[k - 1].time + frame : 0;
      const high = k + 1 < page.keys.length ? page.keys[k + 1].time - frame : Infinity;
      page.keys[k].time = Math.min(high, Math.max(low, t));
      page.time = page.keys[k].time;
      show();
      if (done) {
        moving = false;
        actions.edited(`key ${k + 1} moved to ${page.keys[k].time.toFixed(2)} s`);
      }
    },
  });

  function show() {
    const animation = { keyframes: page.keys.map((k) => ({ time: k.time, easing: k.easing ?? 'linear' })) };
    ruler.draw({ animation, time: page.time, selectedKey: page.selectedKey, fps: ANIMATION_FPS });
    $('time-readout').textContent = `${page.time.toFixed(2)} s`;
    const key = page.selectedKey != null ? page.keys[page.selectedKey] : null;
    $('easing').disabled = !key;
    $('easing').value = key?.easing ?? 'linear';
    $('delete-key').disabled = !key;
    $('keys').textContent = page.keys.length ? `${page.keys.length} keys, ${lastTime(page.keys).toFixed(2)} s` : 'no keys';
  }

  $('add-key').addEventListener('click', () => {
    if (!page.rig) {
      actions.say('Add handles first: a key holds their pose.', { error: true });
      return;
    }
    const time = snapToFrame(page.time, ANIMATION_FPS);
    const same = page.keys.find((k) => k.time === time);
    actions.beforeEdit();
    page.keys = withKey(page.keys, keyOf(time, page.handles, same?.easing ?? 'linear'));
    page.selectedKey = page.keys.findIndex((k) => k.time === time);
    show();
    actions.edited(`key at ${time.toFixed(2)} s`);
  });

  $('easing').addEventListener('change', (event) => {
    if (page.selectedKey == null) return;
    actions.beforeEdit();
    page.keys = structuredClone(page.keys);
    page.keys[page.selectedKey].easing = event.target.value;
    show();
    actions.edited(`key ${page.selectedKey + 1}: ${event.target.value} to the next`);
    event.target.blur();
  });

  $('delete-key').addEventListener('click', () => {
    if (page.selectedKey == null) return;
    actions.beforeEdit();
    page.keys = page.keys.filter((_, i) => i !== page.selectedKey);
    page.selectedKey = null;
    show();
    actions.edited('key deleted');
  });

  $('clear-keys').addEventListener('click', () => {
    actions.beforeEdit();
    page.keys = [];
    page.selectedKey = null;
    show();
    actions.edited('keys cleared');
  });

  // Plays the keys from the playhead (from 0 when at the end) to the last, then stops there.
  $('play').addEventListener('click', () => {
    if (page.keys.length < 2 || page.playing) return;
    const end = lastTime(page.keys);
    const from = page.time >= end ? 0 : page.time;
    const start = performance.now();
    let worst = 0;
    const frame = () => {
      const t = Math.min(end, from + (performance.now() - start) / 1000);
      seek(t);
      worst = Math.max(worst, page.frameMs);
      if (t < end) {
        page.playing = requestAnimationFrame(frame);
      } else {
        page.playing = null;
        actions.say(`played ${from.toFixed(2)}–${end.toFixed(2)} s; slowest frame (cage product and surface) ${worst.toFixed(1)} ms`);
      }
    };
    page.playing = requestAnimationFrame(frame);
  });

  return { show };
}
