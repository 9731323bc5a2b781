// What the page writes: the scene (the subdivision scene format `splineskin subdiv deform`
// reads, the current pose as pose 0) and the server's exports of it, saved as downloads.

/** Matrices as scenes write them: `{"matrix": [[a, b, c, d], [e, f, g, h], [i, j, k, l]]}`. */
function matrixOf(t) {
  return { matrix: [t.slice(0, 4), t.slice(4, 8), t.slice(8, 12)] };
}

/**
 * The scene of `cageName`'s handles (rest positions), weight `family` and the current pose
 * (`transforms`: one flat 3 × 4 map per handle), as a subdivision scene file holds it; with
 * `keyframes` (`{time, transforms}` each, two or more), its `animation` at `fps`.
 */
export function sceneFile(cageName, handles, family, transforms, { keyframes = [], fps = 24 } = {}) {
  const scene = {
    splineskin_subdiv_scene: 1,
    obj: cageName,
    handles: handles.map((h) => ({ position: h.rest })),
    weights: { family },
    poses: [{ name: 'pose', transforms: transforms.map(matrixOf) }],
  };
  if (keyframes.length >= 2) {
    scene.animation = {
      fps,
      keyframes: keyframes.map((k) => ({ time: k.time, pose: k.transforms.map(matrixOf) })),
    };
  }
  return scene;
}

/** Offers `blob` to the user as a download named `name`. */
export function saveBlob(name, blob) {
  const url = URL.createObjectURL(blob);
  const link = document.createElement('a');
  link.href = url;
  link.download = name;
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 0);
}

/** The file name of `cageName` with extension `ext` (`tube.obj` → `tube.usda`). */
export function withExtension(cageName, ext) {
  const stem = cageName.replace(/\.[^.]*$/, '') || 'cage';
  return `${stem}.${ext}`;
}
