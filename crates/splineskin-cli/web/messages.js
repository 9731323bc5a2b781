// The status bar: the message line, the error and notice boxes, and the progress bar with its
// running clock.

const $ = (id) => document.getElementById(id);

/** Shows `error` (an Error or text) in the error box until it is clicked. */
export function showError(error) {
  const box = $('error');
  box.textContent = error instanceof Error ? error.message : String(error);
  box.hidden = false;
  document.body.dataset.error = '1';
}

/** Hides the error box. */
export function clearError() {
  $('error').hidden = true;
  delete document.body.dataset.error;
}

/** Something the user should know about what was opened; stays until clicked. */
export function showNotice(text) {
  const box = $('notice');
  box.textContent = text;
  box.hidden = !text;
}

/** Puts `text` in the status line. */
export function say(text) {
  $('message').textContent = text;
}

/** The progress clock's timer and when its label started (ms): the status bar's own state. */
const clock = { timer: null, start: 0 };

/**
 * Shows `label` with a running clock (restarted unless `restart` is false: a count within the
 * same stage), and a filled bar for `fraction` (0…1) when given.
 */
export function progress(label, fraction = null, restart = true) {
  const box = $('progress');
  clearInterval(clock.timer);
  const bar = box.querySelector('.bar');
  bar.classList.toggle('determinate', fraction !== null);
  bar.querySelector('.fill').style.width = fraction === null ? '0' : `${(100 * fraction).toFixed(1)}%`;
  if (!label) {
    box.hidden = true;
    $('progress-stop').hidden = true;
    return;
  }
  if (restart || box.hidden) clock.start = performance.now();
  const { start } = clock;
  const tick = () => {
    $('progress-text').textContent = `${label} ${((performance.now() - start) / 1000).toFixed(1)} s`;
  };
  tick();
  box.hidden = false;
  clock.timer = setInterval(tick, 100);
}

/** `n thing` or `n things`. */
export function plural(n, thing) {
  return `${n} ${thing}${n === 1 ? '' : 's'}`;
}
