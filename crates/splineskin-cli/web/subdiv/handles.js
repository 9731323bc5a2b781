// The page's handles as the subdivision scene orders them (`splineskin::subdiv::scene`): point
// handles first, then bones (segments between two points). Each has a pose about its pivot (a
// point handle's position, a bone's first end): `{ kind, rest, end?, offset, rotation }`, its
// map `x ↦ rest + offset + R (x − rest)` (rig.js handleMap).

import { IDENTITY_ROTATION, handleMap } from './rig.js';

/** A point handle placed at `rest`, at rest. */
export function pointHandle(rest) {
  return { kind: 'point', rest, offset: [0, 0, 0], rotation: [...IDENTITY_ROTATION] };
}

/** A bone from `rest` (its pivot) to `end`, at rest. */
export function boneHandle(rest, end) {
  return { kind: 'bone', rest, end, offset: [0, 0, 0], rotation: [...IDENTITY_ROTATION] };
}

const isBone = (h) => h.kind === 'bone';

/** `handles` with `h` in scene order (a point after the points, a bone last), and its index. */
export function withHandle(handles, h) {
  const at = isBone(h) ? handles.length : handles.filter((x) => !isBone(x)).length;
  return [[...handles.slice(0, at), h, ...handles.slice(at)], at];
}

/** The scene's `handles` and `bones` of the page's handles (rest positions). */
export function sceneHandles(handles) {
  return {
    handles: handles.filter((h) => !isBone(h)).map((h) => ({ position: h.rest })),
    bones: handles.filter(isBone).map((h) => ({ ends: [h.rest, h.end] })),
  };
}

/** Where each handle's pivot is now (rest plus offset), x, y, z flat. */
export function pivots(handles) {
  return handles.flatMap((h) => h.rest.map((r, k) => r + h.offset[k]));
}

/** The number of bones among `handles`. */
export function boneCount(handles) {
  return handles.filter(isBone).length;
}

/**
 * The bones' segments now, x, y, z flat into `out` (6 numbers per bone, in order): the pivot's
 * place and the image of the far end under the bone's map.
 */
export function boneSegments(handles, out) {
  let o = 0;
  for (const h of handles) {
    if (!isBone(h)) continue;
    const t = handleMap(h);
    const [x, y, z] = h.end;
    for (let k = 0; k < 3; k++) out[o + k] = h.rest[k] + h.offset[k];
    for (let k = 0; k < 3; k++) out[o + 3 + k] = t[4 * k] * x + t[4 * k + 1] * y + t[4 * k + 2] * z + t[4 * k + 3];
    o += 6;
  }
  return out;
}
