// @ts-check
// 4×4 matrices and 3-vectors for the 3D preview. Matrices are column-major, as WebGL reads them:
// m[column * 4 + row]; `multiply(a, b)` applies b first, then a.

/**
 * @typedef {number[]} Vec3  A 3-vector `[x, y, z]`.
 * @typedef {Float32Array} Mat4  A 4×4 matrix, column-major.
 */

/** @type {(a: Vec3, b: Vec3) => Vec3} */
export const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
/** @type {(a: Vec3, b: Vec3) => number} */
export const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
/** @type {(a: Vec3, b: Vec3) => Vec3} */
export const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
/** @type {(a: Vec3) => Vec3} */
export const normalize = (a) => {
  const n = Math.hypot(a[0], a[1], a[2]) || 1;
  return [a[0] / n, a[1] / n, a[2] / n];
};

/**
 * The product `a · b`: `b` applied first.
 * @param {Mat4} a
 * @param {Mat4} b
 * @returns {Mat4}
 */
export function multiply(a, b) {
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

/**
 * Perspective projection with a vertical field of view of `fovy` radians.
 * @param {number} fovy
 * @param {number} aspect
 * @param {number} near
 * @param {number} far
 * @returns {Mat4}
 */
export function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
  return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0]);
}

/**
 * World to camera: the camera at `eye` looks at `target`, with `up` pointing up on the screen.
 * @param {Vec3} eye
 * @param {Vec3} target
 * @param {Vec3} up
 * @returns {Mat4}
 */
export function lookAt(eye, target, up) {
  const z = normalize(sub(eye, target));
  const x = normalize(cross(up, z));
  const y = cross(z, x);
  return new Float32Array([
    x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0, -dot(x, eye), -dot(y, eye), -dot(z, eye), 1,
  ]);
}

/**
 * A planar rigid pose as a matrix: rotation by `angleDeg` about z, then translation by (x, y).
 * @param {number} x
 * @param {number} y
 * @param {number} angleDeg
 * @returns {Mat4}
 */
export function planar(x, y, angleDeg) {
  const a = (angleDeg * Math.PI) / 180, c = Math.cos(a), s = Math.sin(a);
  return new Float32Array([c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, x, y, 0, 1]);
}
