// @ts-check
// How the drawn object is built, the scene's `build`: a 3D-printed model at a scale, or the object at
// full size in a workshop material. The words are the engine's (`model:auto`, `model:1:10`,
// `full:plywood`); this module reads them once and says them in the screen's words.

import { placed } from './geom.js';

/** @typedef {import('./api.js').LengthUnit} LengthUnit */

/**
 * A build's word read: a printed model at a scale (`auto`, or `A:B`), or the object at full size in
 * a workshop material.
 * @typedef {{kind: 'model', scale: string} | {kind: 'full', material: string}} Build
 */

/** What a scene without `build` is built as. */
export const DEFAULT_BUILD = 'model:auto';

/** The workshop materials, as [word, label], in the engine's order. @type {[string, string][]} */
export const MATERIALS = [['plywood', 'Plywood'], ['aluminium', 'Aluminium'], ['steel', 'Steel']];

/** The terms of the engine's 1-2-5 series: 1, 2, 5, 10, … 10000. */
const TERMS = [1, 10, 100, 1000].flatMap((d) => [1, 2, 5].map((s) => s * d)).concat(10000);

/** The engine's 1-2-5 series of model scales, 10000:1 down to 1:10000, largest first: what an `auto`
 * scale is chosen from, and what the Settings tab offers. */
export const SCALES = [
  ...TERMS.filter((t) => t > 1).reverse().map((t) => `${t}:1`),
  ...TERMS.map((t) => `1:${t}`),
];

/**
 * A build's word read: `{kind: 'model', scale: 'auto' | 'A:B'}` or `{kind: 'full', material}`; null
 * for a word this app does not know (the engine says what is wrong with it).
 * @param {string | null | undefined} text
 * @returns {Build | null}
 */
export function parseBuild(text) {
  const word = String(text ?? DEFAULT_BUILD).trim().toLowerCase();
  let m = /^model(?::(auto)?)?$/.exec(word);
  if (m) return { kind: 'model', scale: 'auto' };
  if ((m = /^model:(\d+):(\d+)$/.exec(word)) && Number(m[1]) >= 1 && Number(m[2]) >= 1) {
    return { kind: 'model', scale: `${Number(m[1])}:${Number(m[2])}` };
  }
  if ((m = /^full(?::(\w+))?$/.exec(word))) {
    const material = m[1] === 'aluminum' ? 'aluminium' : m[1] || 'plywood';
    if (MATERIALS.some(([w]) => w === material)) return { kind: 'full', material };
  }
  return null;
}

/**
 * The word of a build read by `parseBuild`.
 * @param {Build} b
 */
export function buildWord(b) {
  return b.kind === 'full' ? `full:${b.material}` : `model:${b.scale}`;
}

/** The scene's build, read (a word the app does not know reads as null). @type {(scene: import('./scene.js').Scene) => Build | null} */
export const sceneBuild = (scene) => parseBuild(scene.build ?? DEFAULT_BUILD);

/** The material's label. @type {(word: string) => string} */
const materialLabel = (word) => MATERIALS.find(([w]) => w === word)?.[1] ?? word;

/** A length in millimetres as the app shows a size: whole millimetres from 100 mm up, three figures
 * below. @type {(v: number) => string} */
export const mm = (v) => String(v >= 100 ? Math.round(v) : Number(v.toPrecision(3)));

/** A model's extent `[w, h]` in millimetres: “214 × 180 mm”. @type {(size: number[]) => string} */
export const extent = ([w, h]) => `${mm(w)} × ${mm(h)} mm`;

/**
 * A build in words: “Printed model at 1:10”, with “(auto)” when `auto` (the scale was chosen by the
 * engine) and its extent when known; “Full size, plywood”. `word` is a build's word.
 * @param {string} word
 * @param {{auto?: boolean, modelMm?: number[] | null}} [options]
 */
export function describe(word, { auto = false, modelMm = null } = {}) {
  const b = parseBuild(word);
  if (!b) return `Build ${word}`;
  if (b.kind === 'full') return `Full size, ${materialLabel(b.material).toLowerCase()}`;
  const scale = b.scale === 'auto' ? 'a scale chosen when designed' : b.scale;
  const size = Array.isArray(modelMm) && modelMm.length === 2 ? `, ${extent(modelMm)}` : '';
  return `Printed model at ${scale}${auto && b.scale !== 'auto' ? ' (auto)' : ''}${size}`;
}

/**
 * What a design file's `build` record says, in words (see `describe`); null for files without one.
 * @param {import('./api.js').BuildRecord | undefined} record
 */
export function describeRecord(record) {
  if (!record?.checked) return null;
  const asked = parseBuild(record.asked);
  return describe(record.checked, { auto: asked?.kind === 'model' && asked.scale === 'auto', modelMm: record.model_mm });
}

/**
 * The scale an unbuildable design's reason suggests (“print at 1:5 or smaller”), as `A:B`, or null
 * when it suggests none. The engine writes the suggestion in exactly these words.
 * @param {string | null | undefined} reason
 */
export function suggestedScale(reason) {
  const m = /\bprint at (\d+):(\d+) or (?:smaller|larger)\b/.exec(reason || '');
  return m ? `${Number(m[1])}:${Number(m[2])}` : null;
}

/**
 * Millimetres in one unit of a scene's `units` word, read as the engine reads it with its table
 * `units` (GET /api/units): the unit one of whose words it is, trimmed and with its ASCII letters
 * lowered (a scene without the word is in millimetres); null for a word of no unit.
 * @param {string | undefined} word
 * @param {LengthUnit[]} units
 * @returns {number | null}
 */
function millimetresPerUnit(word, units) {
  // The engine lowers ASCII letters only; a letter that lowers to one elsewhere (the Kelvin sign's k)
  // must not make a word it refuses.
  const read = String(word ?? 'mm').trim().replace(/[A-Z]+/g, (letters) => letters.toLowerCase());
  return units.find((u) => u.words.includes(read))?.millimetres ?? null;
}

/**
 * The printed model's extent `[w, h]` in millimetres at a fixed `scale` (`A:B`): everything drawn (the
 * fixed bodies, the moving bodies at every pose, the linkage region), as the engine measures it, its
 * units read with the engine's table `units`; null when the units are none of the table's (or the
 * table is not loaded: empty) or nothing is drawn.
 * @param {import('./scene.js').Scene} scene
 * @param {string} scale
 * @param {LengthUnit[]} units
 * @returns {[number, number] | null}
 */
export function modelExtent(scene, scale, units) {
  const perUnit = millimetresPerUnit(scene.units, units);
  const [a, b] = scale.split(':').map(Number);
  const drawn = [
    ...scene.fixed_bodies.flatMap((f) => f.polygon),
    ...scene.moving_bodies.flatMap((m) => m.poses.flatMap((pose) => placed(m.polygon, pose))),
    ...(scene.linkage_region || []),
  ];
  if (!perUnit || !(a > 0 && b > 0) || drawn.length === 0) return null;
  const xs = drawn.map((p) => p[0]), ys = drawn.map((p) => p[1]);
  const k = (perUnit * a) / b;
  return [(Math.max(...xs) - Math.min(...xs)) * k, (Math.max(...ys) - Math.min(...ys)) * k];
}
