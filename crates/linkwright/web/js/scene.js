// @ts-check
// The scene/1 document the person edits, and the edits themselves. Every function here either reads
// a scene or changes the scene object it is given (the store snapshots it first, for undo).

import { add, bounds, centroid, dist, lerp, placed, segmentDistance, sub, tidy, toBody, toWorld, wrapDeg } from './geom.js';

/**
 * @typedef {import('./geom.js').Point} Point
 * @typedef {import('./geom.js').Pose} Pose
 * @typedef {import('./geom.js').Polygon} Polygon
 */

/**
 * The scene/1 document (docs/formats.md), as the editor holds it: `normalize` fills the lists,
 * `weights`, `settings` and `mechanism` a file may leave out.
 * @typedef {object} Scene
 * @property {'scene/1'} linkwright
 * @property {string} name
 * @property {string} [units]  what one unit of the drawing is (`mm` when absent)
 * @property {FixedBody[]} fixed_bodies
 * @property {MovingBody[]} moving_bodies
 * @property {Polygon} [linkage_region]  world coordinates
 * @property {Polygon[]} [avoid_regions]  world coordinates
 * @property {string} mechanism  `auto` or a family's id
 * @property {string} [build]  `model:auto` when absent (build.js reads it)
 * @property {number[]} [must_hit_poses]  intermediate poses (from 0) to hit as closely as the ends
 * @property {Record<string, Point>} [pinned_joints]  joints placed by the person, at the first pose
 * @property {Point} [gravity]
 * @property {Weights} weights
 * @property {Settings} settings
 *
 * @typedef {{name: string, polygon: Polygon}} FixedBody  Its outline in world coordinates.
 * @typedef {object} MovingBody
 * @property {string} name
 * @property {Polygon} polygon  in the body's own frame
 * @property {Pose[]} poses  where the body should be, in order (one, where it starts, with a path)
 * @property {DrawnPath} [path]  a curve its tracer should follow instead of poses
 * @property {number} [mass_kg]
 * @property {string} [material]
 * @property {number} [thickness]
 *
 * @typedef {{tracer: Point, points: Point[], closed?: boolean, exact?: number[]}} DrawnPath  The tracer in
 *   the body's frame, the curve in world coordinates, and the points of it (indices) the tracer must pass.
 * @typedef {{accuracy: number, smoothness: number, location: number, size: number, transmission: number}} Weights
 * @typedef {object} Settings
 * @property {number} seed
 * @property {number} samples
 * @property {number} particles
 * @property {number} iterations
 * @property {number} pose_tolerance
 * @property {number} angle_tolerance_deg
 * @property {number} min_transmission_deg
 * @property {number} comfortable_transmission_deg
 *
 * @typedef {'fixed' | 'moving' | 'region' | 'avoid'} ShapeKind  What a drawn shape is.
 * @typedef {{kind: ShapeKind, index: number, vertex?: number}} Selection  A shape of the scene (the
 *   region's index is 0), and one of its corners when `vertex` is given.
 */

/** Defaults the app writes into a new scene (the engine's own defaults, with fewer samples so a
 * first design takes seconds). */
/** @type {Settings} */
export const DEFAULT_SETTINGS = {
  seed: 0, samples: 20000, particles: 100, iterations: 20,
  pose_tolerance: 0.5, angle_tolerance_deg: 3, min_transmission_deg: 10, comfortable_transmission_deg: 35,
};
/** @type {Weights} */
export const DEFAULT_WEIGHTS = { accuracy: 10000, smoothness: 1, location: 10, size: 1, transmission: 10 };
/** The engine's defaults for fields a file leaves out. @type {Settings} */
export const ENGINE_SETTINGS = { ...DEFAULT_SETTINGS, samples: 100000 };

/**
 * An empty scene.
 * @returns {Scene}
 */
export function newScene() {
  return {
    linkwright: 'scene/1',
    name: 'untitled',
    units: 'mm',
    fixed_bodies: [],
    moving_bodies: [],
    mechanism: 'auto',
    weights: { ...DEFAULT_WEIGHTS },
    settings: { ...DEFAULT_SETTINGS },
  };
}

/**
 * Reads a scene file's JSON, filling the defaults the editor needs. Throws with a message.
 * @param {any} doc  the parsed JSON, of any shape
 * @returns {Scene}
 */
