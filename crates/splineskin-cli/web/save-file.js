// A file handed to the browser as a download: shared by the 2D editor and the Catmull–Clark page.

/** Hands `data` (text or a Blob) to the browser as a download named `name`, of MIME type `type`. */
export function download(data, name, type) {
  const url = URL.createObjectURL(data instanceof Blob ? data : new Blob([data], { type }));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}
