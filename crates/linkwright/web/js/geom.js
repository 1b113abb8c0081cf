// @ts-check
// Plane geometry for the editor: points are [x, y] arrays in world coordinates (y up), poses are
// [x, y, angleDeg] as in scene/1 (a body point m sits at R(angle)·m + (x, y)).

/**
 * @typedef {[number, number]} Point  A point `[x, y]` (world coordinates, y up; or a body's own frame;
 *   or screen pixels, y down, where a name says so). The offset between two is a Point too.
 * @typedef {[number, number, number]} Pose  A body's pose `[x, y, angle_deg]`: its frame's origin and
 *   its counter-clockwise turn.
 * @typedef {Point[]} Polygon  An outline, its corners in order.
 * @typedef {{minX: number, minY: number, maxX: number, maxY: number}} Bounds  A box along the axes.
 */

export const DEG = Math.PI / 180;

/** @type {(a: Point, b: Point) => Point} */
export const add = (a, b) => [a[0] + b[0], a[1] + b[1]];
/** @type {(a: Point, b: Point) => Point} */
export const sub = (a, b) => [a[0] - b[0], a[1] - b[1]];
/** @type {(a: Point, s: number) => Point} */
export const scale = (a, s) => [a[0] * s, a[1] * s];
/** @type {(a: Point, b: Point) => number} */
export const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);
/** @type {(a: Point, b: Point, t: number) => Point} */
export const lerp = (a, b, t) => [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];

/**
 * Rotates `p` by `deg` degrees counter-clockwise about the origin.
 * @param {Point} p
 * @param {number} deg
 * @returns {Point}
 */
export function rotate(p, deg) {
  const c = Math.cos(deg * DEG), s = Math.sin(deg * DEG);
  return [c * p[0] - s * p[1], s * p[0] + c * p[1]];
}

/** The world position of body point `m` at `pose`. @type {(pose: Pose, m: Point) => Point} */
export const toWorld = (pose, m) => add(rotate(m, pose[2]), [pose[0], pose[1]]);

/** The body point at world position `w` for `pose`. @type {(pose: Pose, w: Point) => Point} */
export const toBody = (pose, w) => rotate(sub(w, [pose[0], pose[1]]), -pose[2]);

/** A body's outline placed at `pose`, in world coordinates. @type {(polygon: Polygon, pose: Pose) => Polygon} */
export const placed = (polygon, pose) => polygon.map((m) => toWorld(pose, m));

/**
 * The area of `poly`, positive when its corners go counter-clockwise.
 * @param {Polygon} poly
 */
export function signedArea(poly) {
  let s = 0;
  for (let i = 0; i < poly.length; i++) {
    const a = poly[i], b = poly[(i + 1) % poly.length];
    s += a[0] * b[1] - b[0] * a[1];
  }
  return s / 2;
}

/**
 * The area centroid (the vertex mean for a degenerate polygon).
 * @param {Polygon} poly
 * @returns {Point}
 */
