// An operator that follows the user (POST /api/defops/{id}/follow, crates/splineskin-editor/
// src/defop_routes.rs): an operator is trained on configurations near the rest; dragged far
// from them it extrapolates (pins slide, art leaves its handle). While a drag moves the handles,
// the page sends their configuration Q; when no training sample has every handle within the
// sampling radius of Q's (the server's test, `trained_distance > reach`), the server solves the
// ground truth at Q and about it, starting from the operator's prediction, refits, joins, and
// answers a new operator. On release it adds Q itself (`settle`), so the drawing comes to rest
// on the ground truth's fit. One request is in flight at a time; moves made meanwhile are sent
// when it returns (only the latest configuration matters).
//
// The swap does not jump: the new rig is blended in from the old over BLEND_MS,
//   points = (1 − s) · old(Q) + s · new(Q),   s = smoothstep(elapsed / BLEND_MS),
// both evaluated at the same Q every frame. Each operator interpolates the handles at every Q
// (the fit's constraint), and so does any blend of two.

/** Milliseconds over which a followed operator replaces the one before. */
export const BLEND_MS = 200;

/**
 * Blends `rig.deform` from `from` (another rig of the same drawing and handles) over BLEND_MS
 * from now. Allocates its scratch once here: frames allocate nothing.
 */
export function blendIn(rig, from, now = performance.now()) {
  const own = rig.deform.bind(rig);
  const scratch = new Float64Array(2 * rig.nPoints);
  rig.blendingUntil = now + BLEND_MS;
  // Done (in time, or settled early by endBlend): the new rig alone from now on.
  rig.endBlend = () => {
    rig.deform = own;
    rig.blendingUntil = 0;
  };
  rig.deform = (pose, out) => {
    own(pose, out);
    const left = rig.blendingUntil - performance.now();
    if (left <= 0) {
      rig.endBlend();
      return;
    }
    const t = 1 - left / BLEND_MS;
    const s = t * t * (3 - 2 * t);
    from.deform(pose, scratch);
    for (let k = 0; k < out.length; k++) out[k] = s * out[k] + (1 - s) * scratch[k];
  };
}

/** Ends `rig`'s blend now, if one is in progress: its next deform is its own. */
export function endBlend(rig) {
  if (rig?.blendingUntil) rig.endBlend();
}

/**
 * The page's side of following. `send(rig, handles, settle)` asks the server (api.followOperator)
 * and resolves to `{ info, data }` for a new operator or null; `current()` gives the rig in use
 * and whether the scene it was trained for is still the page's (null when not an operator);
 * `swap(old, info, data)` installs a new operator; `state(name)` reports 'idle', 'sampling'.
 */
export class OperatorFollower {
  constructor({ send, current, swap, state, failed }) {
    Object.assign(this, { sendRequest: send, current, swap, state, failed });
    /** Whether drags are followed (on by default). */
    this.enabled = true;
    this.inFlight = false;
    /** What to send when the request in flight returns: null, 'move' or 'settle'. */
    this.queued = null;
    /** Operators swapped in, and the last answer's info (for the status line and tests). */
    this.swaps = 0;
    this.lastInfo = null;
  }

  /** The handles moved (a drag frame): asked about unless at the configuration last asked. */
  moved() {
    const rig = this.current();
    if (rig && !sameValues(this.lastQ, rig.q)) this.request('move');
  }

  /** The drag ended. */
  released() {
    this.request('settle');
  }

  request(kind) {
    if (!this.enabled) return;
    if (this.inFlight) {
      if (this.queued !== 'settle') this.queued = kind;
      return;
    }
    this.run(kind);
  }

  async run(kind) {
    const rig = this.current();
    if (!rig) return;
    this.inFlight = true;
    this.state('sampling');
    const handles = [];
    for (let l = 0; l < rig.nHandles; l++) handles.push([rig.q[2 * l], rig.q[2 * l + 1]]);
    this.lastQ = Float64Array.from(rig.q);
    try {
      const answer = await this.sendRequest(rig, handles, kind === 'settle');
      if (answer && this.current() === rig) {
        this.lastInfo = answer.info;
        this.swaps++;
        this.swap(rig, answer.info, answer.data);
      }
    } catch (e) {
      this.failed(e);
    } finally {
      this.inFlight = false;
      const next = this.queued;
      this.queued = null;
      if (next) this.run(next);
      else this.state('idle');
    }
  }
}

/** Whether the arrays hold the same numbers (a loop: called every frame, allocates nothing). */
function sameValues(a, b) {
  if (!a || a.length !== b.length) return false;
  for (let k = 0; k < a.length; k++) if (a[k] !== b[k]) return false;
  return true;
}
