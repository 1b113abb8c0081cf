// @ts-check
// The side panel's Object and Settings tabs: the list of shapes with names and poses, how the object is
// built, and the search settings. Every change goes through the store as one undo step.

import { buildWord, DEFAULT_BUILD, extent, MATERIALS, modelExtent, parseBuild, SCALES } from './build.js';
import { bodyColour } from './canvas.js';
import { tidy } from './geom.js';
import * as S from './scene.js';
import { clear, html } from './svg.js';

/**
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./scene.js').ShapeKind} ShapeKind
 * @typedef {import('./scene.js').Settings} Settings
 * @typedef {import('./scene.js').Weights} Weights
 * @typedef {import('./build.js').Build} Build
 * @typedef {(Node | string | null)[]} Nodes
 */

/**
 * Replaces a panel's content, keeping the focused field focused (the panel is rebuilt on every change).
 * @param {HTMLElement} host
 * @param {Nodes} children
 */
function rebuild(host, children) {
  const active = document.activeElement;
  const focused = active instanceof HTMLElement && host.contains(active) ? active.dataset.key : null;
  clear(host).append(...children.filter((c) => c !== null));
  if (focused) {
    const again = host.querySelector(`[data-key="${CSS.escape(focused)}"]`);
    if (again instanceof HTMLElement) again.focus();
  }
}

/**
 * A number field that calls `onCommit` with a number typed (Enter or leaving the field).
 * @param {number} value
 * @param {string} key  its `data-key`, which keeps it focused across a rebuild
 * @param {(v: number) => void} onCommit
 * @param {Record<string, unknown>} [attrs]
 */
const number = (value, key, onCommit, attrs = {}) =>
  html('input', {
    type: 'number', value: String(value), 'data-key': key, step: 'any', ...attrs,
    onchange: (e) => {
      const v = Number(e.currentTarget.value);
      if (e.currentTarget.value !== '' && Number.isFinite(v)) onCommit(v);
    },
    onkeydown: (e) => { if (e.key === 'Enter') e.currentTarget.blur(); },
  });

/**
 * The Object tab: the shapes drawn, each to select, rename or delete, and the selected moving body's poses.
 * @param {HTMLElement} host
 * @param {Store} store
 */
export function renderObjectTab(host, store) {
  const { scene, ui } = store;
  const sel = ui.selection;
  /** @type {(kind: ShapeKind, index: number) => boolean} */
  const isSel = (kind, index) => !!sel && sel.kind === kind && sel.index === index;
  /** @type {(kind: ShapeKind, index: number) => void} */
  const select = (kind, index) => store.setUi({ selection: { kind, index } });
  /** @type {(kind: ShapeKind, index: number) => void} */
  const remove = (kind, index) => store.edit(`delete ${kind}`, (s) => S.deleteShape(s, { kind, index }));
  /** @type {(kind: ShapeKind, index: number, label: string, colour: string, named: boolean) => HTMLLIElement} */
  const row = (kind, index, label, colour, named) =>
    html('li', { class: isSel(kind, index) ? 'row selected' : 'row', onclick: () => select(kind, index) }, [
      html('span', { class: 'swatch', style: `background:${colour}` }),
      named
        ? html('input', {
          class: 'name', value: label, 'data-key': `${kind}-name-${index}`, 'aria-label': 'name',
          onclick: (e) => e.stopPropagation(),
          onchange: (e) => {
            const name = e.currentTarget.value;
            store.edit('rename', (s) => { (kind === 'fixed' ? s.fixed_bodies : s.moving_bodies)[index].name = name; });
          },
        })
        : html('span', { class: 'name', text: label }),
      html('button', { class: 'icon', title: 'Delete', 'aria-label': `delete ${label}`, text: '×', onclick: (e) => { e.stopPropagation(); remove(kind, index); } }),
    ]);

  /** @type {Nodes} */
  const out = [];
  out.push(html('h3', { text: 'Fixed bodies' }));
  out.push(scene.fixed_bodies.length
    ? html('ul', { class: 'list' }, scene.fixed_bodies.map((b, i) => row('fixed', i, b.name, '#c4c4c4', true)))
    : html('p', { class: 'empty', text: 'None yet: choose Draw “Fixed body” and drag a rectangle.' }));
  out.push(html('h3', { text: 'Moving bodies' }));
  out.push(scene.moving_bodies.length
    ? html('ul', { class: 'list' }, scene.moving_bodies.map((b, i) => row('moving', i, b.name, bodyColour(i), true)))
    : html('p', { class: 'empty', text: 'None yet: choose Draw “Moving body” to draw the part that moves.' }));
  out.push(html('h3', { text: 'Regions' }));
  const regions = [];
  if (scene.linkage_region) regions.push(row('region', 0, 'linkage region', '#2b6cb0', false));
  (scene.avoid_regions || []).forEach((_, i) => regions.push(row('avoid', i, `avoid region ${i + 1}`, '#d62728', false)));
  out.push(regions.length
    ? html('ul', { class: 'list' }, regions)
    : html('p', { class: 'empty', text: 'Optional: a linkage region says where the joints should go; avoid regions where links may not go.' }));

  if (sel?.kind === 'moving' && scene.moving_bodies[sel.index]) {
    out.push(...poseTable(store, sel.index));
    if (scene.moving_bodies[sel.index].path) out.push(...pathSection(store, sel.index));
  }
  rebuild(host, out);
}

