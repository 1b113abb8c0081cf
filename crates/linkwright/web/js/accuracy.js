// @ts-check
// How closely a design reaches the drawn poses: per pose and body, the largest corner distance (in the
// scene's units and as a share of the body's size d) and the angle still missing. A design/1 file may
// carry these in `metrics.pose_errors`; older files do not, and then they come from the analysis the app
// fetches anyway (the same numbers: its `max_vertex` and `angle_deg` at each pose).

import { bounds } from './geom.js';
import { html } from './svg.js';

/**
 * @typedef {import('./scene.js').Scene} Scene
 * @typedef {import('./geom.js').Polygon} Polygon
 * @typedef {import('./api.js').Metrics} Metrics
 * @typedef {import('./api.js').Analysis} Analysis
 */

/**
 * @typedef {{position: number, rel: number, angle: number}} Miss  How far a body is from a pose: the
 *   largest corner distance (scene units), it over the body's size d, the angle still missing (°).
 * @typedef {Miss & {pose: number, body: number}} MissRow  A body's miss at a pose (both from 0).
 * @typedef {object} PoseErrors  The pose errors of the mechanism shown.
 * @property {MissRow[]} rows  every pose and body
 * @property {MissRow} worst  the row missed most
 * @property {Miss} max  each field the largest over all rows
 * @property {boolean} reached  every pose is reached (see REACHED)
 * @property {import('./api.js').Metrics['far_from_pose'] | null} far  the engine's mark of a design far from a pose
 */

/**
 * Within these a pose counts as reached. The synthesis perturbs the intermediate poses on purpose
 * (`pose_tolerance`, paper §4.1) and refines the joints afterwards, so a design rarely hits a pose
 * exactly; a miss under 1% of the body's size and under 1° is too small to see at the scale of the
 * object, while anything larger is a miss a person should be told about rather than a success.
 */
export const REACHED = { positionRelD: 0.01, angleDeg: 1 };

/**
 * A path design traces the drawn curve when no point of either is farther from the other than this
 * share of the curve's size (a hand's drawing is rarely truer), and passes an exact point within the
 * engine's `EXACT_POINT_TOLERANCE`, 0.2% of it.
 */
export const TRACED = { maxRel: 0.02, exactRel: 0.002 };

/**
 * The verification badge of a path design, from its `metrics.path_error`.
 * @param {import('./api.js').PathError} e
 * @param {Scene} scene
 */
export function pathBadge(e, scene) {
  const units = scene.units || 'mm';
  const exact = e.exact;
  const missed = exact && exact.distance_rel > TRACED.exactRel ? exact : null;
  const close = e.max_rel <= TRACED.maxRel;
  const traces = `traces the drawn path within ${fmtUp(e.max)} ${units} (${pct(e.max_rel)} of its size; ${fmt(e.mean)} ${units} on average)`;
  const text = missed
    ? `It misses exact point ${missed.point + 1} of the path by ${fmt(missed.distance)} ${units} (${pct(missed.distance_rel)} of the path's size), and no linkage closer was found; it ${traces}`
    : `${close ? '✓ ' : ''}Re-simulated independently: ${traces}${exact ? `, passing its exact points within ${fmtUp(exact.distance)} ${units}` : ''}`;
  return html('p', {
    class: missed ? 'badge far verified' : close ? 'badge ok verified' : 'badge warn verified',
    text,
    title: missed
      ? 'Every hard constraint holds, but the tracer does not pass a point marked exact. Mark fewer points exact (a four-bar passes at most nine), move it nearer the curve, or pick another type of linkage in Settings.'
      : `Every hard constraint holds. The distance is measured both ways: from every point of the drawn path to the traced curve, and from every point of the traced curve to the drawn path; a path counts as traced within ${TRACED.maxRel * 100}% of its size.`,
  });
}

/**
 * The body size d: the shorter side of the outline's bounding box in its own frame, as the engine has it.
 * @param {Polygon} polygon
 */
export function bodySize(polygon) {
  const bb = bounds(polygon);
  return Math.min(bb.maxX - bb.minX, bb.maxY - bb.minY);
}

/**
 * True when `x` is a finite number.
 * @param {unknown} x
 * @returns {x is number}
 */
