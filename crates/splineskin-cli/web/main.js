// The editor: opens a drawing, places and drags handles, and keeps the drawing following them —
// one matrix–vector product per frame in the page, precomputation on the server (or the
// WebAssembly module in a worker, backend.js).
//
// This module opens drawings, reacts to every change of the scene (`sceneChanged`) and wires the
// page's controls, gestures and keys to the modules that do the work. The state is store.js's;
// docs/ARCHITECTURE.md draws the page's modules.

import * as affine from './affine.js';
import { setAdaptive, refineForPoses } from './adaptive.js';
import * as anim from './animation.js';
import * as api from './api.js';
import { autosave, savedSession } from './autosave.js';
import { syncControls } from './controls.js';
import { exportAnimation, exportLottie, exportSvg, saveScene } from './downloads.js';
import * as edits from './edits.js';
import { DefOpLiveRig } from './defop.js';
import { flexibleSolve, render, scheduleFrame } from './frames.js';
import { installGestures } from './gestures.js';
import { wireKeys } from './keyboard.js';
import { clearError, clearNotice, plural, progress, say, showError, showNotice, toggleStatusDetails } from './messages.js';
import { drawOverlay, updateMesh, updateWeights } from './overlays.js';
import { drawTimeline, pause, play, seek, showTime, updateOnion } from './playback.js';
import { precompute } from './precompute.js';
import { littleEndian } from './rig.js';
import {
  DEFAULT_DEFOP_SAMPLES,
  DEFAULT_MARGIN,
  DEFOP_ENERGIES,
  MAX_DEFOP_SAMPLES,
  MAX_MARGIN,
  editor,
  fps,
  isDefop,
  keyframes,
  listen,
  rigKeyOf,
  setRigState,
  shortName,
} from './store.js';
import { TimelineRuler } from './timeline.js';
import { DrawingView, posedHandles } from './view.js';
import { drawFoldMarks, showViewBoxReport, toggleFoldMarks } from './viewbox.js';

const $ = (id) => document.getElementById(id);

/** Shows document `info`; `source` is the text of the file the page opened (null: the server's). */
function show(info, source = null) {
  const view = new DrawingView($('canvas'), info);
  editor.info = info;
  editor.source = source;
  editor.view = view;
  editor.scene = structuredClone(info.scene);
  editor.rest = Float64Array.from(info.rest);
  editor.points = Float64Array.from(info.rest);
  editor.rig = null;
  editor.rigKey = null;
  editor.rigPreview = false;
  editor.partialFramesSaid = false;
  editor.selected = null;
  editor.selection = [];
  pause();
  editor.time = 0;
  editor.selectedKey = null;
  editor.animating = false;
  editor.onionPoints = [null, null];
  editor.weightsShown = null;
  editor.adaptive.original = null;
  editor.adaptive.toOriginal = null;
  editor.history.clear();
  editor.frameTimes = [];
  editor.productTimes = [];
  editor.viewBoxReport = null;
  showViewBoxReport(null);
  setRigState('none');
  document.title = `${info.name} — splineskin editor`;
  clearError();
  // Junction markers are hidden by default (they clutter the art); showing them is the
  // junction-editing mode, in which a click on a marker changes its kind.
  editor.shown.junctions = false;
  $('show-junctions').checked = false;
  say(`${shortName()}: ${info.n_curves} curves in ${info.paths.length} paths`);
  // A scene's defop section: offered in the Weights menu, its sample count prefilled.
  $('defop-samples').value = info.operator?.samples ?? DEFAULT_DEFOP_SAMPLES;
  const offer = info.operator
    ? [`this scene describes a ${DEFOP_ENERGIES[info.operator.family]} operator (${info.operator.samples} samples): ` +
        'pick it in the Weights menu to train it']
    : [];
  showNotice([...info.warnings, ...offer].join('\n'));
  syncControls();
  sceneChanged();
}

async function open(file) {
  say(`opening ${file.name}…`);
  progress(`reading ${file.name}`);
  try {
    const source = await file.text();
    show(await api.openFile(file), source);
  } catch (e) {
    showError(e);
    say(`${file.name} was not opened`);
  } finally {
    progress(null);
  }
}

/** Places pins over the art (the server's rule, `splineskin rig`'s), the user's own kept. */
async function autoPins() {
  if (!editor.info) return;
  try {
    const { pins } = await api.autoPins(editor.info.id, editor.scene.handles);
    const n = edits.addPins(pins.slice(editor.scene.handles.length));
    say(n ? `${shortName()}: ${plural(n, 'pin')} placed over the art (Ctrl+Z takes them away)` : `${shortName()}: its pins cover the art already`);
  } catch (e) {
    showError(e);
  }
}