/**
 * The selected moving body's poses as editable numbers.
 * @param {Store} store
 * @param {number} b
 */
function poseTable(store, b) {
  const body = store.scene.moving_bodies[b];
  /** @type {(p: number, k: number, v: number) => void} */
  // Through the scene's own moves, so a body's path goes with it.
  const set = (p, k, v) => store.edit(`edit pose ${p + 1}`, (s) => {
    if (k === 2) return S.setPoseAngle(s, b, p, v);
    const at = s.moving_bodies[b].poses[p];
    S.translate(s, { kind: 'moving', index: b }, k === 0 ? [tidy(v, 3) - at[0], 0] : [0, tidy(v, 3) - at[1]], p);
  });
  const head = html('tr', {}, [
    ...['Pose', 'x', 'y', 'angle°'].map((t) => html('th', { text: t })),
    html('th', { text: 'Must hit', title: 'The linkage must reach this pose within 0.5% of the body size and 0.5°; other poses in between are guides' }),
  ]);
  const n = body.poses.length;
  /** @type {(p: number) => HTMLInputElement} */
  const mustHit = (p) => {
    const ends = p === 0 || p === n - 1;
    return html('input', {
      type: 'checkbox', 'data-key': `must-hit-${p}`, checked: S.isMustHit(store.scene, p), disabled: ends,
      'aria-label': `Pose ${p + 1} must be hit`,
      title: ends ? 'The first and last poses, where the object rests, are always hit' : 'Must the linkage hit this pose?',
      onclick: (e) => e.stopPropagation(),
      onchange: (e) => {
        const on = e.currentTarget.checked;
        store.edit(`${on ? 'mark' : 'unmark'} pose ${p + 1} must-hit`, (s) => S.setMustHit(s, p, on));
      },
    });
  };
  const rows = body.poses.map((pose, p) =>
    html('tr', { class: p === store.ui.pose ? 'current' : '', onclick: () => store.setUi({ pose: p }) }, [
      html('td', { text: String(p + 1) }),
      html('td', {}, [number(tidy(pose[0], 2), `pose-${b}-${p}-x`, (v) => set(p, 0, v))]),
      html('td', {}, [number(tidy(pose[1], 2), `pose-${b}-${p}-y`, (v) => set(p, 1, v))]),
      html('td', {}, [number(tidy(pose[2], 2), `pose-${b}-${p}-a`, (v) => set(p, 2, v))]),
      html('td', { class: 'must-hit' }, [mustHit(p)]),
    ]));
  return [
    html('h3', { text: `Poses of ${body.name}` }),
    html('table', { class: 'poses' }, [html('thead', {}, [head]), html('tbody', {}, rows)]),
    html('p', { class: 'note', text: 'Pose 1 is where the motion starts; the linkage visits the poses in order. Every moving body has one pose per column of the pose bar. The first and last poses are always hit; tick “Must hit” for a pose in between that matters as much (◆ in the pose bar).' }),
  ];
}