function finite(x) {
  return typeof x === 'number' && Number.isFinite(x);
}

/**
 * The file's `pose_errors` when it has the scene's shape (N poses × K bodies of numbers), else null.
 * @param {Metrics | null | undefined} metrics
 * @param {number} n
 * @param {number} k
 * @returns {Miss[][] | null}
 */
function fromMetrics(metrics, n, k) {
  const pe = metrics?.pose_errors;
  if (!Array.isArray(pe) || pe.length !== n) return null;
  const ok = pe.every((row) => Array.isArray(row) && row.length === k
    && row.every((e) => e && finite(e.position) && finite(e.position_rel_d) && finite(e.angle_deg)));
  if (!ok) return null;
  return pe.map((row) => row.map((e) => ({ position: e.position, rel: e.position_rel_d, angle: Math.abs(e.angle_deg) })));
}

/**
 * The same numbers from the analysis of `/api/simulate` (null when it does not fit the scene).
 * @param {Analysis | null | undefined} analysis
 * @param {Scene} scene
 * @param {number} n
 * @param {number} k
 * @returns {Miss[][] | null}
 */
function fromAnalysis(analysis, scene, n, k) {
  const poses = analysis?.poses;
  if (!Array.isArray(poses) || poses.length !== n) return null;
  const sizes = scene.moving_bodies.map((b) => bodySize(b.polygon));
  if (!poses.every((p) => Array.isArray(p.bodies) && p.bodies.length === k)) return null;
  return poses.map((p) => p.bodies.map((b, j) => ({
    position: b.max_vertex,
    rel: sizes[j] > 0 ? b.max_vertex / sizes[j] : Infinity,
    angle: Math.abs(b.angle_deg),
  })));
}

/** How far a miss is past the line of "reached" (1 at the line): ranks the rows to find the worst. */
/** @type {(e: Miss) => number} */
const severity = (e) => Math.max(e.rel / REACHED.positionRelD, e.angle / REACHED.angleDeg);

/**
 * The pose errors of the mechanism shown: `{rows: [{pose, body, position, rel, angle}], worst (the
 * row missed most), max: {position, rel, angle} (each the largest over all rows), reached}`, or null
 * while neither the file nor the analysis has them.
 * @param {Metrics | null | undefined} metrics
 * @param {Analysis | null | undefined} analysis
 * @param {Scene} scene
 * @returns {PoseErrors | null}
 */
export function poseErrors(metrics, analysis, scene) {
  const n = scene.moving_bodies[0]?.poses.length || 0;
  const k = scene.moving_bodies.length;
  if (!n || !k) return null;
  const fileTable = fromMetrics(metrics, n, k);
  const table = fileTable || fromAnalysis(analysis, scene, n, k);
  if (!table) return null;
  const rows = table.flatMap((row, pose) => row.map((e, body) => ({ pose, body, ...e })));
  const worst = rows.reduce((a, b) => (severity(b) > severity(a) ? b : a));
  /** @type {Miss} */
  const max = { position: 0, rel: 0, angle: 0 };
  for (const r of rows) {
    for (const f of /** @type {(keyof Miss)[]} */ (['position', 'rel', 'angle'])) max[f] = Math.max(max[f], r[f]);
  }
  const file = metrics?.worst_pose_error;
  if (fileTable && file && finite(file.position) && finite(file.position_rel_d) && finite(file.angle_deg)) {
    Object.assign(max, { position: file.position, rel: file.position_rel_d, angle: Math.abs(file.angle_deg) });
  }
  // The engine marks a design far from a pose (a quarter of the body's size, or 5°) when its search
  // found none closer.
  const far = fileTable && metrics?.far_from_pose ? metrics.far_from_pose : null;
  return { rows, worst, max, reached: max.rel <= REACHED.positionRelD && max.angle <= REACHED.angleDeg, far };
}

/** Decimals that show a length or an angle legibly: two below 1, one above. */
/** @type {(x: number) => number} */
const decimals = (x) => (x < 1 ? 2 : 1);

/**
 * `x` rounded for reading (a dash when it is not a number).
 * @param {number | null | undefined} x
 */
