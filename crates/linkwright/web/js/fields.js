// @ts-check
// The engine names what is wrong by its place in the scene file (`moving_bodies[0].poses[1]`); the
// person knows the screen. These are the screen's words for those places, and what to select there.

/**
 * @typedef {import('./scene.js').Scene} Scene
 * @typedef {{text: string, selection?: import('./scene.js').Selection, pose?: number}} ScreenPlace
 *   Where a field of the scene file is on screen: in words, and the shape (and pose) to select there.
 */

/** @type {Record<string, string>} */
const SETTINGS = {
  mechanism: 'Type',
  build: 'Build',
  units: 'Units',
  samples: 'Samples',
  seed: 'Seed',
  particles: 'Particles',
  iterations: 'Iterations',
  pose_tolerance: 'Pose tolerance',
  angle_tolerance_deg: 'Angle tolerance',
  min_transmission_deg: 'Min. transmission',
  comfortable_transmission_deg: 'Comfortable transmission',
};
/** @type {Record<string, string>} */
const WEIGHTS = { accuracy: 'Accuracy', smoothness: 'Smoothness', location: 'Location', size: 'Size', transmission: 'Transmission' };

/**
 * A number as the engine writes it (Rust: `5000000.0`, `1e6`, `NaN`, `inf`) in the screen's words.
 * @param {string} text
 */
function plainNumber(text) {
  const v = Number(text.replace(/^(-?)inf$/, '$1Infinity'));
  if (Number.isNaN(v)) return 'not a number';
  if (!Number.isFinite(v)) return v > 0 ? 'infinite' : 'minus infinite';
  return String(v);
}

/**
 * `message` (the engine's words) in the screen's words: the scene file's names of places
 * (`settings.pose_tolerance`, `linkage_region`, `moving_bodies[0].poses[2]`) as the screen names
 * them, a pose written as the file does (`[x_mm, y_mm, angle_deg]`) as its x, y and angle, an
 * outline's vertices and edges (counted from 0) as its corners and sides (counted from 1), numbers
 * such as `1e6` written out, and the mechanism families (`"slider_crank"`) as Settings › Type
 * names them (`families`, the engine's list, when loaded).
 * @param {string} message
 * @param {Scene} scene
 * @param {{id: string, label: string}[]} [families]
 */
export function screenWords(message, scene, families = []) {
  let out = message
    .replace(/\bis \[([^\],]+), ([^\],]+), ([^\],]+)\]; write three finite numbers \[x_mm, y_mm, angle_deg\] within ±(\S+)/g,
      (_, x, y, a, most) => `is at x ${plainNumber(x)}, y ${plainNumber(y)}, angle ${plainNumber(a)}°; x, y and the angle must be numbers between −${plainNumber(most)} and ${plainNumber(most)}`)
    .replace(/\[x_mm, y_mm, angle_deg\]/g, 'x, y and angle')
    .replace(/\bvertex (\d+)/g, (_, i) => `corner ${Number(i) + 1}`)
    .replace(/\bedge (\d+) crosses edge (\d+)/g, (_, i, j) => `side ${Number(i) + 1} crosses side ${Number(j) + 1}`)
    .replace(/\bvertices\b/g, 'corners')
    .replace(/\ba polygon\b/g, 'an outline')
    .replace(/(^|[^\w.])(\d+(?:\.\d+)?e[+-]?\d+)\b/g, (_, before, n) => `${before}${plainNumber(n)}`)
    .replace(/\b(?:moving_bodies|fixed_bodies)\[\d+\](?:\.poses\[\d+\])?/g, (f) => screenField(f, scene).text)
    .replace(/\b(?:settings|weights)\.\w+/g, (f) => `“${screenField(f, scene).text}”`)
    .replace(/\blinkage_region\b/g, 'the linkage region')
    .replace(/\bavoid_regions\b/g, 'the avoid regions')
    .replace(/\bmust_hit_poses\b/g, 'the poses marked must-hit')
    .replace(/\bpinned_joints\b/g, 'the pinned joints')
    .replace(/\bthe the\b/g, 'the');
  for (const f of [{ id: 'auto', label: 'automatic' }, ...families]) {
    out = out.replaceAll(`"${f.id}"`, `“${f.label}”`).replace(new RegExp(`^${f.id}\\b`), `The ${f.label}`);
  }
  return out;
}

/**
 * Where `field` is on screen: `{text}` in words (“Moving body “lid”, pose 2”, “Settings › Samples”),
 * with `selection` and `pose` when it names a drawn shape or one of its poses.
 * @param {string} field
 * @param {Scene} scene
 * @returns {ScreenPlace}
 */
export function screenField(field, scene) {
  const path = field.replace(/^scene\.?/, '');
  let m = /^(moving_bodies|fixed_bodies)\[(\d+)\](.*)$/.exec(path);
  if (m) {
    const moving = m[1] === 'moving_bodies';
    const index = Number(m[2]);
    const name = (moving ? scene.moving_bodies : scene.fixed_bodies)[index]?.name;
    const text = `${moving ? 'Moving body' : 'Fixed body'} ${name ? `“${name}”` : index + 1}`;
    /** @type {import('./scene.js').Selection} */
    const selection = { kind: moving ? 'moving' : 'fixed', index };
    const pose = /^\.poses\[(\d+)\]/.exec(m[3]);
    if (moving && pose) return { text: `${text}, pose ${Number(pose[1]) + 1}`, selection, pose: Number(pose[1]) };
    if (/^\.(outline|polygon)/.test(m[3])) return { text: `${text}, its outline`, selection };
    return { text, selection };
  }
  if ((m = /^settings\.(\w+)/.exec(path)) || (m = /^(mechanism|build|units)$/.exec(path))) return { text: `Settings › ${SETTINGS[m[1]] || m[1]}` };
  if ((m = /^weights\.(\w+)/.exec(path))) return { text: `Settings › ${WEIGHTS[m[1]] || m[1]} weight` };
  if (path.startsWith('linkage_region')) return { text: 'Linkage region' };
  if ((m = /^avoid_regions\[(\d+)\]/.exec(path))) return { text: `Avoid region ${Number(m[1]) + 1}` };
  return { text: path || 'the scene' };
}
