// The status bar: the message line, the notes and the notice, the error box, the progress bar
// with its running clock, and the details view that shows the bar's texts in full (the bar's
// rows have a fixed height and cut what does not fit).

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

/**
 * Something the user should know about what was opened; stays until clicked, or until
 * `clearNotice(key)` when given a `key` (a notice about a state that can end).
 */
export function showNotice(text, key = '') {
  const box = $('notice');
  box.textContent = text;
  box.hidden = !text;
  box.dataset.key = key;
  statusChanged();
}

/** Takes the notice away if it is the one shown with `key`. */
export function clearNotice(key) {
  if ($('notice').dataset.key === key) showNotice('');
}

/** Puts `text` in the status line. */
export function say(text) {
  $('message').textContent = text;
  statusChanged();
}

/** Shows `text` in the note `id` of the status bar (hidden when empty), `title` on hover. */
export function showNote(id, text, title = '') {
  const note = $(id);
  note.hidden = !text;
  note.textContent = text;
  note.title = title;
  statusChanged();
}

/** The status bar's texts that can be cut, in the order the details view lists them. */
const CUT_TEXTS = ['message', 'progress-text', 'notice', 'viewbox-note', 'fold-note'];

/**
 * After a text of the bar changed: "more…" is offered while any text is cut, and an open
 * details view shows the texts as they are now.
 */
function statusChanged() {
  requestAnimationFrame(() => {
    const cut = CUT_TEXTS.map($).some((e) => !e.hidden && e.offsetParent && e.scrollWidth > e.clientWidth + 1);
    $('status-more').hidden = !cut && $('status-details').hidden;
    if (!$('status-details').hidden) fillDetails();
  });
}

/** Writes every shown text of the bar, in full (with its hover text), into the details view. */
function fillDetails() {
  const box = $('status-details');
  box.replaceChildren();
  for (const e of CUT_TEXTS.map($)) {
    if (e.hidden || !e.offsetParent || !e.textContent) continue;
    const p = document.createElement('p');
    p.textContent = e.title && e.id !== 'notice' ? `${e.textContent}\n${e.title}` : e.textContent;
    box.append(p);
  }
}

/** Opens or closes the details view (the "more…" button; a click on the view closes it). */
export function toggleStatusDetails() {
  const box = $('status-details');
  box.hidden = !box.hidden;
  if (!box.hidden) fillDetails();
  statusChanged();
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
    statusChanged();
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
  statusChanged();
}

/** `n thing` or `n things`. */
export function plural(n, thing) {
  return `${n} ${thing}${n === 1 ? '' : 's'}`;
}
