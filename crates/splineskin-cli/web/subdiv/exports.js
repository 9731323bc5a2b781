// What the page writes: the scene (the subdivision scene format `splineskin subdiv deform`
// reads, the current pose as pose 0, the keys as its animation) and the server's exports of
// it, saved as downloads (../save-file.js).

import { download } from '../save-file.js';
import { sceneHandles } from './handles.js';
import { handleMap } from './rig.js';
import { postRaw } from './server.js';

/** Frames per second of exported animations (and the ruler's frames). */
export const ANIMATION_FPS = 24;

/** Matrices as scenes write them: `{"matrix": [[a, b, c, d], [e, f, g, h], [i, j, k, l]]}`. */
function matrixOf(t) {
  return { matrix: [t.slice(0, 4), t.slice(4, 8), t.slice(8, 12)] };
}

/**
 * The scene of `cageName`'s handles (handles.js: point handles and bones, rest positions),
 * weight `family` and the current pose (`transforms`: one flat 3 × 4 map per handle), as a
 * subdivision scene file holds it; with `keyframes` (`{time, transforms, easing}` each, two or
 * more), its `animation` at `fps`.
 */
export function sceneFile(cageName, handles, family, transforms, { keyframes = [], fps = 24 } = {}) {
  const { handles: points, bones } = sceneHandles(handles);
  const scene = {
    splineskin_subdiv_scene: 1,
    obj: cageName,
    handles: points,
    ...(bones.length ? { bones } : {}),
    weights: { family },
    poses: [{ name: 'pose', transforms: transforms.map(matrixOf) }],
  };
  if (keyframes.length >= 2) {
    scene.animation = {
      fps,
      keyframes: keyframes.map((k) => ({
        time: k.time,
        pose: k.transforms.map(matrixOf),
        ...(k.easing && k.easing !== 'linear' ? { easing: k.easing } : {}),
      })),
    };
  }
  return scene;
}

/** The file name of `cageName` with extension `ext` (`tube.obj` → `tube.usda`). */
export function withExtension(cageName, ext) {
  const stem = cageName.replace(/\.[^.]*$/, '') || 'cage';
  return `${stem}.${ext}`;
}

/**
 * Saves `page`'s scene (`scene`) or the server's export of it (`usda`, `glb`, `obj`): the
 * current pose, or with two keys or more their animation; `say` reports.
 */
export async function exportAs(page, format, say) {
  if (!page.cage || page.handles.length === 0) {
    say('Add handles first: the export is the posed surface.', { error: true });
    return;
  }
  const keyframes = page.keys.map((k) => ({
    time: k.time,
    easing: k.easing,
    transforms: k.poses.map((p, i) => handleMap({ rest: page.handles[i].rest, ...p })),
  }));
  const scene = sceneFile(page.cage.name, page.handles, page.family, page.handles.map(handleMap), {
    keyframes,
    fps: ANIMATION_FPS,
  });
  if (format === 'scene') {
    download(JSON.stringify(scene, null, 1), withExtension(page.cage.name, 'json'), 'application/json');
    return;
  }
  delete scene.splineskin_subdiv_scene;
  delete scene.obj;
  const body = JSON.stringify({ name: page.cage.name, obj: page.objText, level: page.cage.surface.level, scene });
  say(`exporting ${format}…`);
  const response = await postRaw(`/api/subdiv/export?format=${format}`, body, { 'content-type': 'application/json' });
  const name = withExtension(page.cage.name, format === 'obj' ? 'posed.obj' : format);
  download(await response.blob(), name);
  const what = scene.animation ? `the animation (${page.keys.length} keys)` : 'the current pose';
  say(`${name}: the ${format === 'glb' ? 'limit surface' : 'fitted cage'} of ${what}`);
}