/** How far from the art a click still adds a pin on it, CSS pixels. */
const SNAP_PX = 6;

/** The notice that turns and scales were set aside: it goes once no operator family is chosen. */
const TURNS_SET_ASIDE = 'turns-set-aside';

/** After any change of the scene: precompute if its rest part changed, else redraw. */
function sceneChanged() {
  if (!isDefop(editor.scene)) clearNotice(TURNS_SET_ASIDE);
  const key = rigKeyOf(editor.scene);
  if (editor.scene.handles.length === 0) {
    editor.abort?.abort();
    editor.rig = null;
    editor.rigKey = key;
    editor.rigPreview = false;
    setRigState('none');
    progress(null);
    if (isDefop(editor.scene)) say(`${shortName()}: click on the art to add point handles; the operator is trained for them`);
    render();
  } else if (key !== editor.rigKey) {
    precompute();
  } else {
    render();
    flexibleSolve();
  }
  syncControls();
  updateWeights();
  updateMesh();
  drawTimeline();
  updateOnion();
  autosave();
}

/**
 * Puts back a saved session after a reload: its file reopened (if it was one the page opened),
 * its scene and time. Undo goes back to the drawing as it opened.
 */
async function recoverSession(session) {
  if (session.source) {
    const file = new File([session.source], session.name.split(/[\\/]/).pop());
    const info = await api.openFile(file);
    show(info, session.source);
  } else if (session.name !== editor.info.name || session.svgLength !== editor.info.svg.length) {
    return false;
  }
  const scene = session.scene;
  if (!Array.isArray(scene.handles) || !Array.isArray(scene.pose) || scene.pose.length !== scene.handles.length) return false;
  editor.history.record(editor.scene);
  editor.scene = { ...structuredClone(editor.scene), ...scene };
  editor.time = Number.isFinite(session.time) ? session.time : 0;
  editor.animating = Boolean(scene.animation);
  const tolerance = session.adaptive?.tolerance;
  if (Number.isFinite(tolerance) && tolerance > 0) {
    editor.adaptive.on = true;
    editor.adaptive.tolerance = tolerance;
    $('adaptive-tolerance').value = String(tolerance * 100);
  }
  syncControls();
  sceneChanged();
  const when = new Date(session.savedAt).toLocaleString();
  showNotice(`restored your session on ${shortName()} from ${when} (Undo goes back to the file as it opened)`);
  document.body.dataset.recovered = '1';
  return true;
}

const gestureActions = {
  select: edits.select,
  posed(maps) {
    pause();
    for (const [i, map] of maps) editor.scene.pose[i] = map;
    editor.solveSeq++; // a solve of an older pose must not land now
    scheduleFrame();
  },
  dragged(before, handles) {
    editor.history.record(before);
    // Animating: the dragged pins are keyed at the shown time.
    if (editor.animating && editor.scene.animation?.keyframes.length) {
      editor.selectedKey = anim.setKey(editor.scene, editor.time, editor.scene.pose, handles);
    }
    sceneChanged();
    if (editor.rig instanceof DefOpLiveRig) editor.follower.released();
    else if (editor.adaptive.on) refineForPoses();
  },
  boxChanged(box) {
    editor.view.showBox(box);
  },
  clicked(p, [clientX, clientY], altKey) {
    const junction = editor.shown.junctions ? editor.view.junctionAt(editor.points, p) : null;
    if (junction) {
      edits.cycleJunction(junction);
    } else if (altKey) {
      // Alt places a pin anywhere (say, outside a shape).
      edits.addHandle(p);
    } else {
      // Pins go on the art, as in Puppet Warp: a click a few pixels off a thin stroke snaps to it.
      const near = editor.view.artNear(clientX, clientY, SNAP_PX);
      if (near) edits.addHandle(editor.view.toUser(...near));
      else if (editor.selection.length) edits.deselect();
      else say('pins go on the art: click a shape or stroke (Alt-click: anywhere)');
    }
  },
  viewChanged() {
    drawOverlay();
    drawFoldMarks();
  },
};

