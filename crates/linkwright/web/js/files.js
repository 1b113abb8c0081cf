// @ts-check
// Files in and out: open a scene (button or drag-and-drop), save it, download blobs, the example
// gallery, and the autosave that brings the last scene back on reload.

import * as api from './api.js';
import { bodyColour } from './canvas.js';
import { bounds, placed } from './geom.js';
import { normalize, toFile } from './scene.js';
import { clear, html, points, svg } from './svg.js';

/**
 * @typedef {import('./scene.js').Scene} Scene
 * @typedef {import('./api.js').Design} Design
 * @typedef {import('./api.js').Balance} Balance
 * @typedef {import('./api.js').ExampleSummary} ExampleSummary
 * @typedef {import('./fabricate.js').PrintForm} PrintForm
 * @typedef {import('./geom.js').Point} Point
 */

/**
 * What a project/1 keeps besides its scene: the design shown for it, which of its mechanisms
 * (null: the design itself, i: its alternative i), the counterbalance springs suggested (or null) and
 * the print settings (or null).
 * @typedef {{design: Design, which: number | null, balance: Balance | null, print: PrintForm | null}} Project
 * @typedef {{scene: Scene, project?: Project} | {design: Design, scene?: undefined}} OpenedFile
 *   A file read: a scene (with its project's design), or a design for the scene shown.
 */

/**
 * The state kept for the next reload.
 * @typedef {object} SavedState
 * @property {Scene} scene
 * @property {number} pose
 * @property {{ox: number, oy: number, k: number, left?: number, top?: number}} [view]  the view, and
 *   where the canvas was on the page then
 * @property {{design: Design, scene: Scene, which: number | null} | null} result  the design shown, when fresh
 * @property {boolean} live
 */

const AUTOSAVE = 'linkwright.autosave.v1';

/**
 * Offers `blob` as a download called `name`.
 * @param {Blob} blob
 * @param {string} name
 */
export function saveBlob(blob, name) {
  const url = URL.createObjectURL(blob);
  const a = html('a', { href: url, download: name });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}

/**
 * Saves the scene as a file: a project/1 (docs/formats.md) when `design` is given — the design shown
 * for it, with `which` (null: the design itself, i: its alternative i), the counterbalance springs
 * suggested (`balance`, or null) and the print settings (`print`) — so that it opens with all of it,
 * without a redesign; else the plain scene/1.
 * @param {Scene} scene
 * @param {Partial<Project>} [shown]
 */
export function saveScene(scene, { design = undefined, which = null, balance = null, print = null } = {}) {
  const name = (scene.name || 'scene').replace(/[^\w.-]+/g, '_');
  const doc = design
    ? { linkwright: PROJECT, scene: toFile(scene), design, which, balance, print }
    : toFile(scene);
  saveBlob(new Blob([JSON.stringify(doc, null, 1)], { type: 'application/json' }), `${name}.json`);
}

/** The project file's format. */
export const PROJECT = 'project/1';

/** Files larger than this are not scenes, designs or projects (a project of the largest example with
 * its design is about 300 kB). */
const MAX_FILE_BYTES = 8 * 1024 * 1024;

/**
 * Reads a dropped or chosen file: a scene/1, a design/1 (for the scene shown), or a project/1 (a
 * scene with its design: `{scene, project: {design, which, balance, print}}`).
 * @param {File} file
 * @returns {Promise<OpenedFile>}
 */
export async function readFile(file) {
  if (file.size > MAX_FILE_BYTES) throw new Error(`${file.name} is larger than 8 MB: not a Linkwright file`);
  /** @type {any} the file's JSON, of any shape until checked */
  let doc;
  try {
    doc = JSON.parse(await file.text());
  } catch (e) {
    throw new Error(`${file.name} is not JSON (${e instanceof Error ? e.message : e})`);
  }
  if (doc?.linkwright === 'design/1') return { design: doc };
  if (doc?.linkwright === PROJECT) return { scene: normalize(doc.scene), project: project(doc) };
  return { scene: normalize(doc) };
}

/**
 * The parts of a project/1 besides its scene, checked for their shape (the server checks the design
 * against the scene when it is shown).
 * @param {any} doc  a project/1's JSON
 * @returns {Project}
 */
function project(doc) {
  /** @type {(v: unknown) => boolean} */
  const object = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);
  const design = doc.design;
  if (!object(design) || design.linkwright !== 'design/1') {
    throw new Error('its "design" is not a design/1 document');
  }
  const count = design.alternatives?.length ?? 0;
  const which = doc.which ?? null;
  if (which !== null && !(Number.isInteger(which) && which >= 0 && which < count)) {
    throw new Error(`its "which" is ${JSON.stringify(which)}: null for the design, or an alternative from 0 to ${count - 1}`);
  }
  const balance = object(doc.balance) && Array.isArray(doc.balance.springs) ? doc.balance : null;
  const print = object(doc.print) && object(doc.print.values) ? doc.print : null;
  return { design, which, balance, print };
}

