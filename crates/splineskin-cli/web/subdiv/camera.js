// An orbit camera: it looks at `target` from `distance` away, turned `azimuth` about the up
// axis (+y) and raised `elevation` (radians). Matrices are column-major, as WebGL takes them.

const FIELD_OF_VIEW = (35 * Math.PI) / 180;
const MAX_ELEVATION = Math.PI / 2 - 0.01;

/** A camera framing a sphere of `radius` about `centre`. */
export function fitCamera({ centre, radius }) {
  return {
    target: [...centre],
    distance: radius / Math.sin(FIELD_OF_VIEW / 2) * 1.1,
    azimuth: 0.6,
    elevation: 0.35,
    near: radius * 0.01,
  };
}

/** The camera's position in the world. */
export function eye(camera) {
  const { target, distance, azimuth, elevation } = camera;
  const c = Math.cos(elevation);
  return [
    target[0] + distance * c * Math.sin(azimuth),
    target[1] + distance * Math.sin(elevation),
    target[2] + distance * c * Math.cos(azimuth),
  ];
}

/** Turns the camera by a drag of `dx, dy` pixels. */
export function orbit(camera, dx, dy) {
  camera.azimuth -= dx * 0.01;
  camera.elevation = Math.max(-MAX_ELEVATION, Math.min(MAX_ELEVATION, camera.elevation + dy * 0.01));
}

/** Moves the target in the view plane by a drag of `dx, dy` pixels of a view `height` tall. */
export function pan(camera, dx, dy, height) {
  const [right, up] = viewAxes(camera);
  const perPixel = (2 * camera.distance * Math.tan(FIELD_OF_VIEW / 2)) / height;
  for (let k = 0; k < 3; k++) {
    camera.target[k] += (-dx * right[k] + dy * up[k]) * perPixel;
  }
}

/** The world length of one pixel, of a view `height` tall, at the depth of the point `at`. */
export function pixelSize(camera, at, height) {
  const e = eye(camera);
  const forward = viewAxes(camera)[2];
  const depth = Math.max(camera.near, at.reduce((s, v, k) => s + (v - e[k]) * forward[k], 0));
  return (2 * depth * Math.tan(FIELD_OF_VIEW / 2)) / height;
}

/**
 * The move in the world, parallel to the view, of a point at `at` dragged by `dx, dy` pixels
 * of a view `height` tall.
 */
export function dragInView(camera, at, dx, dy, height) {
  const [right, up] = viewAxes(camera);
  const perPixel = pixelSize(camera, at, height);
  return [0, 1, 2].map((k) => (dx * right[k] - dy * up[k]) * perPixel);
}

/** Zooms by a wheel step (`deltaY` > 0 moves away). */
export function zoom(camera, deltaY) {
  camera.distance *= Math.exp(deltaY * 0.001);
}

/** The view's right, up and forward directions in the world. */
export function viewAxes(camera) {
  const e = eye(camera);
  const f = normalise(camera.target.map((t, k) => t - e[k]));
  const right = normalise(cross(f, [0, 1, 0]));
  return [right, cross(right, f), f];
}

/** `projection · view` for a view `aspect` wide per unit of height. */
export function viewProjection(camera, aspect) {
  const e = eye(camera);
  const [r, u, f] = viewAxes(camera);
  const view = [
    r[0], u[0], -f[0], 0,
    r[1], u[1], -f[1], 0,
    r[2], u[2], -f[2], 0,
    -dot(r, e), -dot(u, e), dot(f, e), 1,
  ];
  const near = camera.near;
  const far = camera.distance * 4;
  const t = 1 / Math.tan(FIELD_OF_VIEW / 2);
  const projection = [
    t / aspect, 0, 0, 0,
    0, t, 0, 0,
    0, 0, (far + near) / (near - far), -1,
    0, 0, (2 * far * near) / (near - far), 0,
  ];
  return multiply(projection, view);
}

function multiply(a, b) {
  const out = new Float32Array(16);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      out[c * 4 + r] = s;
    }
  }
  return out;
}

const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalise = (a) => {
  const l = Math.hypot(a[0], a[1], a[2]) || 1;
  return [a[0] / l, a[1] / l, a[2] / l];
};
