// Files out: the deformed SVG, the animation (Lottie, animated SVG, GIF, APNG) and the scene
// file, downloaded.

import * as api from './api.js';
import { settleBlend } from './frames.js';
import { progress, say, showError, showNotice } from './messages.js';
import { pause } from './playback.js';
import { precompute } from './precompute.js';
import { download } from './save-file.js';
import { DEFAULT_DEFOP_SAMPLES, DEFOP_ENERGIES, baseName, editor, isDefop, rigReady } from './store.js';

const $ = (id) => document.getElementById(id);

/**
 * What deformed the drawing as shown, for the export (api.exportSvg): the rig and pose, or the
 * operator and its configuration Q; null without handles or while no rig matches the scene.
 */
function shownDeformation() {
  const { scene } = editor;
  if (scene.handles.length === 0 || !rigReady()) return null;
  if (isDefop(scene)) {
    editor.rig.configuration(scene.pose);
    return { defop: editor.rig.id, q: editor.rig.q };
  }
  return { rig: editor.rig.id, pose: scene.pose };
}

/** Downloads the drawing as shown as SVG (the viewBox as the export menu says). */
export async function exportSvg() {
  try {
    const viewbox = $('export-viewbox').value;
    settleBlend();
    const svg = await api.exportSvg(editor.info.id, editor.points, viewbox, shownDeformation());
    download(svg, `${baseName()}-deformed.svg`, 'image/svg+xml');
    const outside = editor.viewBoxReport?.outside.length ?? 0;
    const how = !outside ? '' : viewbox === 'fit' ? ' (viewBox grown to include the art)' : ' (viewBox kept: art outside it is cropped)';
    say(`exported ${baseName()}-deformed.svg${how}`);
  } catch (e) {
    showError(e);
    // The server keeps a few rigs only: an old one is built again, and Export works again.
    if (e.status === 404 && editor.rig) {
      editor.rigKey = null;
      precompute();
    }
  }
}

/** Downloads the timeline's animation as Lottie JSON, its report in the notice box. */
export async function exportLottie() {
  pause();
  progress('writing the Lottie animation');
  try {
    const { json, report } = await api.exportLottie(editor.info.id, editor.scene);
    download(json, `${baseName()}.json`, 'application/json');
    editor.lottieReport = report;
    say(`exported ${baseName()}.json: ${report?.summary ?? `${json.length} bytes`}`);
    showNotice(report?.warnings.length ? `Lottie: ${report.warnings.join('\n')}` : '');
  } catch (e) {
    showError(e);
  } finally {
    progress(null);
  }
}

/** The file name ending of each animation format of the menu. */
const ANIMATION_FILES = { svg: ['svg', 'image/svg+xml'], gif: ['gif', 'image/gif'], apng: ['png', 'image/png'] };

/**
 * Downloads the timeline's animation in the format the menu names (an animated SVG, a GIF or
 * an animated PNG), as `splineskin animate` writes it, the viewBox as the export menu says.
 */
export async function exportAnimation() {
  pause();
  const format = $('animation-format').value;
  const [ending, type] = ANIMATION_FILES[format];
  const name = `${baseName()}.${ending}`;
  progress(`writing ${name}`);
  try {
    const { blob, warning } = await api.exportAnimation(editor.info.id, editor.scene, format, $('export-viewbox').value);
    download(blob, name, type);
    say(`exported ${name}: ${blob.size} bytes`);
    if (warning) showNotice(warning);
  } catch (e) {
    showError(e);
  } finally {
    progress(null);
  }
}

/** Downloads the scene file (our JSON scene, the drawing inline). */
export async function saveScene() {
  try {
    // With an operator, the file keeps the scene's weights and says how to train the operator
    // in its `defop` section (the server writes it: scene_file.rs), so that
    // `splineskin defop train` on it trains the same one.
    const json = await api.sceneFile(editor.info.id, editor.scene);
    download(json, `${baseName()}-scene.json`, 'application/json');
    const { weights } = editor.scene;
    say(
      isDefop(editor.scene)
        ? `saved ${baseName()}-scene.json with its operator (${DEFOP_ENERGIES[weights.family]}, ` +
            `${weights.samples ?? DEFAULT_DEFOP_SAMPLES} samples) in its defop section`
        : `saved ${baseName()}-scene.json`,
    );
  } catch (e) {
    showError(e);
  }
}