const rulerActions = {
  seek,
  keyPressed(k) {
    pause();
    editor.selectedKey = k;
    editor.keyDragBefore = structuredClone(editor.scene);
    editor.animating = true;
    showTime(keyframes()[k].time, { timed: false });
  },
  keyMoved(k, t, done) {
    const keys = keyframes();
    if (!keys[k]) return;
    const step = 1 / fps();
    const lo = k > 0 ? keys[k - 1].time : -Infinity;
    const hi = k < keys.length - 1 ? keys[k + 1].time : Infinity;
    // Between its neighbours: a keyframe does not pass another.
    if (t <= lo) t = lo + step;
    if (t >= hi) t = hi - step;
    if (t > lo && t < hi && t >= 0) {
      keys[k].time = t;
      editor.time = t;
      drawTimeline();
    }
    if (done && editor.keyDragBefore) {
      if (JSON.stringify(editor.keyDragBefore.animation) !== JSON.stringify(editor.scene.animation)) {
        editor.history.record(editor.keyDragBefore);
      }
      editor.keyDragBefore = null;
      showTime(editor.time, { timed: false });
      sceneChanged();
    }
  },
};

/** Wires the page: gestures on the drawing, the ruler, every control and key. */
function wire() {
  installGestures($('canvas'), editor, gestureActions);
  editor.ruler = new TimelineRuler($('ruler'), rulerActions);
  wireTimeline();
  wireFiles();
  wireSettings();
  wireView();
  wireKeys();
}

/** The timeline's buttons and fields: play, key, duplicate and delete keyframes, easing, fps. */
function wireTimeline() {
  $('loop').checked = editor.loop;
  $('onion').checked = editor.shown.onion;
  $('easing').replaceChildren(
    ...anim.EASINGS.map((name) => {
      const option = document.createElement('option');
      option.value = name;
      option.textContent = anim.EASING_LABELS[name];
      return option;
    }),
  );
  $('play').addEventListener('click', () => (editor.playing ? pause() : play()));
  $('key-pose').addEventListener('click', () => edits.key());
  $('key-pins').addEventListener('click', () => edits.key([...editor.selection]));
  $('duplicate-key').addEventListener('click', edits.duplicateKey);
  $('delete-key').addEventListener('click', edits.deleteKey);
  $('easing').addEventListener('change', (event) => {
    const k = editor.selectedKey;
    if (k === null || !keyframes()[k]) return;
    edits.edit((scene) => (scene.animation.keyframes[k].easing = event.target.value));
  });
  $('fps').addEventListener('change', (event) => {
    const rate = Number(event.target.value);
    if (!(rate > 0 && rate <= anim.MAX_FPS)) {
      showError(`frames per second: ${event.target.value} is not a number above 0 and at most ${anim.MAX_FPS}`);
      drawTimeline();
      return;
    }
    if (editor.scene.animation) edits.edit((scene) => (scene.animation.fps = rate));
  });
  $('loop').addEventListener('change', (event) => (editor.loop = event.target.checked));
  $('onion').addEventListener('change', (event) => {
    editor.shown.onion = event.target.checked;
    updateOnion();
  });
}

/** Opening files (the file field, or a drop on the drawing) and the files out. */
function wireFiles() {
  $('open-file').addEventListener('change', (event) => {
    const file = event.target.files[0];
    event.target.value = '';
    if (file) open(file);
  });
  const stage = $('stage');
  stage.addEventListener('dragover', (event) => {
    event.preventDefault();
    stage.classList.add('dragging-file');
  });
  stage.addEventListener('dragleave', () => stage.classList.remove('dragging-file'));
  stage.addEventListener('drop', (event) => {
    event.preventDefault();
    stage.classList.remove('dragging-file');
    const file = event.dataTransfer?.files?.[0];
    if (file) open(file);
  });

  $('export-svg').addEventListener('click', exportSvg);
  $('save-scene').addEventListener('click', saveScene);
  $('export-lottie').addEventListener('click', exportLottie);
  $('export-animation').addEventListener('click', exportAnimation);
  $('progress-stop').addEventListener('click', () => {
    if (!editor.job) return;
    $('progress-stop').hidden = true;
    progress('stopping the training', null, false);
    api.stopJob(editor.job).catch(showError);
  });
}

