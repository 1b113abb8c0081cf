// @ts-check
// The 3D preview of a fabrication: every printed part's mesh in its assembled place, moving with the
// linkage. Plain WebGL 2: one indexed mesh per part drawn with its carrier's pose, flat shading from
// screen-space derivatives, a light that follows the camera. Drag to turn, scroll to zoom,
// double-click to see everything again. The scene is y-up with z towards the viewer, as drawn.
// Why our own viewer and not three.js: the parts are a few thousand flat-shaded triangles moved by
// planar poses, which takes some 250 lines, while a 3D library is megabytes of someone else's code to
// embed in the binary or to fetch, and the app fetches nothing from the internet.

import { bodyColour } from './canvas.js';
import { cross, lookAt, multiply, normalize, perspective, planar } from './mat4.js';

/**
 * @typedef {import('./api.js').Preview} Preview
 * @typedef {import('./mat4.js').Vec3} Vec3
 * @typedef {import('./mat4.js').Mat4} Mat4
 * @typedef {{vao: WebGLVertexArrayObject, buffers: WebGLBuffer[], count: number}} Mesh  a mesh uploaded
 * @typedef {Mesh & {carrier: number, colour: Vec3}} PartMesh  a part's mesh, its carrier and colour
 * @typedef {{target: Vec3, radius: number, distance: number, yaw: number, pitch: number}} Camera
 *   The camera orbits `target` at `distance`, turned by `yaw` and `pitch` (radians); `radius` is the
 *   sphere around everything shown.
 */

/** What each kind of part looks like; `body` parts take their moving body's colour, as in the drawing. @type {Record<string, [string, string]>} */
export const ROLE_COLOURS = {
  ground: ['#b8bec6', 'Fixed body'],
  body: ['#e67e22', 'Moving body'],
  link: ['#4a6fa5', 'Link'],
  crank: ['#b03a2e', 'Crank (turn it)'],
  connector: ['#2a9d8f', 'Connector and pins'],
  guide: ['#8e5cc2', 'Slider guide'],
  spring_bracket: ['#e9c46a', 'Spring bracket'],
  spring: ['#5c677d', 'Spring'],
};

/** Coils of the drawn springs, and their wire's radius as a share of the coil's. */
const COILS = 10;
const WIRE = 0.16;

/**
 * A spring of unit length along x and unit coil radius: a wire tube around a helix from x = 0 to 1.
 * Drawn with a model matrix that stretches x to the hooks' distance, so the coils spread as it does.
 */
function unitSpring() {
  const steps = COILS * 12, sides = 6;
  /** @type {number[]} */
  const positions = [];
  /** @type {number[]} */
  const indices = [];
  for (let i = 0; i <= steps; i++) {
    const t = i / steps, a = 2 * Math.PI * COILS * t;
    const radial = [0, Math.cos(a), Math.sin(a)];
    for (let k = 0; k < sides; k++) {
      const b = (2 * Math.PI * k) / sides, c = Math.cos(b) * WIRE, s = Math.sin(b) * WIRE;
      // The wire's section: across the coil a share of its radius, along the axis a share of the pitch
      // (both stretch with the spring).
      positions.push(t + (s / WIRE) * (0.3 / COILS), radial[1] * (1 + c), radial[2] * (1 + c));
    }
  }
  for (let i = 0; i < steps; i++) {
    for (let k = 0; k < sides; k++) {
      const a = i * sides + k, b = i * sides + ((k + 1) % sides), c = a + sides, d = b + sides;
      indices.push(a, b, d, a, d, c);
    }
  }
  return { positions, indices };
}

/** @type {[number, number, number]} */
const BACKGROUND = [0.965, 0.972, 0.98];
const IDENTITY = planar(0, 0, 0);
const FOV = (35 * Math.PI) / 180;

const VERTEX = `#version 300 es
uniform mat4 u_view_projection;
uniform mat4 u_model;
in vec3 a_position;
out vec3 v_world;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  gl_Position = u_view_projection * world;
}`;

