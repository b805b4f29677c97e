// relief studio's 3D view: the heightfield as a lit mesh in metres, orbit camera (drag to turn,
// wheel to zoom). WebGL 1 with 16-bit indices: at most 181 × 181 vertices.

const orbit = { yaw: 0.6, pitch: 0.7, distance: 2.6 };
let gl = null;
let mesh = null;
let canvas = null;

const VERTEX = `
attribute vec3 position; attribute vec3 normal; attribute vec3 colour;
uniform mat4 transform; varying vec3 shade;
void main() {
  float light = max(dot(normalize(normal), normalize(vec3(-0.5, 0.8, 0.4))), 0.0) * 0.8 + 0.25;
  shade = colour * light;
  gl_Position = transform * vec4(position, 1.0);
}`;
const FRAGMENT = `precision mediump float; varying vec3 shade; void main() { gl_FragColor = vec4(shade, 1.0); }`;

/** Starts the view on `element` (a canvas) and its orbit camera. */
export function setup3d(element) {
  canvas = element;
  gl = canvas.getContext("webgl", { preserveDrawingBuffer: true, antialias: true });
  setupOrbit();
  if (!gl) return;
  const compile = (type, source) => {
    const shader = gl.createShader(type);
    gl.shaderSource(shader, source);
    gl.compileShader(shader);
    return shader;
  };
  const program = gl.createProgram();
  gl.attachShader(program, compile(gl.VERTEX_SHADER, VERTEX));
  gl.attachShader(program, compile(gl.FRAGMENT_SHADER, FRAGMENT));
  gl.linkProgram(program);
  gl.useProgram(program);
  gl.program = program;
  gl.enable(gl.DEPTH_TEST);
}

/** Shows `result` (its samples `z`, north row first), each vertex coloured `colourOf(z)` (RGB, 0–255). */
export function show3d(result, colourOf) {
  if (!gl) return;
  build(result, colourOf);
  draw();
}

/** Builds the mesh from the result: at most 181 × 181 vertices (16-bit indices). */
function build(result, colourOf) {
  const { width: w, height: h, z } = result;
  const e = result.extent;
  const step = Math.max(1, Math.ceil(Math.max(w, h) / 181));
  // Metres on every axis (a geographic grid's degrees too).
  const [mx, my] = result.metres_per_unit;
  const nx = Math.floor((w - 1) / step) + 1;
  const ny = Math.floor((h - 1) / step) + 1;
  const size = Math.max(mx * (e.max[0] - e.min[0]), my * (e.max[1] - e.min[1]));
  const exaggeration = 2.0;
  const height = (i, j) => {
    const v = z[Math.min(h - 1, j * step) * w + Math.min(w - 1, i * step)];
    return v === v ? v : result.min;
  };
  const positions = new Float32Array(nx * ny * 3);
  const normals = new Float32Array(nx * ny * 3);
  const colours = new Float32Array(nx * ny * 3);
  const sx = ((mx * (e.max[0] - e.min[0])) / size) * 2;
  const sz = ((my * (e.max[1] - e.min[1])) / size) * 2;
  const hy = (exaggeration * 2) / size;
  for (let j = 0; j < ny; j++) {
    for (let i = 0; i < nx; i++) {
      const k = j * nx + i;
      const v = height(i, j);
      positions.set([(i / Math.max(1, nx - 1) - 0.5) * sx, (v - result.min) * hy, (j / Math.max(1, ny - 1) - 0.5) * sz], 3 * k);
      const gx = (height(Math.min(nx - 1, i + 1), j) - height(Math.max(0, i - 1), j)) * hy / (2 * sx / Math.max(1, nx - 1));
      const gz = (height(i, Math.min(ny - 1, j + 1)) - height(i, Math.max(0, j - 1))) * hy / (2 * sz / Math.max(1, ny - 1));
      normals.set([-gx, 1, -gz], 3 * k);
      const [r, g, b] = colourOf(v);
      colours.set([r / 255, g / 255, b / 255], 3 * k);
    }
  }
  const indices = new Uint16Array((nx - 1) * (ny - 1) * 6);
  let n = 0;
  for (let j = 0; j + 1 < ny; j++) {
    for (let i = 0; i + 1 < nx; i++) {
      const a = j * nx + i;
      indices.set([a, a + nx, a + 1, a + 1, a + nx, a + nx + 1], n);
      n += 6;
    }
  }
  const buffer = (data, name) => {
    const b = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    const at = gl.getAttribLocation(gl.program, name);
    gl.enableVertexAttribArray(at);
    gl.vertexAttribPointer(at, 3, gl.FLOAT, false, 0, 0);
    return b;
  };
  if (mesh) mesh.buffers.forEach((b) => gl.deleteBuffer(b));
  const buffers = [buffer(positions, "position"), buffer(normals, "normal"), buffer(colours, "colour")];
  const elements = gl.createBuffer();
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, elements);
  gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, indices, gl.STATIC_DRAW);
  buffers.push(elements);
  mesh = { buffers, count: indices.length };
}

function multiply(a, b) {
  const out = new Float32Array(16);
  for (let c = 0; c < 4; c++) for (let r = 0; r < 4; r++) {
    let s = 0;
    for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
    out[c * 4 + r] = s;
  }
  return out;
}

function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2);
  const nf = 1 / (near - far);
  return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0]);
}

function lookAt(eye, target) {
  const sub = (a, b) => a.map((v, i) => v - b[i]);
  const norm = (a) => { const l = Math.hypot(...a); return a.map((v) => v / l); };
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const zAxis = norm(sub(eye, target));
  const xAxis = norm(cross([0, 1, 0], zAxis));
  const yAxis = cross(zAxis, xAxis);
  return new Float32Array([
    xAxis[0], yAxis[0], zAxis[0], 0, xAxis[1], yAxis[1], zAxis[1], 0, xAxis[2], yAxis[2], zAxis[2], 0,
    -dot(xAxis, eye), -dot(yAxis, eye), -dot(zAxis, eye), 1,
  ]);
}

function draw() {
  if (!gl || !mesh) return;
  gl.viewport(0, 0, canvas.width, canvas.height);
  gl.clearColor(0.07, 0.08, 0.1, 1);
  gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
  const d = orbit.distance;
  const eye = [d * Math.cos(orbit.pitch) * Math.sin(orbit.yaw), d * Math.sin(orbit.pitch), d * Math.cos(orbit.pitch) * Math.cos(orbit.yaw)];
  const transform = multiply(perspective(0.8, canvas.width / canvas.height, 0.05, 20), lookAt(eye, [0, 0.2, 0]));
  gl.uniformMatrix4fv(gl.getUniformLocation(gl.program, "transform"), false, transform);
  gl.drawElements(gl.TRIANGLES, mesh.count, gl.UNSIGNED_SHORT, 0);
}

function setupOrbit() {
  let drag = null;
  canvas.addEventListener("pointerdown", (e) => { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener("pointerup", () => { drag = null; });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    orbit.yaw -= (e.clientX - drag[0]) * 0.01;
    orbit.pitch = Math.max(0.05, Math.min(1.5, orbit.pitch + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    draw();
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    orbit.distance = Math.max(0.8, Math.min(8, orbit.distance * Math.exp(e.deltaY * 0.001)));
    draw();
  }, { passive: false });
}
