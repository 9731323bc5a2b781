// The menus and buttons as the state has them: the weight family and its settings, what can be
// undone, deleted or reset.

import * as affine from './affine.js';
import { DEFAULT_DEFOP_SAMPLES, DEFAULT_MARGIN, MESH_FAMILIES, editor, isDefop } from './store.js';

const $ = (id) => document.getElementById(id);

/** Sets the menus, checkboxes and buttons from the state. */
export function syncControls() {
  const { scene } = editor;
  $('family').value = scene.weights.family;
  $('flexible').checked = scene.flexible;
  const defop = isDefop(scene);
  $('flexible').disabled = defop;
  $('flexible').parentElement.title = defop
    ? 'Flexible G¹ does not apply to a trained operator: its join keeps the junction constraints as they are'
    : 'G¹ junctions keep parallel tangents but not their length ratio (solved on mouse-up)';
  $('adaptive').checked = editor.adaptive.on;
  $('adaptive').disabled = defop;
  $('adaptive-label').title = defop
    ? 'Control points are added to the spline fit of weights; a trained operator joins the drawing as it is'
    : "Where a curve cannot follow the pose you drag to, split it at rest and add a control point there (the artist's anchors stay; added ones are ringed among the junctions)";
  $('adaptive-tolerance-label').hidden = !editor.adaptive.on || defop;
  $('defop-samples-label').hidden = !defop;
  $('margin-label').hidden = !MESH_FAMILIES.has(scene.weights.family);
  $('margin').value = String(Number(((scene.margin ?? DEFAULT_MARGIN) * 100).toPrecision(6)));
  if (defop) $('defop-samples').value = scene.weights.samples ?? DEFAULT_DEFOP_SAMPLES;
  $('show-weights').disabled = defop;
  $('undo').disabled = !editor.history.canUndo;
  $('redo').disabled = !editor.history.canRedo;
  $('delete-handle').disabled = editor.selection.length === 0;
  $('reset-pose').disabled = scene.pose.every((T) => affine.isIdentity(T));
}