/** Undo, redo, delete and reset, and the weight family's settings. */
function wireSettings() {
  $('undo').addEventListener('click', edits.undo);
  $('redo').addEventListener('click', edits.redo);
  $('delete-handle').addEventListener('click', edits.deleteHandles);
  $('auto-pins').addEventListener('click', autoPins);
  $('reset-pose').addEventListener('click', () =>
    edits.edit((scene) => (scene.pose = scene.pose.map(() => [...affine.IDENTITY]))),
  );
  $('family').addEventListener('change', (event) =>
    edits.edit((scene) => {
      const family = event.target.value;
      if (family === 'shepard') {
        scene.weights = { family, exponent: 2 };
      } else if (family in DEFOP_ENERGIES) {
        const samples = Number.parseInt($('defop-samples').value, 10);
        scene.weights = { family, samples: Number.isInteger(samples) ? samples : DEFAULT_DEFOP_SAMPLES };
        scene.flexible = false; // does not apply (syncControls disables it)
        // The operator moves pins, it does not turn or scale them: set turns and scales aside
        // here, visibly and undoably, rather than keep them unseen for another family.
        if (edits.translationsOnly(scene)) {
          showNotice('the operator moves pins only: their turns and scales were set aside (Ctrl+Z brings them back)', TURNS_SET_ASIDE);
        }
      } else {
        scene.weights = { family };
      }
    }),
  );
  $('defop-samples').addEventListener('change', (event) => {
    const samples = Number(event.target.value);
    if (!Number.isInteger(samples) || samples < 1 || samples > MAX_DEFOP_SAMPLES) {
      showError(`training samples: ${event.target.value} is not a whole number from 1 to ${MAX_DEFOP_SAMPLES}`);
      syncControls();
      return;
    }
    // The field's change on losing the focus (a click on Stop training) repeats the value: no edit.
    if (isDefop(editor.scene) && editor.scene.weights.samples !== samples) {
      edits.edit((scene) => (scene.weights = { ...scene.weights, samples }));
    }
  });
  $('margin').addEventListener('change', (event) => {
    const percent = Number(event.target.value);
    if (event.target.value.trim() === '' || !(percent >= 0 && percent <= 100 * MAX_MARGIN)) {
      showError(`margin ${event.target.value} %: expected a number from 0 to ${100 * MAX_MARGIN}`);
      syncControls();
      return;
    }
    if (percent / 100 === (editor.scene.margin ?? DEFAULT_MARGIN)) return; // nothing to undo
    edits.edit((scene) => (scene.margin = percent / 100));
  });
  $('flexible').addEventListener('change', (event) => edits.edit((scene) => (scene.flexible = event.target.checked)));
  $('adaptive').addEventListener('change', (event) => setAdaptive(event.target.checked));
  $('adaptive-tolerance').addEventListener('change', (event) => {
    const percent = Number(event.target.value);
    if (!(percent > 0 && percent <= 10)) {
      showError(`add control points within ${event.target.value} %: expected a number above 0, at most 10`);
      event.target.value = String(editor.adaptive.tolerance * 100);
      return;
    }
    editor.adaptive.tolerance = percent / 100;
    refineForPoses();
  });
}

/** What is drawn over the art, the message boxes, and the view's fit. */
function wireView() {
  // The overlays' checkboxes start as the state has them and set it.
  const toggles = { 'show-junctions': ['junctions', drawOverlay], 'show-weights': ['weights', updateWeights], 'show-mesh': ['mesh', updateMesh] };
  for (const [id, [name, redraw]] of Object.entries(toggles)) {
    $(id).checked = editor.shown[name];
    $(id).addEventListener('change', (event) => {
      editor.shown[name] = event.target.checked;
      redraw();
    });
  }
  $('error').addEventListener('click', clearError);
  $('notice').addEventListener('click', () => showNotice(''));
  $('status-more').addEventListener('click', toggleStatusDetails);
  $('fold-note').addEventListener('click', toggleFoldMarks);
  $('status-details').addEventListener('click', toggleStatusDetails);
  $('fit').addEventListener('click', () => {
    if (!editor.view) return;
    editor.view.fit(posedHandles(editor.scene));
    drawOverlay();
    drawFoldMarks();
  });

  window.addEventListener('resize', () => editor.view && drawOverlay());
}

// Events of the lower modules (store.js): an edit, or a rig the backend no longer has.
listen('scene-changed', sceneChanged);
listen('rig-lost', precompute);
// For the browser tests and the console.
window.splineskinEditor = editor;

/** Wires the page, shows the server's drawing and puts back the session saved before a reload. */
async function boot() {
  wire();
  if (!littleEndian()) {
    showError('this browser stores numbers big-endian; the editor reads little-endian data');
    return;
  }
  // Read before the first autosave replaces it.
  const session = await savedSession();
  try {
    show(await api.initialDocument());
  } catch (e) {
    showError(e);
  }
  if (session && editor.info) {
    editor.restoring = true;
    try {
      await recoverSession(session);
    } catch (e) {
      showNotice(`the previous session could not be restored: ${e.message ?? e}`);
    } finally {
      editor.restoring = false;
      autosave();
    }
  }
  document.body.dataset.booted = '1';
}

boot();
