// The scene/1 document the person edits, and the edits themselves. Every function here either reads
// a scene or changes the scene object it is given (the store snapshots it first, for undo).

import { add, bounds, centroid, dist, lerp, placed, sub, tidy, toBody, wrapDeg } from './geom.js';

/** Defaults the app writes into a new scene (the engine's own defaults, with fewer samples so a
 * first design takes seconds). */
export const DEFAULT_SETTINGS = {
  seed: 0, samples: 20000, particles: 100, iterations: 20,
  pose_tolerance: 0.5, angle_tolerance_deg: 3, min_transmission_deg: 10, comfortable_transmission_deg: 30,
};
export const DEFAULT_WEIGHTS = { accuracy: 1000, smoothness: 1, location: 10, size: 1, transmission: 1 };
/** The engine's defaults for fields a file leaves out. */
export const ENGINE_SETTINGS = { ...DEFAULT_SETTINGS, samples: 100000 };

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

/** Reads a scene file's JSON, filling the defaults the editor needs. Throws with a message. */
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

/** The scene as the file is written: empty optional parts left out. */
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

export const poseCount = (scene) => (scene.moving_bodies.length ? scene.moving_bodies[0].poses.length : 0);

export const isEmpty = (scene) =>
  scene.fixed_bodies.length === 0 && scene.moving_bodies.length === 0 && !scene.linkage_region;

/** Every polygon of the scene in world coordinates, for fitting the view. */
export function allPoints(scene) {
  const pts = [];
  for (const b of scene.fixed_bodies) pts.push(...b.polygon);
  for (const b of scene.moving_bodies) for (const p of b.poses) pts.push(...placed(b.polygon, p));
  if (scene.linkage_region) pts.push(...scene.linkage_region);
  for (const r of scene.avoid_regions || []) pts.push(...r);
  return pts;
}

/** The shorter side of a body outline's box (the engine's body size d). */
export function bodySize(polygon) {
  const b = bounds(polygon);
  return Math.min(b.maxX - b.minX, b.maxY - b.minY);
}

const tidyPoly = (poly) => poly.map((p) => [tidy(p[0]), tidy(p[1])]);

