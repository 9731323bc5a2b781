// Types of splineskin.js, the JavaScript API of splineskin's WebAssembly module (docs/javascript.md);
// browser-tests/js-api-types.ts is type-checked against them.

/** One affine map per pin, SVG order [a, b, c, d, e, f]: p ↦ (a x + c y + e, b x + d y + f). */
export type Pose = ReadonlyArray<readonly [number, number, number, number, number, number]> | Float64Array;

/** A failure of the module; the message names the file and element concerned. */
export class SplineskinError extends Error {
  /** 400 bad input, 404 dropped, 413 too large, 500 a bug. */
  status: number;
}

/**
 * Loads the module: its URL, a fetch Response, its bytes or a compiled module; default
 * splineskin.wasm beside splineskin.js. `threads`: with the threaded module
 * (splineskin-threads.wasm), how many threads to compute on (Node, or a worker of a
 * cross-origin-isolated page); the one-thread module ignores it.
 */
export function load(
  source?: string | URL | Response | ArrayBuffer | ArrayBufferView | WebAssembly.Module,
  options?: { threads?: number },
): Promise<Splineskin>;

export class Splineskin {
  /** The threads the module computes on (1 unless the threaded module was given threads). */
  readonly threads: number;
  /** Opens an SVG document or a scene (JSON, drawing inline); `name` names it in messages. */
  open(text: string, name?: string): Drawing;
}

export interface RigOptions {
  /** Pin positions [x, y], root user units. */
  pins: ReadonlyArray<readonly [number, number]>;
  /** The weights: 'bbw' (smooth, default), 'shepard', 'harmonic' or 'biharmonic'. */
  weights?: 'bbw' | 'shepard' | 'harmonic' | 'biharmonic';
  /** Flexible G¹ junctions (solved by Rig.solve). */
  flexible?: boolean;
  /** Junction kind overrides. */
  junctions?: ReadonlyArray<{ path: number; joint: number; kind: 'C0' | 'C1' | 'G1' | 'angle' }>;
}

export class Drawing {
  /** The module's description (paths, elements, junction kinds, warnings, the scene opened). */
  readonly info: any;
  readonly name: string;
  /** Chain points of all paths. */
  readonly nPoints: number;
  readonly nCurves: number;
  /** The root viewBox [x, y, width, height]. */
  readonly viewBox: [number, number, number, number];
  /** Rest chain points x0, y0, x1, y1, …. */
  readonly rest: Float64Array;
  readonly warnings: string[];
  /** The document to show, every imported element a <path data-splineskin-element="k">. */
  readonly document: string;
  /** The d of every element at `points`, in the element's own coordinates. */
  elementPathData(points: ArrayLike<number>): string[];
  /** Precomputes weights and the rig's operator. */
  rig(options: RigOptions): Rig;
  /** Path data of every path at `points`. */
  pathData(points: ArrayLike<number>): string[];
  /** The SVG document at `points`, styles kept; with `rig` and `pose`, gradients and text follow. */
  svg(points: ArrayLike<number>, options?: { rig?: Rig; pose?: Pose; viewBox?: 'keep' | 'fit' }): string;
}

export class Rig {
  readonly id: string;
  /** O, row-major (2 · nPoints) × (6 · nHandles). */
  readonly operator: Float64Array;
  readonly nHandles: number;
  readonly nPoints: number;
  readonly flexible: boolean;
  /** points = O · vec(T) into `out` (2 · nPoints numbers), allocating nothing; returns `out`. */
  update(pose: Pose, out: Float64Array): Float64Array;
  /** The module's solve at `pose` (flexible G¹ when the rig is flexible). */
  solve(pose: Pose): Float64Array;
}
