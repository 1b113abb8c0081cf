// @ts-check
// Counterbalance springs in words a person can buy and fit them from: what each is, where its ends
// hook on, named as the person named the parts (the engine names a moving body `body1` and a ground
// point `ground`), and on which part each printed bracket for a hook is mounted.

import { bounds, distanceTo } from './geom.js';
import { html } from './svg.js';

/**
 * @typedef {import('./geom.js').Point} Point
 * @typedef {import('./scene.js').Scene} Scene
 * @typedef {import('./api.js').Balance} Balance
 * @typedef {import('./api.js').Fabrication} Fabrication
 * @typedef {{hooks?: {on: string, part: string, point: Point}[]}} SpringHooks  a fabrication report's
 *   spring: where its ends hook on the printed parts
 */

/** What the app says when no spring helps: the search hooks springs on the fixed bodies, in the
 * linkage region and on the moving parts. */
export const NO_SPRING = 'No spring hooked on the fixed bodies, in the linkage region or on the moving parts lowers the peak torque of this design.';

/** How much lower the springs of `balance` make the peak torque, in whole percent. @type {(balance: Balance) => number} */
export const springCut = (balance) =>
  Math.round(100 * (1 - balance.peak_with_springs_nm / Math.max(balance.peak_nm, 1e-300)));

/**
 * @typedef {{scene: Scene, mechanism: import('./api.js').Mechanism | null}} Naming  The scene whose
 *   names the person gave (its moving and fixed bodies), and the mechanism shown, whose parts the
 *   engine's names are of.
 */

/**
 * The part the engine calls `part`, holding the point `point` (first pose), as the person knows it:
 * a moving body by its name, the ground by the fixed body the point is on (or the one beside it), a
 * link by what it is (the crank, the rocker). With `mount`, what a bracket reaching the point is
 * mounted on: off every fixed body, the one nearest it.
 * @param {string} part
 * @param {Point} point
 * @param {Naming} naming
 * @param {{mount?: boolean}} [options]
 */
export function partWords(part, point, { scene, mechanism }, { mount = false } = {}) {
  const found = mechanism?.parts?.find((p) => p.name === part);
  const body = found?.kind === 'body' ? found.body : /^body(\d+)$/.test(part) && !found ? Number(part.slice(4)) - 1 : null;
  if (body !== null && body !== undefined && scene.moving_bodies[body]) {
    const name = scene.moving_bodies[body].name;
    return name ? `the moving body “${name}”` : `moving body ${body + 1}`;
  }
  if (part === 'ground' || found?.kind === 'fixed') return groundWords(point, scene, mount);
  return `the ${part}`;
}

/**
 * A ground point in words: the fixed body it is on; off them all (the engine hooks a spring in the
 * linkage region too), the ground beside the nearest, or with `mount` that nearest body itself.
 * @param {Point | undefined} point
 * @param {Scene} scene
 * @param {boolean} mount
 */
function groundWords(point, scene, mount) {
  const bodies = scene.fixed_bodies;
  if (!point || !bodies.length) return 'the ground';
  /** @type {(b: import('./scene.js').FixedBody) => string} */
  const named = (b) => (b.name ? `the fixed body “${b.name}”` : `fixed body ${bodies.indexOf(b) + 1}`);
  const away = bodies.map((b) => {
    const box = bounds(b.polygon);
    return { b, d: distanceTo(b.polygon, point), tol: 1e-4 * Math.hypot(box.maxX - box.minX, box.maxY - box.minY) };
  });
  const on = away.find((a) => a.d <= a.tol);
  if (on) return named(on.b);
  const nearest = away.reduce((a, b) => (b.d < a.d ? b : a)).b;
  return mount ? named(nearest) : `the ground beside ${named(nearest)}`;
}

/**
 * The printed part each spring bracket of a fabrication `answer` is mounted on, in words: bracket name
 * to words (“the moving body “bed””), from the hooks the report lists for each spring.
 * @param {Fabrication} answer  the fabricate answer (its report's parts and springs)
 * @param {Naming} naming
 * @returns {Map<string, string>}
 */