export function centroid(poly) {
  const a = signedArea(poly);
  if (Math.abs(a) < 1e-12) {
    const s = poly.reduce((acc, p) => add(acc, p), /** @type {Point} */ ([0, 0]));
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

/**
 * The box around `points` (empty: infinite the wrong way round).
 * @param {Point[]} points
 * @returns {Bounds}
 */
export function bounds(points) {
  let minX = Infinity, minY = Infinity, maxX = -Infinity, maxY = -Infinity;
  for (const [x, y] of points) {
    minX = Math.min(minX, x); minY = Math.min(minY, y);
    maxX = Math.max(maxX, x); maxY = Math.max(maxY, y);
  }
  return { minX, minY, maxX, maxY };
}

/**
 * Distance from `p` to segment a–b, and the parameter of the closest point.
 * @param {Point} p
 * @param {Point} a
 * @param {Point} b
 * @returns {{d: number, t: number}}
 */
export function segmentDistance(p, a, b) {
  const ab = sub(b, a);
  const len2 = ab[0] * ab[0] + ab[1] * ab[1];
  const t = len2 === 0 ? 0 : Math.max(0, Math.min(1, ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2));
  return { d: dist(p, add(a, scale(ab, t))), t };
}

/**
 * The four corners of the box spanned by two points, counter-clockwise.
 * @param {Point} a
 * @param {Point} b
 * @returns {Polygon}
 */
export function rectangle(a, b) {
  const x0 = Math.min(a[0], b[0]), x1 = Math.max(a[0], b[0]);
  const y0 = Math.min(a[1], b[1]), y1 = Math.max(a[1], b[1]);
  return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
}

/**
 * An ellipse inscribed in the box spanned by two points, as a polygon of `n` vertices.
 * @param {Point} a
 * @param {Point} b
 * @returns {Polygon}
 */
export function ellipse(a, b, n = 32) {
  const c = lerp(a, b, 0.5);
  const rx = Math.abs(b[0] - a[0]) / 2, ry = Math.abs(b[1] - a[1]) / 2;
  return Array.from({ length: n }, (_, i) => {
    const t = (2 * Math.PI * i) / n;
    /** @type {Point} */
    const p = [c[0] + rx * Math.cos(t), c[1] + ry * Math.sin(t)];
    return p;
  });
}

/**
 * The angle `a` (degrees) brought into (−180, 180].
 * @param {number} a
 */
export function wrapDeg(a) {
  let w = ((a % 360) + 360) % 360;
  return w > 180 ? w - 360 : w;
}

/** Rounds to a tidy number of decimals for display and files. @type {(x: number, decimals?: number) => number} */
export const tidy = (x, decimals = 3) => Math.round(x * 10 ** decimals) / 10 ** decimals;

/** @type {(a: Point, b: Point) => number} */
const cross = (a, b) => a[0] * b[1] - a[1] * b[0];

/**
 * True when segments a0–a1 and b0–b1 cross away from their ends (by more than `tol` along each).
 * @param {Point} a0
 * @param {Point} a1
 * @param {Point} b0
 * @param {Point} b1
 * @param {number} tol
 */
function segmentsCross(a0, a1, b0, b1, tol) {
  const da = sub(a1, a0), db = sub(b1, b0);
  const denom = cross(da, db), la = Math.hypot(...da), lb = Math.hypot(...db);
  if (la === 0 || lb === 0 || Math.abs(denom) <= 1e-12 * la * lb) return false;
  const w = sub(b0, a0);
  const t = cross(w, db) / denom, u = cross(w, da) / denom;
  return t > tol / la && t < 1 - tol / la && u > tol / lb && u < 1 - tol / lb;
}

/**
 * The narrowest width of `points` (the least distance between two parallel lines with all of them
 * between): across the direction of some pair of them, so every pair is tried.
 * @param {Point[]} points
 */
export function narrowestWidth(points) {
  let best = Infinity;
  for (let i = 0; i < points.length; i++) {
    for (let j = i + 1; j < points.length; j++) {
      const d = sub(points[j], points[i]), len = Math.hypot(...d);
      if (len === 0) continue;
      let lo = 0, hi = 0;
      for (const p of points) {
        const s = cross(d, sub(p, points[i])) / len;
        lo = Math.min(lo, s);
        hi = Math.max(hi, s);
      }
      best = Math.min(best, hi - lo);
    }
  }
  return best === Infinity ? 0 : best;
}

/**
 * @typedef {{kind: 'few'} | {kind: 'flat', width: number} | {kind: 'crossing', sides: [number, number]}} OutlineProblem
 *   Why an outline cannot be a shape (see `outlineProblem`).
 */

/**
 * Why `points` (an outline, in order) cannot be a shape, or null when they can: `{kind: 'few'}` for
 * fewer than three corners, `{kind: 'flat', width}` when it is narrower than `minWidth` (on one line,
 * or almost), `{kind: 'crossing', sides: [i, j]}` (0-based, side i from corner i to the next) when it
 * crosses itself. What the engine refuses (`Polygon::validate`: too few corners, no area, crossing),
 * and with `minWidth` a sliver it would take, which is of no use as a part.
 * @param {Point[]} points
 * @param {number} [minWidth]
 * @returns {OutlineProblem | null}
 */
export function outlineProblem(points, minWidth = 0) {
  const n = points.length;
  if (n < 3) return { kind: 'few' };
  const box = bounds(points);
  const size = Math.hypot(box.maxX - box.minX, box.maxY - box.minY);
  const width = narrowestWidth(points);
  if (width <= 1e-9 * size || width < minWidth) return { kind: 'flat', width };
  const tol = 1e-9 * size;
  for (let i = 0; i < n; i++) {
    for (let j = i + 1; j < n; j++) {
      const [a0, a1] = [points[i], points[(i + 1) % n]];
      const [b0, b1] = [points[j], points[(j + 1) % n]];
      if (j === i + 1 || (i === 0 && j === n - 1)) {
        // Neighbouring sides meet at their shared corner only: one folded back onto the other is a spike.
        const [shared, u0, v0] = j === i + 1 ? [a1, a0, b1] : [a0, a1, b0];
        const u = sub(u0, shared), v = sub(v0, shared);
        const folded = Math.abs(cross(u, v)) <= 1e-12 * Math.hypot(...u) * Math.hypot(...v) && u[0] * v[0] + u[1] * v[1] > 0;
        if (folded) return { kind: 'crossing', sides: [i, j] };
      } else if (segmentsCross(a0, a1, b0, b1, tol) || segmentDistance(b0, a0, a1).d <= tol || segmentDistance(a0, b0, b1).d <= tol) {
        return { kind: 'crossing', sides: [i, j] };
      }
    }
  }
  // Wide, not crossing, yet of no area: only within rounding of the engine's own test.
  if (Math.abs(signedArea(points)) <= 1e-9 * size * size) return { kind: 'flat', width };
  return null;
}

/**
 * True when `p` is inside `poly` (even-odd; a point on the boundary may answer either way).
 * @param {Polygon} poly
 * @param {Point} p
 */
export function contains(poly, p) {
  let inside = false;
  for (let i = 0, j = poly.length - 1; i < poly.length; j = i++) {
    const [a, b] = [poly[i], poly[j]];
    if ((a[1] > p[1]) !== (b[1] > p[1]) && p[0] < ((b[0] - a[0]) * (p[1] - a[1])) / (b[1] - a[1]) + a[0]) inside = !inside;
  }
  return inside;
}

/**
 * The distance from `p` to the area of `poly`: 0 inside.
 * @param {Polygon} poly
 * @param {Point} p
 */
export function distanceTo(poly, p) {
  if (contains(poly, p)) return 0;
  return Math.min(...poly.map((a, i) => segmentDistance(p, a, poly[(i + 1) % poly.length]).d));
}

/**
 * A smooth curve through `points` (a centripetal Catmull-Rom spline, which neither overshoots
 * between unevenly spaced points nor loops), `steps` points per span from each point to the next;
 * round the loop back to the first when `closed`. The points themselves are on it.
 * @param {Point[]} points
 * @param {boolean} closed
 * @param {number} steps
 * @returns {Point[]}
 */
export function smoothThrough(points, closed, steps) {
  const n = points.length;
  if (n < 3) return points.slice();
  /** @type {(i: number) => Point} */
  const at = (i) => {
    if (closed) return points[((i % n) + n) % n];
    // Past the ends, the end's neighbour mirrored through it.
    if (i < 0) return sub(scale(points[0], 2), points[1]);
    if (i >= n) return sub(scale(points[n - 1], 2), points[n - 2]);
    return points[i];
  };
  /** @type {Point[]} */
  const out = [];
  const spans = closed ? n : n - 1;
  for (let i = 0; i < spans; i++) {
    const [p0, p1, p2, p3] = [at(i - 1), at(i), at(i + 1), at(i + 2)];
    // Knots spaced by the square root of the chords (the centripetal choice); a repeated point
    // would give a zero span, so each is kept above a tiny length.
    const t1 = Math.max(Math.sqrt(dist(p0, p1)), 1e-9);
    const t2 = t1 + Math.max(Math.sqrt(dist(p1, p2)), 1e-9);
    const t3 = t2 + Math.max(Math.sqrt(dist(p2, p3)), 1e-9);
    /** @type {(a: Point, b: Point, ta: number, tb: number, t: number) => Point} */
    const mix = (a, b, ta, tb, t) => lerp(a, b, (t - ta) / (tb - ta));
    for (let k = 0; k < steps; k++) {
      const t = t1 + ((t2 - t1) * k) / steps;
      const a1 = mix(p0, p1, 0, t1, t), a2 = mix(p1, p2, t1, t2, t), a3 = mix(p2, p3, t2, t3, t);
      const b1 = mix(a1, a2, 0, t2, t), b2 = mix(a2, a3, t1, t3, t);
      out.push(mix(b1, b2, t1, t2, t));
    }
  }
  if (!closed) out.push(points[n - 1]);
  return out;
}
