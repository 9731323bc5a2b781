// The WebGL2 drawing of the page: the limit surface shaded (a light at the eye and a dim one
// from above, two-sided), painted by one handle's weight on demand, the cage as lines on
// demand, the handles as dots, the bones as segments and the selected handle's gizmo
// (gizmo.js). Geometry is uploaded by `setMesh` (topology), `setPositions` (per frame),
// `setWeights`, `setHandles`, `setBones` and `setGizmo`; `draw` renders with a camera's matrix.

import { GIZMO_PARTS } from './gizmo.js';

const SURFACE_VERTEX = `#version 300 es
uniform mat4 u_matrix;
in vec3 a_position;
in vec3 a_normal;
in float a_weight;
out vec3 v_normal;
out vec3 v_position;
out float v_weight;
void main() {
  v_normal = a_normal;
  v_position = a_position;
  v_weight = a_weight;
  gl_Position = u_matrix * vec4(a_position, 1.0);
}`;

const SURFACE_FRAGMENT = `#version 300 es
precision highp float;
uniform vec3 u_eye;
uniform bool u_paint;
in vec3 v_normal;
in vec3 v_position;
in float v_weight;
out vec4 colour;
void main() {
  vec3 n = normalize(v_normal);
  vec3 toEye = normalize(u_eye - v_position);
  float facing = abs(dot(n, toEye));
  float sky = 0.5 + 0.5 * n.y;
  vec3 base = gl_FrontFacing ? vec3(0.30, 0.48, 0.80) : vec3(0.75, 0.45, 0.30);
  if (u_paint) {
    // White (weight 0) to red (weight 1).
    base = mix(vec3(0.95, 0.95, 0.95), vec3(0.85, 0.10, 0.10), clamp(v_weight, 0.0, 1.0));
  }
  colour = vec4(base * (0.25 + 0.6 * facing + 0.2 * sky), 1.0);
}`;

const LINE_VERTEX = `#version 300 es
uniform mat4 u_matrix;
in vec3 a_position;
void main() { gl_Position = u_matrix * vec4(a_position, 1.0); }`;

const LINE_FRAGMENT = `#version 300 es
precision highp float;
uniform vec3 u_colour;
out vec4 colour;
void main() { colour = vec4(u_colour, 1.0); }`;

const POINT_VERTEX = `#version 300 es
uniform mat4 u_matrix;
in vec3 a_position;
void main() {
  gl_Position = u_matrix * vec4(a_position, 1.0);
  gl_PointSize = 12.0;
}`;

const CAGE_COLOUR = [0.12, 0.12, 0.15];
const HANDLE_COLOUR = [0.1, 0.1, 0.1];
const SELECTED_COLOUR = [0.9, 0.2, 0.1];