const FRAGMENT = `#version 300 es
precision highp float;
uniform vec3 u_colour;
uniform vec3 u_light;
uniform vec3 u_eye;
in vec3 v_world;
out vec4 colour;
void main() {
  // The face's normal from how the position changes across the screen, turned towards the eye.
  vec3 n = normalize(cross(dFdx(v_world), dFdy(v_world)));
  vec3 to_eye = normalize(u_eye - v_world);
  if (dot(n, to_eye) < 0.0) n = -n;
  float diffuse = max(dot(n, u_light), 0.0);
  float rim = pow(1.0 - max(dot(n, to_eye), 0.0), 3.0);
  colour = vec4(u_colour * (0.38 + 0.62 * diffuse) + 0.06 * rim, 1.0);
}`;

/** `#rrggbb` as three numbers from 0 to 1. @type {(hex: string) => Vec3} */
const rgb = (hex) => [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16) / 255);

/**
 * The key of a part (of the preview or the report) in ROLE_COLOURS.
 * @param {{role: string, name: string}} part
 */
export function partKind(part) {
  if (part.role === 'link' && part.name === 'crank') return 'crank';
  return part.role in ROLE_COLOURS ? part.role : 'link';
}

/**
 * The colour of a part: its kind's, or for a moving body, that body's colour in the drawing.
 * @param {{role: string, name: string, body?: number}} part
 */
export function partColour(part) {
  return part.role === 'body' ? bodyColour(part.body ?? 0) : ROLE_COLOURS[partKind(part)][0];
}

/**
 * A shader compiled.
 * @param {WebGL2RenderingContext} gl
 * @param {number} type
 * @param {string} source
 */
function compile(gl, type, source) {
  const shader = gl.createShader(type);
  if (!shader) throw new Error('shader');
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(shader) || 'shader');
  return shader;
}

/**
 * The one program the preview draws with.
 * @param {WebGL2RenderingContext} gl
 */
function program(gl) {
  const p = gl.createProgram();
  if (!p) throw new Error('program');
  gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, VERTEX));
  gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT));
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p) || 'program');
  return p;
}