/**
 * Wires drag-and-drop of files onto the page, `overlay` shown while files are over it; `open(file)`
 * handles one.
 * @param {HTMLElement} overlay
 * @param {(file: File) => void} open
 */
export function dropTarget(overlay, open) {
  let depth = 0;
  /** @type {(e: DragEvent) => boolean} */
  const hasFiles = (e) => [...(e.dataTransfer?.types || [])].includes('Files');
  window.addEventListener('dragenter', (e) => { if (hasFiles(e)) { depth++; overlay.hidden = false; } });
  window.addEventListener('dragleave', () => { depth = Math.max(0, depth - 1); if (!depth) overlay.hidden = true; });
  window.addEventListener('dragover', (e) => { if (hasFiles(e)) e.preventDefault(); });
  window.addEventListener('drop', (e) => {
    if (!hasFiles(e)) return;
    e.preventDefault();
    depth = 0;
    overlay.hidden = true;
    const file = e.dataTransfer?.files[0];
    if (file) open(file);
  });
}

/**
 * A small picture of a scene: fixed bodies and the moving bodies at every pose.
 * @param {Scene} scene
 */
export function sceneThumbnail(scene, w = 150, h = 96) {
  const moving = scene.moving_bodies.flatMap((b, i) => b.poses.map((p, k) => ({ i, k, pts: placed(b.polygon, p) })));
  const all = [...scene.fixed_bodies.flatMap((b) => b.polygon), ...moving.flatMap((m) => m.pts)];
  const pic = svg('svg', { viewBox: `0 0 ${w} ${h}`, width: w, height: h });
  if (!all.length) return pic;
  const bb = bounds(all), pad = 5;
  const k = Math.min((w - 2 * pad) / Math.max(bb.maxX - bb.minX, 1e-9), (h - 2 * pad) / Math.max(bb.maxY - bb.minY, 1e-9));
  const ox = (w - (bb.maxX - bb.minX) * k) / 2, oy = (h - (bb.maxY - bb.minY) * k) / 2;
  /** @type {(p: Point) => Point} */
  const s = (p) => [ox + (p[0] - bb.minX) * k, h - oy - (p[1] - bb.minY) * k];
  for (const b of scene.fixed_bodies) pic.append(svg('polygon', { class: 'fixed', points: points(b.polygon.map(s)) }));
  for (const m of moving) {
    pic.append(svg('polygon', { class: m.k === 0 ? 'moving' : 'skin', style: `--c:${bodyColour(m.i)}`, points: points(m.pts.map(s)) }));
  }
  return pic;
}

/**
 * Fills the example gallery `list`; `choose(scene, entry)` opens one, `fail(message)` says why the
 * gallery cannot be loaded.
 * @param {HTMLElement} list
 * @param {(scene: Scene, entry: ExampleSummary) => void} choose
 * @param {(message: string) => void} fail
 */
export async function fillGallery(list, choose, fail) {
  clear(list);
  let entries;
  try {
    entries = await api.examples();
  } catch (e) {
    fail(e instanceof Error ? e.message : String(e));
    return;
  }
  for (const entry of entries) {
    const button = html('button', { class: 'example', 'data-example': entry.name, title: `Open “${entry.title}”` }, [
      html('div', { class: 'pic' }),
      html('b', { text: entry.title }),
      html('small', { text: `${entry.bodies} moving bod${entry.bodies === 1 ? 'y' : 'ies'}, ${entry.poses} poses` }),
    ]);
    list.append(button);
    api.example(entry.name).then((scene) => {
      button.querySelector('.pic')?.append(sceneThumbnail(normalize(scene)));
      button.addEventListener('click', () => choose(normalize(scene), entry));
    }).catch((e) => fail(e.message));
  }
}

/**
 * The last session's state, or null.
 * @returns {SavedState | null}
 */
export function restore() {
  try {
    const saved = JSON.parse(localStorage.getItem(AUTOSAVE) || 'null');
    if (!saved?.scene) return null;
    return { ...saved, scene: normalize(saved.scene) };
  } catch {
    return null;
  }
}

/**
 * Saves the state for the next reload (quietly does nothing when storage is unavailable or full).
 * @param {SavedState} state
 */
export function autosave(state) {
  try {
    localStorage.setItem(AUTOSAVE, JSON.stringify(state));
  } catch {
    // Private mode or full storage: the scene can still be saved as a file.
  }
}