export function normalize(doc) {
  if (!doc || typeof doc !== 'object') throw new Error('the file is not a JSON object');
  if (doc.linkwright !== 'scene/1') {
    throw new Error(`this is not a scene/1 file (its "linkwright" field is ${JSON.stringify(doc.linkwright)})`);
  }
  const s = structuredClone(doc);
  s.name = typeof s.name === 'string' ? s.name : 'untitled';
  s.fixed_bodies = Array.isArray(s.fixed_bodies) ? s.fixed_bodies : [];
  s.moving_bodies = Array.isArray(s.moving_bodies) ? s.moving_bodies : [];
  if (s.avoid_regions !== undefined && !Array.isArray(s.avoid_regions)) delete s.avoid_regions;
  if (s.must_hit_poses !== undefined && !Array.isArray(s.must_hit_poses)) delete s.must_hit_poses;
  s.weights = { ...DEFAULT_WEIGHTS, ...(s.weights || {}) };
  s.settings = { ...ENGINE_SETTINGS, ...(s.settings || {}) };
  s.mechanism = s.mechanism || 'auto';
  // A build the app cannot show is kept for the engine to name; one that is not text is dropped.
  if (s.build !== undefined && typeof s.build !== 'string') delete s.build;
  for (const b of [...s.fixed_bodies, ...s.moving_bodies]) {
    if (!Array.isArray(b.polygon)) throw new Error('a body has no polygon');
  }
  for (const b of s.moving_bodies) if (!Array.isArray(b.poses)) b.poses = [];
  return s;
}

/**
 * The scene as the file is written: empty optional parts left out.
 * @param {Scene} scene
 * @returns {Scene}
 */
export function toFile(scene) {
  const s = structuredClone(scene);
  if (!s.avoid_regions || s.avoid_regions.length === 0) delete s.avoid_regions;
  if (!s.linkage_region) delete s.linkage_region;
  // The first and last poses are always hit: only intermediate marks are written.
  const n = poseCount(s);
  s.must_hit_poses = (s.must_hit_poses || []).filter((i) => i > 0 && i < n - 1);
  if (s.must_hit_poses.length === 0) delete s.must_hit_poses;
  return s;
}

/**
 * What a design depends on in the drawing (settings may change without hiding it): a design is
 * fresh while the scene's key is the one it was made for.
 * @param {Scene} scene
 */
export function geometryKey(scene) {
  return JSON.stringify([
    // A body's mass (or its material and thickness) changes the torque, not the design.
    // Nor does a body's name.
    scene.fixed_bodies.map(({ name, ...body }) => body),
    scene.moving_bodies.map(({ mass_kg, material, thickness, name, ...body }) => body), scene.linkage_region || null,
    scene.avoid_regions || [], scene.must_hit_poses || [],
  ]);
}

/** Points a drawn path keeps, spaced evenly along the stroke (the engine measures every one). */
const PATH_POINTS = 120;

/**
 * Makes `stroke` (world points, the first on moving body `body` at pose `pose`) the body's path: its
 * tracer where the stroke began, the body kept at that pose alone (where it is when the tracer
 * starts). Returns false when the scene has other moving bodies (a path is one body's motion).
 * @param {Scene} scene
 * @param {number} body
 * @param {number} pose
 * @param {Point[]} stroke
 * @param {boolean} closed
 */
export function setPath(scene, body, pose, stroke, closed) {
  if (scene.moving_bodies.length !== 1) return false;
  const b = scene.moving_bodies[body];
  const at = b.poses[Math.min(pose, b.poses.length - 1)] || [0, 0, 0];
  const tracer = toBody(at, stroke[0]).map((v) => tidy(v, 3));
  const ends = closed ? stroke.slice(0, -1) : stroke;
  b.path = { tracer: /** @type {Point} */ (tracer), points: evenly(ends, closed, PATH_POINTS).map(([x, y]) => [tidy(x, 3), tidy(y, 3)]), closed };
  b.poses = [at];
  delete scene.must_hit_poses;
  return true;
}

/**
 * Marks point `point` of body `body`'s path as one the tracer must pass exactly, or unmarks it.
 * @param {Scene} scene
 * @param {number} body
 * @param {number} point
 * @param {boolean} on
 */
export function setExact(scene, body, point, on) {
  const path = scene.moving_bodies[body]?.path;
  if (!path || !(point >= 0 && point < path.points.length)) return;
  const rest = (path.exact || []).filter((i) => i !== point);
  const exact = on ? [...rest, point].sort((a, b) => a - b) : rest;
  if (exact.length) path.exact = exact;
  else delete path.exact;
}