/** Adds a shape drawn in world coordinates as `kind`; returns the selection of the new thing. */
export function addShape(scene, kind, world) {
  const poly = tidyPoly(world);
  switch (kind) {
    case 'fixed': {
      scene.fixed_bodies.push({ name: `fixed ${scene.fixed_bodies.length + 1}`, polygon: poly });
      return { kind: 'fixed', index: scene.fixed_bodies.length - 1 };
    }
    case 'moving': {
      const c = centroid(poly).map((v) => tidy(v));
      const local = tidyPoly(poly.map((p) => sub(p, c)));
      const n = Math.max(poseCount(scene), 2);
      const size = bodySize(local);
      // The first moving body gets a second pose beside the first, to be dragged where it should go.
      const poses = Array.from({ length: n }, (_, i) =>
        scene.moving_bodies.length === 0 && i > 0 ? [tidy(c[0] + 1.5 * size * i), c[1], 0] : [c[0], c[1], 0]);
      if (scene.moving_bodies.length > 0 && poseCount(scene) < 2) {
        for (const b of scene.moving_bodies) while (b.poses.length < 2) b.poses.push([...b.poses[b.poses.length - 1]]);
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

/** The polygon of a selection as stored (world for fixed bodies and regions, body frame for moving). */
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

/** The polygon of a selection in world coordinates (a moving body at pose `pose`). */
export function worldPolygon(scene, sel, pose) {
  const poly = storedPolygon(scene, sel);
  if (!poly) return null;
  if (sel.kind !== 'moving') return poly;
  const b = scene.moving_bodies[sel.index];
  return placed(poly, b.poses[Math.min(pose, b.poses.length - 1)] || [0, 0, 0]);
}

/** Moves vertex `v` of a selection to world point `w` (through pose `pose` for a moving body). */
export function moveVertex(scene, sel, v, w, pose) {
  const poly = storedPolygon(scene, sel);
  if (!poly || !poly[v]) return;
  const p = sel.kind === 'moving' ? toBody(scene.moving_bodies[sel.index].poses[pose], w) : w;
  poly[v] = [tidy(p[0]), tidy(p[1])];
}

/** Inserts a vertex after `v` at world point `w`. */
export function insertVertex(scene, sel, v, w, pose) {
  const poly = storedPolygon(scene, sel);
  if (!poly) return;
  const p = sel.kind === 'moving' ? toBody(scene.moving_bodies[sel.index].poses[pose], w) : w;
  poly.splice(v + 1, 0, [tidy(p[0]), tidy(p[1])]);
}

/** Deletes vertex `v`; false when the polygon would have fewer than three. */
export function deleteVertex(scene, sel, v) {
  const poly = storedPolygon(scene, sel);
  if (!poly || poly.length <= 3 || !(v >= 0 && v < poly.length)) return false;
  poly.splice(v, 1);
  return true;
}

/** Moves a whole shape by `delta` (a moving body: only its pose `pose`). */
export function translate(scene, sel, delta, pose) {
  if (sel.kind === 'moving') {
    const p = scene.moving_bodies[sel.index].poses[pose];
    p[0] = tidy(p[0] + delta[0]);
    p[1] = tidy(p[1] + delta[1]);
    return;
  }
  const poly = storedPolygon(scene, sel);
  if (!poly) return;
  for (let i = 0; i < poly.length; i++) poly[i] = [tidy(poly[i][0] + delta[0]), tidy(poly[i][1] + delta[1])];
}

export function setPoseAngle(scene, body, pose, deg) {
  scene.moving_bodies[body].poses[pose][2] = tidy(deg, 2);
}

export function deleteShape(scene, sel) {
  switch (sel.kind) {
    case 'fixed': scene.fixed_bodies.splice(sel.index, 1); break;
    case 'moving': scene.moving_bodies.splice(sel.index, 1); break;
    case 'region': delete scene.linkage_region; break;
    case 'avoid': scene.avoid_regions.splice(sel.index, 1); break;
    default: break;
  }
}

/** A pose halfway between two (angles the short way round). */
function between(a, b) {
  const m = lerp(a, b, 0.5);
  return [tidy(m[0]), tidy(m[1]), tidy(a[2] + wrapDeg(b[2] - a[2]) / 2, 2)];
}

/** Whether pose `i` must be hit: the first and last always are, others when the scene marks them. */
export function isMustHit(scene, i) {
  return i === 0 || i === poseCount(scene) - 1 || (scene.must_hit_poses || []).includes(i);
}

/** Marks intermediate pose `i` as one the linkage must hit (or not). */
export function setMustHit(scene, i, on) {
  const marked = new Set(scene.must_hit_poses || []);
  if (on) marked.add(i);
  else marked.delete(i);
  scene.must_hit_poses = [...marked].sort((a, b) => a - b);
}

/** The must-hit marks carried along when the poses are renumbered (`map`: old index → new, or null). */
function renumberMustHit(scene, map) {
  if (!scene.must_hit_poses) return;
  scene.must_hit_poses = scene.must_hit_poses.map(map).filter((i) => i !== null).sort((a, b) => a - b);
}

/** Adds a pose after pose `after` for every body: halfway to the next pose, or beyond the last. */
export function insertPose(scene, after) {
  renumberMustHit(scene, (i) => (i > after ? i + 1 : i));
  for (const b of scene.moving_bodies) {
    const cur = b.poses[after];
    const next = b.poses[after + 1];
    let pose;
    if (next) pose = between(cur, next);
    else {
      const prev = b.poses[after - 1];
      const step = prev ? sub(cur, prev) : [bodySize(b.polygon), 0];
      const shift = dist(step, [0, 0]) > 0 ? step : [bodySize(b.polygon), 0];
      const p = add(cur, shift.map((v) => v * 0.5));
      pose = [tidy(p[0]), tidy(p[1]), cur[2]];
    }
    b.poses.splice(after + 1, 0, pose);
  }
}

/** Deletes pose `i` of every body; false when that would leave fewer than two. */
export function deletePose(scene, i) {
  if (poseCount(scene) <= 2) return false;
  renumberMustHit(scene, (k) => (k === i ? null : k > i ? k - 1 : k));
  for (const b of scene.moving_bodies) b.poses.splice(i, 1);
  return true;
}

/** Swaps poses `i` and `j` of every body. */
export function swapPoses(scene, i, j) {
  renumberMustHit(scene, (k) => (k === i ? j : k === j ? i : k));
  for (const b of scene.moving_bodies) [b.poses[i], b.poses[j]] = [b.poses[j], b.poses[i]];
}
