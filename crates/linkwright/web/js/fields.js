// The engine names what is wrong by its place in the scene file (`moving_bodies[0].poses[1]`); the
// person knows the screen. These are the screen's words for those places, and what to select there.

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
};
const WEIGHTS = { accuracy: 'Accuracy', smoothness: 'Smoothness', location: 'Location', size: 'Size' };

/**
 * `message` (the engine's words) with the scene file's names of places (`settings.pose_tolerance`,
 * `linkage_region`, `moving_bodies[0].poses[2]`) in the screen's words.
 */
export function screenWords(message, scene) {
  return message
    .replace(/\b(?:moving_bodies|fixed_bodies)\[\d+\](?:\.poses\[\d+\])?/g, (f) => screenField(f, scene).text)
    .replace(/\b(?:settings|weights)\.\w+/g, (f) => `“${screenField(f, scene).text}”`)
    .replace(/\blinkage_region\b/g, 'the linkage region')
    .replace(/\bavoid_regions\b/g, 'the avoid regions')
    .replace(/\bmust_hit_poses\b/g, 'the poses marked must-hit')
    .replace(/\bpinned_joints\b/g, 'the pinned joints')
    .replace(/\bthe the\b/g, 'the');
}

/**
 * Where `field` is on screen: `{text}` in words (“Moving body “lid”, pose 2”, “Settings › Samples”),
 * with `selection` and `pose` when it names a drawn shape or one of its poses.
 */
export function screenField(field, scene) {
  const path = field.replace(/^scene\.?/, '');
  let m = /^(moving_bodies|fixed_bodies)\[(\d+)\](.*)$/.exec(path);
  if (m) {
    const moving = m[1] === 'moving_bodies';
    const index = Number(m[2]);
    const name = scene[m[1]]?.[index]?.name;
    const text = `${moving ? 'Moving body' : 'Fixed body'} ${name ? `“${name}”` : index + 1}`;
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