/**
 * The path point of body `body` nearest to world point `w` (its index), or -1 without a path.
 * @param {Scene} scene
 * @param {number} body
 * @param {Point} w
 */
export function nearestPathPoint(scene, body, w) {
  return nearestIndex(scene.moving_bodies[body]?.path?.points || [], w);
}

/**
 * The index of the point of `points` nearest `w` (-1 for none).
 * @param {Point[]} points
 * @param {Point} w
 */
function nearestIndex(points, w) {
  return points.reduce((best, p, i) => (best < 0 || dist(p, w) < dist(points[best], w) ? i : best), -1);
}

/**
 * The point of `path`'s curve nearest world point `w`.
 * @param {DrawnPath} path
 * @param {Point} w
 * @returns {Point}
 */
export function onPath(path, w) {
  const pts = path.points;
  const edges = path.closed ? pts.length : pts.length - 1;
  /** @type {{d: number, at: Point}} */
  let best = { d: Infinity, at: pts[0] };
  for (let i = 0; i < edges; i++) {
    const a = pts[i], c = pts[(i + 1) % pts.length];
    const { d, t } = segmentDistance(w, a, c);
    if (d < best.d) best = { d, at: lerp(a, c, t) };
  }
  return best.at;
}

/** How far along a path a reshaping drag reaches: this share of the path's length either side. */
const RESHAPE_REACH = 0.12;

/**
 * Bends body `body`'s path: from `points` (as it was), each point moved by `delta` times a bell of
 * its distance along the path from point `grab`. The body at each of its `poses` (as they were)
 * moves as much as the path's point nearest its tracer (the first pose: the path's first point), so
 * its tracer stays on the path.
 * @param {Scene} scene
 * @param {number} body
 * @param {Point[]} points
 * @param {Pose[]} poses
 * @param {number} grab
 * @param {Point} delta
 */
export function reshapePath(scene, body, points, poses, grab, delta) {
  const b = scene.moving_bodies[body];
  if (!b?.path || points.length !== b.path.points.length) return;
  const closed = b.path.closed;
  const at = [0];
  for (let i = 1; i < points.length; i++) at.push(at[i - 1] + dist(points[i], points[i - 1]));
  const total = at[at.length - 1] + (closed ? dist(points[points.length - 1], points[0]) : 0);
  const reach = Math.max(RESHAPE_REACH * total, 1e-9);
  /** @type {(i: number) => number} */
  const weight = (i) => {
    let d = Math.abs(at[i] - at[grab]);
    if (closed) d = Math.min(d, total - d);
    // A bell that is 1 where grabbed and 1% at `reach`.
    return Math.exp(-4.5 * (d / reach) ** 2);
  };
  b.path.points = points.map((p, i) => {
    const w = weight(i);
    return [tidy(p[0] + w * delta[0], 3), tidy(p[1] + w * delta[1], 3)];
  });
  const tracer = b.path.tracer;
  b.poses = poses.map((pose, k) => {
    const near = k === 0 ? 0 : nearestIndex(points, toWorld(pose, tracer));
    const w = weight(near);
    return [tidy(pose[0] + w * delta[0], 3), tidy(pose[1] + w * delta[1], 3), pose[2]];
  });
}

/**
 * `n` points spaced evenly by length along `points` (fewer when it has fewer), the first kept.
 * @param {Point[]} points
 * @param {boolean} closed
 * @param {number} n
 * @returns {Point[]}
 */
function evenly(points, closed, n) {
  if (points.length <= n) return points;
  const path = closed ? [...points, points[0]] : points;
  const at = [0];
  for (let i = 1; i < path.length; i++) at.push(at[i - 1] + Math.hypot(path[i][0] - path[i - 1][0], path[i][1] - path[i - 1][1]));
  const total = at[at.length - 1];
  const count = closed ? n : n - 1;
  /** @type {Point[]} */
  const out = [];
  let j = 1;
  for (let k = 0; k < n; k++) {
    const want = (total * k) / count;
    while (j < path.length - 1 && at[j] < want) j++;
    const span = at[j] - at[j - 1];
    const t = span > 0 ? Math.min(1, Math.max(0, (want - at[j - 1]) / span)) : 0;
    out.push([path[j - 1][0] + t * (path[j][0] - path[j - 1][0]), path[j - 1][1] + t * (path[j][1] - path[j - 1][1])]);
  }
  return out;
}

/** The number of poses (of every moving body). @type {(scene: Scene) => number} */
export const poseCount = (scene) => (scene.moving_bodies.length ? scene.moving_bodies[0].poses.length : 0);