/**
 * The selected body's path: what it is, and the points its tracer must pass exactly, typed as point
 * numbers (from 1, as the hint names them when one is double-clicked on the canvas).
 * @param {Store} store
 * @param {number} b
 */
function pathSection(store, b) {
  const path = /** @type {import('./scene.js').DrawnPath} */ (store.scene.moving_bodies[b].path);
  const n = path.points.length;
  const field = html('input', {
    type: 'text', 'data-key': `exact-${b}`, 'aria-label': 'Exact points', placeholder: 'none',
    value: (path.exact || []).map((i) => i + 1).join(', '),
    title: `Numbers of path points, 1 to ${n}, separated by commas`,
    onchange: (e) => {
      const input = e.currentTarget;
      const words = input.value.split(/[\s,;]+/).filter(Boolean);
      const numbers = words.map(Number);
      const bad = words.find((w, k) => !Number.isInteger(numbers[k]) || numbers[k] < 1 || numbers[k] > n);
      if (bad !== undefined) {
        store.hint(`“${bad}” is not a point of the path: type numbers from 1 to ${n}, separated by commas.`);
        input.value = (path.exact || []).map((i) => i + 1).join(', ');
        return;
      }
      store.edit('set the exact path points', (s) => {
        const p = s.moving_bodies[b].path;
        if (!p) return;
        const exact = [...new Set(numbers.map((k) => k - 1))].sort((x, y) => x - y);
        if (exact.length) p.exact = exact;
        else delete p.exact;
      });
    },
    onkeydown: (e) => { if (e.key === 'Enter') e.currentTarget.blur(); },
  });
  return [
    html('h3', { text: `Path of ${store.scene.moving_bodies[b].name}` }),
    html('p', { class: 'note', text: `${path.closed ? 'A loop' : 'An open path'} of ${n} points, which the body's tracer follows.` }),
    html('label', { class: 'field' }, [html('span', { text: 'Exact points' }), field]),
    html('p', { class: 'note', text: 'The tracer passes these points exactly, and the rest of the path as closely as it can. Double-click the path with the Select tool to mark or free the point there. A four-bar passes at most nine.' }),
  ];
}

/** @type {[keyof Weights, string, string][]} */
const WEIGHTS = [
  ['accuracy', 'Accuracy', 'how closely the poses are hit'],
  ['smoothness', 'Smoothness', 'how direct the motion between poses is'],
  ['location', 'Location', 'how strongly joints keep to the linkage region'],
  ['size', 'Size', 'how short the links are'],
  ['transmission', 'Transmission', 'how strongly the links keep a comfortable angle, away from dead points'],
];

/**
 * A log-scale slider (0.01 to 1,000,000: the accuracy's default, 10,000, is not its end) with a number
 * field beside it.
 * @param {Store} store
 * @param {keyof Weights} key
 * @param {string} label
 * @param {string} help
 */
function weightControl(store, key, label, help) {
  const value = store.scene.weights[key];
  const pos = value > 0 ? Math.log10(value) : -2;
  const field = number(value, `w-${key}`, (v) => commit(Math.max(0, v)), { min: 0 });
  /** @type {(v: number) => void} */
  const commit = (v) => store.edit(`weight ${key}`, (s) => { s.weights[key] = v; });
  const slider = html('input', {
    type: 'range', min: -2, max: 6, step: 0.05, value: String(pos), 'data-key': `ws-${key}`, 'aria-label': `${label} weight`,
    oninput: (e) => { field.value = String(tidy(10 ** Number(e.currentTarget.value), 3)); },
    onchange: (e) => commit(tidy(10 ** Number(e.currentTarget.value), 3)),
  });
  return html('div', { class: 'field' }, [
    html('label', { text: label, title: help }), slider, field,
    html('small', { text: help }),
  ]);
}

/** The scale and the material chosen last, so that switching between a model and full size gives
 * back what was chosen before. */
const lastBuild = { scale: 'auto', material: 'plywood' };