export function fmt(x) {
  return finite(x) ? x.toFixed(decimals(x)) : '—';
}

/**
 * `x` rounded up, for a bound that must stay true once rounded ("within 0.43" shows as 0.43, 0.431 as 0.44).
 * @param {number} x
 */
function fmtUp(x) {
  if (!finite(x)) return '—';
  const f = 10 ** decimals(x);
  return (Math.ceil(x * f - 1e-9) / f).toFixed(decimals(x));
}

/**
 * A share of d as a percentage.
 * @param {number} rel
 */
export function pct(rel) {
  if (!finite(rel)) return '—';
  const p = rel * 100;
  return `${p.toFixed(p < 10 ? 1 : 0)}%`;
}

/** @type {(scene: Scene, k: number) => string} */
const bodyName = (scene, k) => scene.moving_bodies[k]?.name || `body ${k + 1}`;

/**
 * The verification badge's words for errors `e`: a bound when every pose is reached, else the worst miss.
 * @param {PoseErrors} e
 * @param {Scene} scene
 */
export function reachText(e, scene) {
  const units = scene.units || 'mm';
  if (e.reached) {
    return `✓ Re-simulated independently: reaches every pose within ${fmtUp(e.max.position)} ${units} and ${fmtUp(e.max.angle)}°`;
  }
  const w = e.worst;
  const missed = `Pose ${w.pose + 1} (${bodyName(scene, w.body)}) is missed by ${fmt(w.position)} ${units} (${pct(w.rel)} of its width) and ${fmt(w.angle)}°`;
  return e.far ? `Far from the drawing: ${missed}, and no linkage closer was found` : missed;
}

/**
 * The badge for errors `e` once the design has passed the independent check.
 * @param {PoseErrors} e
 * @param {Scene} scene
 */
export function reachBadge(e, scene) {
  return html('p', {
    class: e.reached ? 'badge ok verified' : e.far ? 'badge far verified' : 'badge warn verified',
    text: reachText(e, scene),
    title: e.far
      ? 'Every hard constraint holds, but the body ends up far from where it was drawn at this pose. Draw a pose between it and its neighbours, move it toward the way the others go, or pick another type of linkage in Settings.'
      : e.reached
      ? `Every hard constraint holds, and every pose is reached within ${REACHED.positionRelD * 100}% of the body's width (the shorter side of its outline's box) and ${REACHED.angleDeg}°.`
      : `Every hard constraint holds, but the design only approximates the poses: a pose counts as reached within ${REACHED.positionRelD * 100}% of the body's width (the shorter side of its outline's box) and ${REACHED.angleDeg}°.`,
  });
}

/**
 * The compact table: one row per pose (and body when there are several), the worst row marked.
 * @param {PoseErrors} e
 * @param {Scene} scene
 */
export function poseTable(e, scene) {
  const several = scene.moving_bodies.length > 1;
  const units = scene.units || 'mm';
  return html('table', { class: 'pose-errors' }, [
    html('thead', {}, [html('tr', {}, [
      html('th', { text: 'Pose' }),
      several ? html('th', { class: 'name', text: 'Body' }) : null,
      html('th', { text: `Off by (${units})`, title: "the largest distance of an outline corner from where it was drawn" }),
      html('th', { text: 'of width', title: "that distance as a share of the body's width (the shorter side of its outline's box: a lid 200 mm long and 15 mm thick is 15 mm wide)" }),
      html('th', { text: 'Angle', title: 'the rotation still missing' }),
    ])]),
    html('tbody', {}, e.rows.map((r) => {
      const missed = severity(r) > 1;
      const cls = [r === e.worst ? 'worst' : '', missed ? 'missed' : ''].filter(Boolean).join(' ');
      return html('tr', { class: cls || null, 'data-pose': String(r.pose), 'data-body': String(r.body) }, [
        html('td', { text: String(r.pose + 1) }),
        several ? html('td', { class: 'name', text: bodyName(scene, r.body) }) : null,
        html('td', { text: fmt(r.position) }),
        html('td', { text: pct(r.rel) }),
        html('td', { text: `${fmt(r.angle)}°` }),
      ]);
    })),
  ]);
}