/** True when nothing is drawn. @type {(scene: Scene) => boolean} */
export const isEmpty = (scene) =>
  scene.fixed_bodies.length === 0 && scene.moving_bodies.length === 0 && !scene.linkage_region;

/**
 * Every polygon of the scene in world coordinates, for fitting the view.
 * @param {Scene} scene
 * @returns {Point[]}
 */
export function allPoints(scene) {
  /** @type {Point[]} */
  const pts = [];
  for (const b of scene.fixed_bodies) pts.push(...b.polygon);
  for (const b of scene.moving_bodies) for (const p of b.poses) pts.push(...placed(b.polygon, p));
  if (scene.linkage_region) pts.push(...scene.linkage_region);
  for (const r of scene.avoid_regions || []) pts.push(...r);
  return pts;
}

/**
 * The shorter side of a body outline's box (the engine's body size d).
 * @param {Polygon} polygon
 */
export function bodySize(polygon) {
  const b = bounds(polygon);
  return Math.min(b.maxX - b.minX, b.maxY - b.minY);
}

/** @type {(poly: Polygon) => Polygon} */
const tidyPoly = (poly) => poly.map((p) => [tidy(p[0]), tidy(p[1])]);

/**
 * Adds a shape drawn in world coordinates as `kind`; returns the selection of the new thing.
 * @param {Scene} scene
 * @param {ShapeKind} kind
 * @param {Polygon} world
 * @returns {Selection}
 */
export function addShape(scene, kind, world) {
  const poly = tidyPoly(world);
  switch (kind) {
    case 'fixed': {
      scene.fixed_bodies.push({ name: `fixed ${scene.fixed_bodies.length + 1}`, polygon: poly });
      return { kind: 'fixed', index: scene.fixed_bodies.length - 1 };
    }
    case 'moving': {
      const [cx, cy] = centroid(poly);
      /** @type {Point} */
      const c = [tidy(cx), tidy(cy)];
      const local = tidyPoly(poly.map((p) => sub(p, c)));
      const n = Math.max(poseCount(scene), 2);
      const size = bodySize(local);
      // The first moving body gets a second pose beside the first, to be dragged where it should go.
      const poses = Array.from({ length: n }, (_, i) => /** @type {Pose} */ (
        scene.moving_bodies.length === 0 && i > 0 ? [tidy(c[0] + 1.5 * size * i), c[1], 0] : [c[0], c[1], 0]));
      if (scene.moving_bodies.length > 0 && poseCount(scene) < 2) {
        for (const b of scene.moving_bodies) {
          while (b.poses.length < 2) {
            const [x, y, a] = b.poses[b.poses.length - 1];
            b.poses.push([x, y, a]);
          }
        }
      }
      scene.moving_bodies.push({ name: `moving ${scene.moving_bodies.length + 1}`, polygon: local, poses });
      return { kind: 'moving', index: scene.moving_bodies.length - 1 };
    }
    case 'region':
      scene.linkage_region = poly;
      return { kind: 'region', index: 0 };
    case 'avoid':
      scene.avoid_regions = scene.avoid_regions || [];
      scene.avoid_regions.push(poly);
      return { kind: 'avoid', index: scene.avoid_regions.length - 1 };
    default:
      throw new Error(`unknown kind ${kind}`);
  }
}

/**
 * The polygon of a selection as stored (world for fixed bodies and regions, body frame for moving).
 * @param {Scene} scene
 * @param {Selection | null} sel
 * @returns {Polygon | null}
 */
export function storedPolygon(scene, sel) {
  if (!sel) return null;
  switch (sel.kind) {
    case 'fixed': return scene.fixed_bodies[sel.index]?.polygon ?? null;
    case 'moving': return scene.moving_bodies[sel.index]?.polygon ?? null;
    case 'region': return scene.linkage_region ?? null;
    case 'avoid': return scene.avoid_regions?.[sel.index] ?? null;
    default: return null;
  }
}

/**
 * The polygon of a selection in world coordinates (a moving body at pose `pose`).
 * @param {Scene} scene
 * @param {Selection | null} sel
 * @param {number} pose
 * @returns {Polygon | null}
 */
export function worldPolygon(scene, sel, pose) {
  const poly = storedPolygon(scene, sel);
  if (!poly || !sel) return null;
  if (sel.kind !== 'moving') return poly;
  const b = scene.moving_bodies[sel.index];
  return placed(poly, b.poses[Math.min(pose, b.poses.length - 1)] || [0, 0, 0]);
}