/** A view drawing into `canvas`; throws when the browser has no WebGL2. */
export function createView(canvas) {
  const gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true });
  if (!gl) {
    throw new Error('this browser has no WebGL2, which the 3D view needs');
  }
  const surface = program(gl, SURFACE_VERTEX, SURFACE_FRAGMENT);
  const lines = program(gl, LINE_VERTEX, LINE_FRAGMENT);
  const points = program(gl, POINT_VERTEX, LINE_FRAGMENT);
  const buffers = {
    position: gl.createBuffer(),
    normal: gl.createBuffer(),
    weight: gl.createBuffer(),
    triangles: gl.createBuffer(),
    cage: gl.createBuffer(),
    edges: gl.createBuffer(),
    handles: gl.createBuffer(),
    bones: gl.createBuffer(),
    gizmo: gl.createBuffer(),
  };
  const counts = { triangles: 0, edges: 0, handles: 0, bones: 0, gizmo: false };
  return {
    setMesh(triangles, edges) {
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, buffers.triangles);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(triangles), gl.STATIC_DRAW);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, buffers.edges);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(edges), gl.STATIC_DRAW);
      counts.triangles = triangles.length;
      counts.edges = edges.length;
    },
    setPositions(surfacePositions, normals, cagePositions) {
      upload(gl, buffers.position, surfacePositions);
      upload(gl, buffers.normal, normals);
      upload(gl, buffers.cage, cagePositions);
    },
    /** One weight per surface vertex (painted when `draw` is asked to paint). */
    setWeights(weights) {
      upload(gl, buffers.weight, weights);
    },
    /** Handle positions, x, y, z flat. */
    setHandles(positions) {
      upload(gl, buffers.handles, positions);
      counts.handles = positions.length / 3;
    },
    /** The bones' segments now, x, y, z flat (boneSegments: six numbers per bone). */
    setBones(segments) {
      upload(gl, buffers.bones, segments);
      counts.bones = segments.length / 6;
    },
    /** The gizmo's segments (gizmoLines), or null for none. */
    setGizmo(lines) {
      counts.gizmo = lines != null;
      if (lines) upload(gl, buffers.gizmo, lines);
    },
    /** `selectedBone`: the index among the bones of the selected one, if a bone is selected. */
    draw(matrix, eyePosition, { showCage, paint, selected, selectedBone = null }) {
      resize(gl);
      gl.clearColor(1, 1, 1, 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      gl.enable(gl.DEPTH_TEST);
      gl.useProgram(surface.program);
      gl.uniformMatrix4fv(surface.uniform('u_matrix'), false, matrix);
      gl.uniform3fv(surface.uniform('u_eye'), eyePosition);
      gl.uniform1i(surface.uniform('u_paint'), paint ? 1 : 0);
      attribute(gl, surface, 'a_position', buffers.position);
      attribute(gl, surface, 'a_normal', buffers.normal);
      const weight = surface.attribute('a_weight');
      if (paint) {
        gl.bindBuffer(gl.ARRAY_BUFFER, buffers.weight);
        gl.enableVertexAttribArray(weight);
        gl.vertexAttribPointer(weight, 1, gl.FLOAT, false, 0, 0);
      } else {
        gl.disableVertexAttribArray(weight);
        gl.vertexAttrib1f(weight, 0);
      }
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, buffers.triangles);
      gl.drawElements(gl.TRIANGLES, counts.triangles, gl.UNSIGNED_INT, 0);
      for (const name of ['a_normal', 'a_weight']) gl.disableVertexAttribArray(surface.attribute(name));
      gl.disable(gl.DEPTH_TEST);
      if (showCage) {
        gl.useProgram(lines.program);
        gl.uniformMatrix4fv(lines.uniform('u_matrix'), false, matrix);
        gl.uniform3fv(lines.uniform('u_colour'), CAGE_COLOUR);
        attribute(gl, lines, 'a_position', buffers.cage);
        gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, buffers.edges);
        gl.drawElements(gl.LINES, counts.edges, gl.UNSIGNED_INT, 0);
      }
      if (counts.bones > 0 || counts.gizmo) {
        gl.useProgram(lines.program);
        gl.uniformMatrix4fv(lines.uniform('u_matrix'), false, matrix);
      }
      if (counts.bones > 0) {
        attribute(gl, lines, 'a_position', buffers.bones);
        gl.uniform3fv(lines.uniform('u_colour'), HANDLE_COLOUR);
        gl.drawArrays(gl.LINES, 0, 2 * counts.bones);
        if (selectedBone != null && selectedBone < counts.bones) {
          gl.uniform3fv(lines.uniform('u_colour'), SELECTED_COLOUR);
          gl.drawArrays(gl.LINES, 2 * selectedBone, 2);
        }
      }
      if (counts.gizmo) {
        attribute(gl, lines, 'a_position', buffers.gizmo);
        for (const part of GIZMO_PARTS) {
          gl.uniform3fv(lines.uniform('u_colour'), part.colour);
          gl.drawArrays(gl.LINES, part.first, part.count);
        }
      }
      if (counts.handles > 0) {
        gl.useProgram(points.program);
        gl.uniformMatrix4fv(points.uniform('u_matrix'), false, matrix);
        attribute(gl, points, 'a_position', buffers.handles);
        gl.uniform3fv(points.uniform('u_colour'), HANDLE_COLOUR);
        gl.drawArrays(gl.POINTS, 0, counts.handles);
        if (selected != null && selected < counts.handles) {
          gl.uniform3fv(points.uniform('u_colour'), SELECTED_COLOUR);
          gl.drawArrays(gl.POINTS, selected, 1);
        }
      }
    },
  };
}

/** f32 copies of the values uploaded as something else (the cage's f64), kept per buffer. */
const scratch = new WeakMap();

function upload(gl, buffer, values) {
  let data = values;
  if (!(values instanceof Float32Array)) {
    data = scratch.get(buffer);
    if (!data || data.length !== values.length) {
      data = new Float32Array(values.length);
      scratch.set(buffer, data);
    }
    data.set(values);
  }
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  gl.bufferData(gl.ARRAY_BUFFER, data, gl.DYNAMIC_DRAW);
}

function attribute(gl, { attribute: location }, name, buffer) {
  const at = location(name);
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  gl.enableVertexAttribArray(at);
  gl.vertexAttribPointer(at, 3, gl.FLOAT, false, 0, 0);
}

/** Matches the drawing buffer to the canvas's size on screen. */
function resize(gl) {
  const canvas = gl.canvas;
  const ratio = window.devicePixelRatio || 1;
  const width = Math.max(1, Math.round(canvas.clientWidth * ratio));
  const height = Math.max(1, Math.round(canvas.clientHeight * ratio));
  if (canvas.width !== width || canvas.height !== height) {
    canvas.width = width;
    canvas.height = height;
  }
  gl.viewport(0, 0, width, height);
}

function program(gl, vertexSource, fragmentSource) {
  const shader = (type, source) => {
    const s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) {
      throw new Error(`shader: ${gl.getShaderInfoLog(s)}`);
    }
    return s;
  };
  const p = gl.createProgram();
  gl.attachShader(p, shader(gl.VERTEX_SHADER, vertexSource));
  gl.attachShader(p, shader(gl.FRAGMENT_SHADER, fragmentSource));
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) {
    throw new Error(`program: ${gl.getProgramInfoLog(p)}`);
  }
  return {
    program: p,
    uniform: (name) => gl.getUniformLocation(p, name),
    attribute: (name) => gl.getAttribLocation(p, name),
  };
}
