// What the editor draws over the art: junction markers and handles, the selected handle's
// weight field (at rest, or carried by the pose), and the triangulated domain the weights are
// solved on, carried by the pose.

import * as affine from './affine.js';
import * as api from './api.js';
import { weightColour, weightImage } from './colour.js';
import { DefOpLiveRig } from './defop.js';
import { selectionCentre } from './gestures.js';
import { showError, say } from './messages.js';
import { skinPoints } from './skinning.js';
import { editor, isDefop, junctionKind, rigReady, shortName } from './store.js';
import { posedHandles } from './view.js';

const $ = (id) => document.getElementById(id);

/** Samples on the long side of the weight grid. */
const WEIGHT_GRID = 200;

/** Samples on the long side of the weight grid drawn on the posed drawing (cells of a mesh). */
const POSED_WEIGHT_GRID = 90;

/** Draws the junction markers (when shown) and the handles, the selection's widgets with them. */
export function drawOverlay() {
  const { view } = editor;
  view.drawJunctions(editor.points, junctionKind, editor.shown.junctions);
  // An operator moves pins only: no rotate or scale widgets.
  const centre = isDefop(editor.scene) ? null : selectionCentre(editor.scene, editor.selection);
  view.drawHandles(posedHandles(editor.scene), editor.selection, centre);
}

/**
 * Shows the selected handle's weight field when asked for (the rig's weights on a grid over the
 * viewBox, fetched per handle; posed, every handle's, carried by the pose), or hides it.
 */
export async function updateWeights() {
  const wanted =
    editor.shown.weights && editor.selected !== null && rigReady() && !(editor.rig instanceof DefOpLiveRig);
  $('weight-legend').hidden = !wanted;
  if (!wanted) {
    editor.weightsShown = null;
    editor.view?.showWeights(null);
    return;
  }
  const { pose } = editor.scene;
  const atRest = pose.every((T) => affine.isIdentity(T));
  // Posed, the field is drawn where the pose puts it (its key changes with the pose).
  const key = `${editor.rig.id}/${editor.selected}${atRest ? '' : `/${JSON.stringify(pose)}`}`;
  if (editor.weightsShown === key) return;
  editor.weightsShown = key;
  const [x, y, w, h] = editor.info.view_box;
  const box = [x, y, x + w, y + h];
  const cells = atRest ? WEIGHT_GRID : POSED_WEIGHT_GRID;
  const scale = cells / Math.max(w, h);
  const width = Math.max(2, Math.round(w * scale));
  const height = Math.max(2, Math.round(h * scale));
  try {
    if (atRest) {
      const values = await api.weightGrid(editor.rig.id, editor.selected, box, width, height);
      if (editor.weightsShown !== key) return;
      editor.view.showWeights(weightImage(values, width, height), box);
      return;
    }
    // Every handle's weights at the grid's points, each point carried where the skinning
    // map Σᵢ wᵢ(x) Tᵢ x puts it, the selected handle's weight coloured over the cells between.
    const grids = await Promise.all(pose.map((_, i) => api.weightGrid(editor.rig.id, i, box, width, height)));
    if (editor.weightsShown !== key) return;
    const [x0, y0, x1, y1] = box;
    const lattice = new Float64Array(2 * width * height);
    for (let r = 0; r < height; r++) {
      for (let c = 0; c < width; c++) {
        const k = r * width + c;
        lattice[2 * k] = x0 + ((c + 0.5) * (x1 - x0)) / width;
        lattice[2 * k + 1] = y0 + ((r + 0.5) * (y1 - y0)) / height;
      }
    }
    const points = skinPoints(pose, lattice, (k, i) => grids[i][k]);
    editor.view.showWeightMesh(points, grids[editor.selected], width, height, weightColour);
  } catch (e) {
    editor.weightsShown = null;
    showError(e);
  }
}

/** Draws the mesh at the current pose (fetched once per rig), or hides it. */
export async function updateMesh() {
  const view = editor.view;
  if (!view) return;
  const wanted = editor.shown.mesh && rigReady() && !isDefop(editor.scene) && !editor.rigPreview;
  if (!wanted) {
    view.drawMesh(null);
    return;
  }
  const id = editor.rig.id;
  if (editor.shownMesh?.rig !== id) {
    if (editor.meshRequest?.rig === id) return;
    editor.meshRequest = { rig: id };
    try {
      const mesh = await api.mesh(id);
      const edges = new Map();
      const t = mesh.triangles;
      for (let k = 0; k < t.length; k += 3) {
        for (const [a, b] of [[t[k], t[k + 1]], [t[k + 1], t[k + 2]], [t[k + 2], t[k]]]) {
          edges.set(a < b ? `${a},${b}` : `${b},${a}`, a < b ? [a, b] : [b, a]);
        }
      }
      editor.shownMesh = { rig: id, mesh, edges: [...edges.values()] };
      say(`${shortName()}: the weights' mesh has ${mesh.vertices.length / 2} vertices and ${t.length / 3} triangles over ${mesh.boundary}`);
    } catch (e) {
      editor.shownMesh = null;
      view.drawMesh(null);
      // Weights without a mesh: said in the status line, the box stays as the user left it.
      if (e.status === 400) say(`${shortName()}: ${e.message}`);
      else showError(e);
      return;
    } finally {
      editor.meshRequest = null;
    }
    if (editor.rig?.id !== id) return;
  }
  // Each vertex where the skinning map puts it: Σᵢ wᵢ(v) Tᵢ v.
  const { mesh, edges } = editor.shownMesh;
  const pose = editor.scene.pose;
  const n = mesh.n_handles;
  if (pose.length !== n) return;
  const points = skinPoints(pose, mesh.vertices, (v, i) => mesh.weights[v * n + i]);
  view.drawMesh(points, edges);
  document.body.dataset.mesh = String(edges.length);
}