export function bracketMounts(answer, naming) {
  const report = answer.report?.linkwright === 'fabrication/1' ? answer.report : null;
  const brackets = new Set((report?.parts || []).filter((p) => p.role === 'spring_bracket').map((p) => p.name));
  const out = new Map();
  for (const spring of report?.springs || []) {
    for (const hook of spring.hooks || []) {
      if (brackets.has(hook.on)) out.set(hook.on, partWords(hook.part, hook.point, naming, { mount: true }));
    }
  }
  return out;
}

/**
 * Each counterbalance spring of `balance` in words a person can buy and fit it from, its ends named
 * as `naming` names the parts. With `hooks` (a fabrication report's springs, in the same order), also
 * the printed part each end hooks on, and for a bracket (`brackets`, from `bracketMounts`) the part
 * it is mounted on.
 * @param {Balance} balance
 * @param {string} units
 * @param {Naming} naming
 * @param {SpringHooks[] | null} [hooks]
 * @param {Map<string, string>} [brackets]
 * @returns {HTMLElement}
 */
export function springList(balance, units, naming, hooks = null, brackets = new Map()) {
  if (!balance.springs.length) return html('p', { class: 'note', text: NO_SPRING });
  /** @type {(p: Point) => string} */
  const at = (p) => `(${p[0].toFixed(1)}, ${p[1].toFixed(1)})`;
  /** @type {(k: number) => HTMLElement | null} */
  const printed = (k) => {
    const ends = hooks?.[k]?.hooks;
    if (!ends?.length) return null;
    const where = ends.map((h) => (brackets.has(h.on) ? `${h.on} (a bracket mounted on ${brackets.get(h.on)})` : h.on));
    return html('div', { 'data-hooks': k, text: `Printed hooks: ${where.join(' and ')}.` });
  };
  return html('ul', { class: 'springs' }, balance.springs.map((s, k) => html('li', {}, s.kind === 'extension'
    ? [html('b', { text: 'Extension spring' }),
      html('div', { text: `Rate ${(s.stiffness_n_per_m / 1000).toPrecision(3)} N/mm, free length ${s.free_length.toFixed(1)} ${units} hook to hook.` }),
      html('div', { text: `Hook one end on ${partWords(s.anchors[0].part, s.anchors[0].point, naming)} at ${at(s.anchors[0].point)} and the other on ${partWords(s.anchors[1].part, s.anchors[1].point, naming)} at ${at(s.anchors[1].point)}, at the first pose.` }),
      printed(k),
      html('small', { text: `It stretches to ${s.length_range[0].toFixed(1)}–${s.length_range[1].toFixed(1)} ${units}, pulling ${s.force_range_n[0].toPrecision(3)}–${s.force_range_n[1].toPrecision(3)} N.` })]
    : [html('b', { text: 'Torsion spring' }),
      html('div', { text: `Rate ${(s.stiffness_nm_per_rad * 1000 * Math.PI / 180).toPrecision(3)} N·mm per degree, on the ground pivot of ${partWords(s.part, s.pivot, naming)} at ${at(s.pivot)}.` }),
      html('div', { text: `Unwound when ${partWords(s.part, s.pivot, naming)} is turned ${s.free_angle_deg.toFixed(0)}° from the first pose.` }),
      html('small', { text: `Wound ${s.twist_range_deg[0].toFixed(0)}–${s.twist_range_deg[1].toFixed(0)}° along the motion, ${(s.torque_range_nm[0] * 1000).toPrecision(3)}–${(s.torque_range_nm[1] * 1000).toPrecision(3)} N·mm.` })])));
}

/**
 * `step` (an assembly step of the engine's) with each spring bracket it puts in place followed by the
 * part the bracket is mounted on.
 * @param {string} step
 * @param {Map<string, string>} brackets
 */
export function withMounts(step, brackets) {
  let out = step;
  for (const [name, words] of brackets) {
    out = out.replace(new RegExp(`: ${name}\\b(?!,)`), `: ${name}, mounted on ${words}`);
  }
  return out;
}