export class Preview3D {
  /**
   * Draws into `canvas`; check `available` before use (WebGL 2 may be off or missing).
   * @param {HTMLCanvasElement} canvas
   */
  constructor(canvas) {
    this.canvas = canvas;
    /** @type {PartMesh[]} */
    this.parts = [];
    /** @type {number[][]} */
    this.poses = [];
    /** @type {NonNullable<Preview['springs']>} */
    this.springs = [];
    /** @type {Mesh | null} */
    this.springMesh = null;
    /** @type {{min: Vec3, max: Vec3} | null} */
    this.bounds = null;
    /** @type {Camera | null} */
    this.camera = null;
    this.t = 0;
    this.frames = 0;
    this.raf = 0;
    /** @type {(() => void) | null} called when the browser takes the 3D context away */
    this.onLost = null;
    /** @type {WebGL2RenderingContext | null} */
    this.gl = null;
    /** @type {WebGLProgram | null} */
    this.program = null;
    /** @type {Record<string, WebGLUniformLocation | null>} */
    this.at = {};
    this.position = 0;
    try {
      this.gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true });
      if (this.gl) this.program = program(this.gl);
    } catch {
      this.gl = null;
    }
    const gl = this.gl, shading = this.program;
    if (!gl || !shading) return;
    this.at = Object.fromEntries(['u_view_projection', 'u_model', 'u_colour', 'u_light', 'u_eye']
      .map((u) => [u, gl.getUniformLocation(shading, u)]));
    this.position = gl.getAttribLocation(shading, 'a_position');
    canvas.addEventListener('webglcontextlost', (e) => {
      e.preventDefault();
      this.gl = null;
      this.onLost?.();
    });
    this.listen();
    new ResizeObserver(() => this.request()).observe(canvas);
  }

  get available() {
    return !!this.gl && !!this.program;
  }

  /**
   * Shows a fabrication's preview (the `preview` member of the fabricate answer).
   * @param {Preview} preview
   */
  load(preview) {
    const gl = this.gl;
    if (!gl || !this.available) return;
    for (const p of this.parts) {
      gl.deleteVertexArray(p.vao);
      p.buffers.forEach((b) => gl.deleteBuffer(b));
    }
    this.parts = preview.parts.map((part) =>
      ({ ...this.mesh(part), carrier: part.carrier, colour: rgb(partColour(part)) }));
    this.poses = preview.poses;
    this.springs = preview.springs || [];
    if (this.springs.length && !this.springMesh) this.springMesh = this.mesh(unitSpring());
    this.bounds = motionBounds(preview);
    this.reset();
  }

  /**
   * A triangle mesh (`positions`, `indices`) uploaded: its vertex array, buffers and index count.
   * @param {{positions: number[], indices: number[]}} mesh
   * @returns {Mesh}
   */
  mesh({ positions, indices }) {
    const gl = this.gl;
    if (!gl) throw new Error('no WebGL 2 context');
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const vertices = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, vertices);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(positions), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(this.position);
    gl.vertexAttribPointer(this.position, 3, gl.FLOAT, false, 0, 0);
    const elements = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, elements);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(indices), gl.STATIC_DRAW);
    gl.bindVertexArray(null);
    return { vao, buffers: [vertices, elements], count: indices.length };
  }

  /**
   * Shows the configuration at fraction `t` of the motion (0 the first pose, 1 the last).
   * @param {number} t
   */
  setFraction(t) {
    this.t = Math.max(0, Math.min(1, Number.isFinite(t) ? t : 0));
    this.request();
  }

  /** Back to the whole assembly, seen from the front, a little from the side and above. */
  reset() {
    const b = this.bounds;
    if (!b) return;
    const radius = Math.max(Math.hypot(b.max[0] - b.min[0], b.max[1] - b.min[1], b.max[2] - b.min[2]) / 2, 1);
    this.camera = {
      target: [0, 1, 2].map((k) => (b.min[k] + b.max[k]) / 2),
      radius,
      // The sphere around every configuration of the motion just fits, so no part leaves the view.
      distance: radius / Math.sin(FOV / 2),
      yaw: -0.45,
      pitch: 0.35,
    };
    this.request();
  }

  /** Draws again on the next animation frame. */
  request() {
    if (this.raf || !this.available) return;
    this.raf = requestAnimationFrame(() => {
      this.raf = 0;
      this.draw();
    });
  }

  /** Draws the parts (and springs) at the current fraction of the motion. */
  draw() {
    const { gl, canvas, camera } = this;
    if (!gl || !this.available || !camera || canvas.clientWidth === 0) return;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.round(canvas.clientWidth * dpr), h = Math.round(canvas.clientHeight * dpr);
    if (canvas.width !== w || canvas.height !== h) {
      canvas.width = w;
      canvas.height = h;
    }
    gl.viewport(0, 0, w, h);
    gl.clearColor(...BACKGROUND, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.useProgram(this.program);

    const { target, distance, yaw, pitch, radius } = camera;
    const back = [Math.cos(pitch) * Math.sin(yaw), Math.sin(pitch), Math.cos(pitch) * Math.cos(yaw)];
    const eye = back.map((v, k) => target[k] + distance * v);
    const up = [0, 1, 0];
    const near = Math.max(distance - 2 * radius, distance / 100), far = distance + 2 * radius;
    gl.uniformMatrix4fv(this.at.u_view_projection, false, multiply(perspective(FOV, w / h, near, far), lookAt(eye, target, up)));
    // The light comes from over the viewer's left shoulder.
    const right = normalize(cross(up, back));
    gl.uniform3fv(this.at.u_light, normalize(back.map((v, k) => v + 0.6 * up[k] - 0.4 * right[k])));
    gl.uniform3fv(this.at.u_eye, eye);

    const models = this.carrierModels();
    for (const p of this.parts) {
      gl.uniformMatrix4fv(this.at.u_model, false, models[p.carrier] || IDENTITY);
      gl.uniform3fv(this.at.u_colour, p.colour);
      gl.bindVertexArray(p.vao);
      gl.drawElements(gl.TRIANGLES, p.count, gl.UNSIGNED_INT, 0);
    }
    // Each spring from its ground hook to its moving hook, wherever their carriers have them now.
    if (this.springMesh) {
      gl.uniform3fv(this.at.u_colour, rgb(ROLE_COLOURS.spring[0]));
      gl.bindVertexArray(this.springMesh.vao);
      for (const spring of this.springs) {
        const [a, b] = spring.hooks.map(([carrier, x, y]) => {
          /** @type {Mat4} */
          const m = models[carrier] || IDENTITY;
          return [m[0] * x + m[4] * y + m[12], m[1] * x + m[5] * y + m[13]];
        });
        const along = [b[0] - a[0], b[1] - a[1]], length = Math.hypot(...along) || 1, r = spring.radius;
        const across = [-along[1] / length * r, along[0] / length * r];
        gl.uniformMatrix4fv(this.at.u_model, false, new Float32Array([
          along[0], along[1], 0, 0, across[0], across[1], 0, 0, 0, 0, r, 0, a[0], a[1], spring.z, 1]));
        gl.drawElements(gl.TRIANGLES, this.springMesh.count, gl.UNSIGNED_INT, 0);
      }
    }
    gl.bindVertexArray(null);
    this.frames += 1;
    canvas.dataset.frames = String(this.frames);
  }

  /**
   * Every carrier's pose at fraction `t`, interpolated between the rows around it.
   * @returns {Mat4[]}
   */
  carrierModels() {
    const rows = this.poses;
    if (!rows.length) return [];
    const at = this.t * (rows.length - 1);
    const i = Math.max(0, Math.min(rows.length - 1, Math.floor(at)));
    const a = rows[i], b = rows[Math.min(rows.length - 1, i + 1)], f = at - i;
    /** @type {Mat4[]} */
    const models = [];
    for (let k = 0; k + 2 < a.length; k += 3) {
      /** @type {(j: number) => number} */
      const mix = (j) => a[k + j] + (b[k + j] - a[k + j]) * f;
      models.push(planar(mix(0), mix(1), mix(2)));
    }
    return models;
  }

  /** Drag to turn, scroll to zoom, double-click to reset. */
  listen() {
    const c = this.canvas;
    /** @type {{x: number, y: number} | null} */
    let drag = null;
    c.addEventListener('pointerdown', (e) => {
      drag = { x: e.clientX, y: e.clientY };
      c.setPointerCapture(e.pointerId);
    });
    c.addEventListener('pointermove', (e) => {
      if (!drag || !this.camera) return;
      this.camera.yaw -= (e.clientX - drag.x) * 0.008;
      this.camera.pitch = Math.max(-1.5, Math.min(1.5, this.camera.pitch + (e.clientY - drag.y) * 0.008));
      drag = { x: e.clientX, y: e.clientY };
      this.request();
    });
    const end = () => { drag = null; };
    c.addEventListener('pointerup', end);
    c.addEventListener('pointercancel', end);
    c.addEventListener('wheel', (e) => {
      if (!this.camera) return;
      e.preventDefault();
      const cam = this.camera;
      cam.distance = Math.max(cam.radius * 0.3, Math.min(cam.radius * 30, cam.distance * Math.exp(e.deltaY * 0.0015)));
      this.request();
    }, { passive: false });
    c.addEventListener('dblclick', () => this.reset());
  }
}

/**
 * The box around every part in every configuration of the motion.
 * @param {Preview} preview
 * @returns {{min: Vec3, max: Vec3} | null}
 */
function motionBounds(preview) {
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  for (const row of preview.poses.length ? preview.poses : [[]]) {
    for (const part of preview.parts) {
      const [x, y, deg] = row.slice(3 * part.carrier, 3 * part.carrier + 3);
      const a = ((deg || 0) * Math.PI) / 180, cos = Math.cos(a), sin = Math.sin(a);
      const p = part.positions;
      for (let i = 0; i + 2 < p.length; i += 3) {
        const q = [(x || 0) + cos * p[i] - sin * p[i + 1], (y || 0) + sin * p[i] + cos * p[i + 1], p[i + 2]];
        for (let k = 0; k < 3; k++) {
          min[k] = Math.min(min[k], q[k]);
          max[k] = Math.max(max[k], q[k]);
        }
      }
    }
  }
  return Number.isFinite(min[0]) ? { min, max } : null;
}