/**
 * How the object is built: a printed model at a scale (auto or fixed), or full size in a material.
 * @param {Store} store
 * @returns {Nodes}
 */
function buildSection(store) {
  const { scene } = store;
  const word = scene.build ?? DEFAULT_BUILD;
  const b = parseBuild(word);
  if (b?.kind === 'model') lastBuild.scale = b.scale;
  if (b?.kind === 'full') lastBuild.material = b.material;
  /** @type {(next: Build) => void} */
  const set = (next) => store.edit('build', (s) => { s.build = buildWord(next); });
  /** @type {(value: 'model' | 'full', label: string, help: string) => HTMLLabelElement} */
  const kind = (value, label, help) => html('label', { class: 'check', title: help }, [
    html('input', {
      type: 'radio', name: 'build-kind', value, 'data-key': `build-${value}`, checked: b?.kind === value,
      onchange: () => set(value === 'model' ? { kind: 'model', scale: lastBuild.scale } : { kind: 'full', material: lastBuild.material }),
    }),
    ` ${label}`,
  ]);
  /** @type {Nodes} */
  const out = [
    html('fieldset', { class: 'build-kind' }, [
      html('legend', { text: 'Built as' }),
      kind('model', 'Printed model', 'a 3D-printed model of the object, at a scale'),
      kind('full', 'Full size', 'the object at its real size, made in a workshop'),
    ]),
  ];
  /** @type {(key: string, label: string, options: string[][], selected: string, onPick: (v: string) => void) => HTMLElement[]} */
  const menu = (key, label, options, selected, onPick) => {
    const id = `settings-${key}`;
    const select = html('select', { id, 'data-key': key, onchange: (e) => onPick(e.currentTarget.value) },
      options.map(([v, t]) => html('option', { value: v, text: t, selected: v === selected })));
    return [html('label', { for: id, text: label }), select];
  };
  if (b?.kind === 'model') {
    const scales = [...new Set([...SCALES, ...(b.scale === 'auto' ? [] : [b.scale])])];
    const size = b.scale === 'auto' ? null : modelExtent(scene, b.scale, store.lengthUnits);
    const help = b.scale === 'auto'
      ? '1:1 when the links fit the printer’s bed and the pins fit the parts, else the largest scale at which they do (the Result tab names it)'
      : size ? `everything drawn is ${extent(size)} in the model` : 'one length of the model for so many of the object';
    out.push(html('div', { class: 'field' }, [
      ...menu('build-scale', 'Scale', [['auto', 'Auto'], ...scales.map((r) => [r, r === '1:1' ? '1:1 (real size)' : r])], b.scale,
        (scale) => set({ kind: 'model', scale })),
      html('small', { text: help }),
    ]));
  } else if (b?.kind === 'full') {
    out.push(html('div', { class: 'field' }, [
      ...menu('build-material', 'Material', MATERIALS, b.material, (material) => set({ kind: 'full', material })),
      html('small', { text: 'the object at its real size, made in a workshop: no print check' }),
    ]));
  } else {
    out.push(html('p', { class: 'note', text: `The scene asks for the build “${word}”, which this app does not know: choose one above.` }));
  }
  return out;
}

/**
 * The Settings tab: units, build, mechanism type, weights, tolerances and the search's size.
 * @param {HTMLElement} host
 * @param {Store} store
 */
