// Type-checked, never run (browser-tests/js-api.test.mjs runs tsc on it): what a TypeScript
// caller of splineskin.js writes compiles against splineskin.d.ts, and mistakes do not.
import { load, SplineskinError, type Drawing, type Pose, type Rig } from '../crates/splineskin-cli/web/splineskin.js';

export async function use(bytes: Uint8Array): Promise<string> {
  const splineskin = await load(bytes);
  const drawing: Drawing = splineskin.open('<svg xmlns="http://www.w3.org/2000/svg"/>', 'x.svg');
  const rig: Rig = drawing.rig({ pins: [[0, 0], [10, 0]], weights: 'bbw', flexible: true });
  const pose: Pose = [[1, 0, 0, 1, 0, 0], [1, 0, 0, 1, 5, 0]];
  const out: Float64Array = rig.update(pose, new Float64Array(2 * drawing.nPoints));
  const solved: Float64Array = rig.solve(new Float64Array(12));
  const d: string[] = drawing.pathData(solved);
  const elements: string[] = drawing.elementPathData(out);
  try {
    return drawing.svg(out, { rig, pose, viewBox: 'fit' }) + d.join() + elements.join();
  } catch (e) {
    if (e instanceof SplineskinError) return `${e.status}: ${e.message}`;
    throw e;
  }
}

export function mistakes(drawing: Drawing, rig: Rig): void {
  // @ts-expect-error: the weights are a family's name
  drawing.rig({ pins: [[0, 0]], weights: 'smooth' });
  // @ts-expect-error: a map has six coefficients
  rig.update([[1, 0, 0, 1]], new Float64Array(4));
  // @ts-expect-error: the viewBox is kept or fitted
  drawing.svg(new Float64Array(4), { viewBox: 'grow' });
}