/**
 * Moves vertex `v` of a selection to world point `w` (through pose `pose` for a moving body).
 * @param {Scene} scene
 * @param {Selection} sel
 * @param {number} v
 * @param {Point} w
 * @param {number} pose
 */
export function moveVertex(scene, sel, v, w, pose) {
  const poly = storedPolygon(scene, sel);
  if (!poly || !poly[v]) return;
  const p = sel.kind === 'moving' ? toBody(scene.moving_bodies[sel.index].poses[pose], w) : w;
  poly[v] = [tidy(p[0]), tidy(p[1])];
}

/**
 * Inserts a vertex after `v` at world point `w` (through pose `pose` for a moving body).
 * @param {Scene} scene
 * @param {Selection} sel
 * @param {number} v
 * @param {Point} w
 * @param {number} pose
 */
export function insertVertex(scene, sel, v, w, pose) {
  const poly = storedPolygon(scene, sel);
  if (!poly) return;
  const p = sel.kind === 'moving' ? toBody(scene.moving_bodies[sel.index].poses[pose], w) : w;
  poly.splice(v + 1, 0, [tidy(p[0]), tidy(p[1])]);
}

/**
 * Deletes vertex `v`; false when the polygon would have fewer than three.
 * @param {Scene} scene
 * @param {Selection} sel
 * @param {number} v
 */
export function deleteVertex(scene, sel, v) {
  const poly = storedPolygon(scene, sel);
  if (!poly || poly.length <= 3 || !(v >= 0 && v < poly.length)) return false;
  poly.splice(v, 1);
  return true;
}

/**
 * Moves a whole shape by `delta` (a moving body: only its pose `pose`, and its path with it, so the
 * tracer stays on the path's start).
 * @param {Scene} scene
 * @param {Selection} sel
 * @param {Point} delta
 * @param {number} pose
 */
export function translate(scene, sel, delta, pose) {
  if (sel.kind === 'moving') {
    const b = scene.moving_bodies[sel.index];
    const p = b.poses[pose];
    if (b.path && pose > 0) {
      // A later pose of a body that follows a path slides along it: its tracer stays on the path.
      const tracer = toWorld(p, b.path.tracer);
      const shift = sub(onPath(b.path, add(tracer, delta)), tracer);
      p[0] = tidy(p[0] + shift[0], 3);
      p[1] = tidy(p[1] + shift[1], 3);
      return;
    }
    p[0] = tidy(p[0] + delta[0]);
    p[1] = tidy(p[1] + delta[1]);
    if (b.path) {
      // Where the body starts carries its path, and the later poses on it.
      b.path.points = b.path.points.map(([x, y]) => [tidy(x + delta[0], 3), tidy(y + delta[1], 3)]);
      for (const later of b.poses.slice(1)) {
        later[0] = tidy(later[0] + delta[0], 3);
        later[1] = tidy(later[1] + delta[1], 3);
      }
    }
    return;
  }
  const poly = storedPolygon(scene, sel);
  if (!poly) return;
  for (let i = 0; i < poly.length; i++) poly[i] = [tidy(poly[i][0] + delta[0]), tidy(poly[i][1] + delta[1])];
}

/**
 * Turns moving body `body` at pose `pose` to `deg` degrees.
 * @param {Scene} scene
 * @param {number} body
 * @param {number} pose
 * @param {number} deg
 */
export function setPoseAngle(scene, body, pose, deg) {
  const b = scene.moving_bodies[body];
  const p = b.poses[pose];
  if (!b.path) {
    p[2] = tidy(deg, 2);
    return;
  }
  // A body with a path turns about its tracer, which stays where it is on the path.
  const before = toWorld(p, b.path.tracer);
  p[2] = tidy(deg, 2);
  const shift = sub(before, toWorld(p, b.path.tracer));
  p[0] = tidy(p[0] + shift[0], 3);
  p[1] = tidy(p[1] + shift[1], 3);
}

/**
 * Deletes a shape.
 * @param {Scene} scene
 * @param {Selection} sel
 */
export function deleteShape(scene, sel) {
  switch (sel.kind) {
    case 'fixed': scene.fixed_bodies.splice(sel.index, 1); break;
    case 'moving': scene.moving_bodies.splice(sel.index, 1); break;
    case 'region': delete scene.linkage_region; break;
    case 'avoid': scene.avoid_regions?.splice(sel.index, 1); break;
    default: break;
  }
}