export function renderSettingsTab(host, store) {
  const { scene } = store;
  const st = scene.settings;
  /** @type {(k: keyof Settings, v: number) => void} */
  const setSetting = (k, v) => store.edit(`setting ${k}`, (s) => { s.settings[k] = v; });
  /** @type {(label: string, control: HTMLElement, help?: string) => HTMLDivElement} */
  const row = (label, control, help) => html('div', { class: 'field' }, [html('label', { text: label }), control, help ? html('small', { text: help }) : null]);
  const mechanism = html('select', {
    'data-key': 'mechanism',
    onchange: (e) => {
      const mechanism = e.currentTarget.value;
      store.edit('mechanism', (s) => { s.mechanism = mechanism; });
    },
  }, [
    ['auto', 'Automatic (best of all types)'],
    ...store.families.map((f) => [f.id, f.description]),
  ].map(([v, t]) => html('option', { value: v, text: t, selected: scene.mechanism === v })));
  const samples = html('div', { class: 'inline' }, [
    number(st.samples, 'samples', (v) => setSetting('samples', Math.min(1000000, Math.max(1, Math.round(v)))), { min: 1, max: 1000000, step: 1000 }),
    .../** @type {[string, number][]} */ ([['Quick', 5000], ['Normal', 20000], ['Paper', 100000]]).map(([t, n]) =>
      html('button', { class: st.samples === n ? 'small on' : 'small', text: t, title: `${n} samples`, onclick: () => setSetting('samples', n) })),
  ]);
  const seed = html('div', { class: 'inline' }, [
    number(st.seed, 'seed', (v) => setSetting('seed', Math.max(0, Math.round(v))), { min: 0, step: 1 }),
    html('button', { class: 'small', text: 'New seed', title: 'Another random search', onclick: () => setSetting('seed', Math.floor(Math.random() * 1e6)) }),
  ]);
  // The engine's units by their symbols (none until loaded), and the scene's word as it is written.
  const knownUnits = store.lengthUnits.map((u) => u.symbol);
  const units = html('select', {
    'data-key': 'units', 'aria-label': 'Units',
    onchange: (e) => {
      const units = e.currentTarget.value;
      store.edit('units', (s) => { s.units = units; });
    },
  }, [...new Set([...knownUnits, scene.units || 'mm'])].map((u) => html('option', { value: u, text: u, selected: (scene.units || 'mm') === u })));
  rebuild(host, [
    html('h3', { text: 'Drawing' }),
    row('Units', units, 'what one unit of the drawing is; changing it renames the unit, it does not rescale the drawing'),
    html('h3', { text: 'Build' }),
    ...buildSection(store),
    html('h3', { text: 'Mechanism' }),
    html('div', { class: 'field wide' }, [html('label', { text: 'Type' }), mechanism]),
    html('h3', { text: 'What matters most' }),
    ...WEIGHTS.map(([k, l, h]) => weightControl(store, k, l, h)),
    html('h3', { text: 'Tolerances' }),
    row('Pose tolerance', number(st.pose_tolerance, 'pose_tolerance', (v) => setSetting('pose_tolerance', Math.max(0, v)), { min: 0, step: 0.1 }),
      'how loosely the in-between poses may be met, as a fraction of the body size (0 = exactly)'),
    row('Angle tolerance °', number(st.angle_tolerance_deg, 'angle_tolerance_deg', (v) => setSetting('angle_tolerance_deg', Math.max(0, v)), { min: 0, step: 1 })),
    row('Min. transmission °', number(st.min_transmission_deg, 'min_transmission_deg', (v) => setSetting('min_transmission_deg', Math.max(0, v)), { min: 0, max: 80, step: 1 }),
      'how far every joint angle must stay from a dead point (0° or 180°)'),
    row('Comfortable transmission °', number(st.comfortable_transmission_deg, 'comfortable_transmission_deg', (v) => setSetting('comfortable_transmission_deg', Math.min(80, Math.max(0, v))), { min: 0, max: 80, step: 1 }),
      'the angle the search prefers every joint to keep from a dead point (textbooks ask for 40°); the Transmission weight says how much'),
    html('h3', { text: 'Search' }),
    row('Samples', samples, 'more samples: better designs, longer runs'),
    row('Seed', seed, 'the same seed gives the same design'),
    row('Particles', number(st.particles, 'particles', (v) => setSetting('particles', Math.min(1000, Math.max(1, Math.round(v)))), { min: 1, max: 1000, step: 10 })),
    row('Iterations', number(st.iterations, 'iterations', (v) => setSetting('iterations', Math.min(200, Math.max(0, Math.round(v)))), { min: 0, max: 200, step: 1 })),
    html('button', {
      text: 'Reset to defaults',
      onclick: () => store.edit('reset settings', (s) => { s.weights = { ...S.DEFAULT_WEIGHTS }; s.settings = { ...S.DEFAULT_SETTINGS }; s.mechanism = 'auto'; }),
    }),
  ]);
}
