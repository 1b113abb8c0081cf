// Plane geometry for the editor: points are [x, y] arrays in world coordinates (y up), poses are
// [x, y, angleDeg] as in scene/1 (a body point m sits at R(angle)·m + (x, y)).

export const DEG = Math.PI / 180;

export const add = (a, b) => [a[0] + b[0], a[1] + b[1]];
export const sub = (a, b) => [a[0] - b[0], a[1] - b[1]];
export const scale = (a, s) => [a[0] * s, a[1] * s];
export const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);
export const lerp = (a, b, t) => [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];

/** Rotates `p` by `deg` degrees counter-clockwise about the origin. */
export function rotate(p, deg) {
  const c = Math.cos(deg * DEG), s = Math.sin(deg * DEG);
  return [c * p[0] - s * p[1], s * p[0] + c * p[1]];
}

/** The world position of body point `m` at `pose`. */
export const toWorld = (pose, m) => add(rotate(m, pose[2]), [pose[0], pose[1]]);

/** The body point at world position `w` for `pose`. */
export const toBody = (pose, w) => rotate(sub(w, [pose[0], pose[1]]), -pose[2]);

export const placed = (polygon, pose) => polygon.map((m) => toWorld(pose, m));

export function signedArea(poly) {
  let s = 0;
  for (let i = 0; i < poly.length; i++) {
    const a = poly[i], b = poly[(i + 1) % poly.length];
    s += a[0] * b[1] - b[0] * a[1];
  }
  return s / 2;
}

/** The area centroid (the vertex mean for a degenerate polygon). */
export function centroid(poly) {
  const a = signedArea(poly);
  if (Math.abs(a) < 1e-12) {
    const s = poly.reduce((acc, p) => add(acc, p), [0, 0]);
    return scale(s, 1 / Math.max(poly.length, 1));
  }
  let cx = 0, cy = 0;
  for (let i = 0; i < poly.length; i++) {
    const p = poly[i], q = poly[(i + 1) % poly.length];
    const c = p[0] * q[1] - q[0] * p[1];
    cx += (p[0] + q[0]) * c;
    cy += (p[1] + q[1]) * c;
  }
  return [cx / (6 * a), cy / (6 * a)];
}

export function bounds(points) {
  let minX = Infinity, minY = Infinity, maxX = -Infinity, maxY = -Infinity;
  for (const [x, y] of points) {
    minX = Math.min(minX, x); minY = Math.min(minY, y);
    maxX = Math.max(maxX, x); maxY = Math.max(maxY, y);
  }
  return { minX, minY, maxX, maxY };
}

/** Distance from `p` to segment a–b, and the parameter of the closest point. */
export function segmentDistance(p, a, b) {
  const ab = sub(b, a);
  const len2 = ab[0] * ab[0] + ab[1] * ab[1];
  const t = len2 === 0 ? 0 : Math.max(0, Math.min(1, ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2));
  return { d: dist(p, add(a, scale(ab, t))), t };
}

/** The four corners of the box spanned by two points, counter-clockwise. */
export function rectangle(a, b) {
  const x0 = Math.min(a[0], b[0]), x1 = Math.max(a[0], b[0]);
  const y0 = Math.min(a[1], b[1]), y1 = Math.max(a[1], b[1]);
  return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
}

/** An ellipse inscribed in the box spanned by two points, as a polygon of `n` vertices. */
export function ellipse(a, b, n = 32) {
  const c = lerp(a, b, 0.5);
  const rx = Math.abs(b[0] - a[0]) / 2, ry = Math.abs(b[1] - a[1]) / 2;
  return Array.from({ length: n }, (_, i) => {
    const t = (2 * Math.PI * i) / n;
    return [c[0] + rx * Math.cos(t), c[1] + ry * Math.sin(t)];
  });
}

/** The angle `a` (degrees) brought into (−180, 180]. */
export function wrapDeg(a) {
  let w = ((a % 360) + 360) % 360;
  return w > 180 ? w - 360 : w;
}

/** Rounds to a tidy number of decimals for display and files. */
export const tidy = (x, decimals = 3) => Math.round(x * 10 ** decimals) / 10 ** decimals;