/**
 * A pose halfway between two (angles the short way round).
 * @param {Pose} a
 * @param {Pose} b
 * @returns {Pose}
 */
function between(a, b) {
  // lerp reads the positions only.
  const m = lerp([a[0], a[1]], [b[0], b[1]], 0.5);
  return [tidy(m[0]), tidy(m[1]), tidy(a[2] + wrapDeg(b[2] - a[2]) / 2, 2)];
}

/**
 * Whether pose `i` must be hit: the first and last always are, others when the scene marks them.
 * @param {Scene} scene
 * @param {number} i
 */
export function isMustHit(scene, i) {
  return i === 0 || i === poseCount(scene) - 1 || (scene.must_hit_poses || []).includes(i);
}

/**
 * Marks intermediate pose `i` as one the linkage must hit (or not).
 * @param {Scene} scene
 * @param {number} i
 * @param {boolean} on
 */
export function setMustHit(scene, i, on) {
  const marked = new Set(scene.must_hit_poses || []);
  if (on) marked.add(i);
  else marked.delete(i);
  scene.must_hit_poses = [...marked].sort((a, b) => a - b);
}

/**
 * The must-hit marks carried along when the poses are renumbered (`map`: old index → new, or null).
 * @param {Scene} scene
 * @param {(i: number) => number | null} map
 */
function renumberMustHit(scene, map) {
  if (!scene.must_hit_poses) return;
  scene.must_hit_poses = scene.must_hit_poses.map(map).filter((i) => i !== null).sort((a, b) => a - b);
}

/**
 * Adds a pose after pose `after` for every body: halfway to the next pose, or beyond the last.
 * @param {Scene} scene
 * @param {number} after
 */
export function insertPose(scene, after) {
  renumberMustHit(scene, (i) => (i > after ? i + 1 : i));
  for (const b of scene.moving_bodies) {
    const cur = b.poses[after];
    const next = b.poses[after + 1];
    /** @type {Pose} */
    let pose;
    if (b.path) pose = alongPath(b.path, cur, next);
    else if (next) pose = between(cur, next);
    else {
      const prev = b.poses[after - 1];
      /** @type {Point} */
      const at = [cur[0], cur[1]];
      /** @type {Point} */
      const across = [bodySize(b.polygon), 0];
      const step = prev ? sub(at, [prev[0], prev[1]]) : across;
      const shift = dist(step, [0, 0]) > 0 ? step : across;
      const p = add(at, [shift[0] * 0.5, shift[1] * 0.5]);
      pose = [tidy(p[0]), tidy(p[1]), cur[2]];
    }
    b.poses.splice(after + 1, 0, pose);
  }
}

/**
 * A pose of a body that follows `path`, after `cur` and before `next` (if any) along it: its tracer on
 * the path's point halfway between theirs (after the last: halfway to the path's end, or a quarter of
 * a loop on), turned as `cur` is.
 * @param {DrawnPath} path
 * @param {Pose} cur
 * @param {Pose | undefined} next
 * @returns {Pose}
 */
function alongPath(path, cur, next) {
  const n = path.points.length;
  const from = nearestIndex(path.points, toWorld(cur, path.tracer));
  let to = next ? nearestIndex(path.points, toWorld(next, path.tracer)) : path.closed ? from + n / 2 : n - 1;
  if (path.closed && to <= from) to += n;
  const at = path.points[Math.round((from + to) / 2) % n];
  const shift = sub(at, toWorld(cur, path.tracer));
  return [tidy(cur[0] + shift[0], 3), tidy(cur[1] + shift[1], 3), cur[2]];
}

/**
 * Deletes pose `i` of every body; false when that would leave fewer than two (one, for a body that
 * follows a path: where it starts).
 * @param {Scene} scene
 * @param {number} i
 */
export function deletePose(scene, i) {
  if (poseCount(scene) <= (scene.moving_bodies.some((b) => b.path) ? 1 : 2)) return false;
  renumberMustHit(scene, (k) => (k === i ? null : k > i ? k - 1 : k));
  for (const b of scene.moving_bodies) b.poses.splice(i, 1);
  return true;
}

/**
 * Swaps poses `i` and `j` of every body.
 * @param {Scene} scene
 * @param {number} i
 * @param {number} j
 */
export function swapPoses(scene, i, j) {
  renumberMustHit(scene, (k) => (k === i ? j : k === j ? i : k));
  for (const b of scene.moving_bodies) [b.poses[i], b.poses[j]] = [b.poses[j], b.poses[i]];
}
