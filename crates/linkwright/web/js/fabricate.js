// @ts-check
// Making the parts: print settings, the Fabricate action (a job on the server), the summary, the
// downloads, the assembly steps, and the 3D preview of the printed parts moving with the linkage. For a
// full-size build the same action asks for the workshop's files: the parts to cut, their stock and
// bolts, the builder's notes, the files and the steps.

import * as api from './api.js';
import { buildWord, DEFAULT_BUILD, describe, parseBuild } from './build.js';
import { partColour, partKind, Preview3D, ROLE_COLOURS } from './preview3d.js';
import { bracketMounts, springCut, springList, withMounts } from './springs.js';
import { html } from './svg.js';

/**
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./result.js').Results} Results
 * @typedef {import('./api.js').Fabrication} Fabrication
 * @typedef {import('./api.js').PrintReport} PrintReport
 * @typedef {import('./api.js').WorkshopReport} WorkshopReport
 * @typedef {import('./api.js').FabricationFile} FabricationFile
 * @typedef {import('./api.js').Preview} Preview
 * @typedef {import('./api.js').PrintSettings} PrintSettings
 * @typedef {import('./api.js').Design} Design
 * @typedef {import('./api.js').Issue} Issue
 * @typedef {import('./build.js').Build} Build
 * @typedef {import('./springs.js').Naming} Naming
 * @typedef {(Node | string)[]} Nodes
 */

/**
 * The print settings panel as filled in: the fields typed (by path, millimetres), the faces the
 * links may go on, and whether the parts get hooks for counterbalance springs.
 * @typedef {{values: Record<string, number>, faces: string, springs?: boolean}} PrintForm
 */

/**
 * The design (and mechanism) something was made for, to tell whether it is of the design shown.
 * @typedef {{design: Design, which: number | null}} MadeFor
 * @typedef {MadeFor & {answer: Fabrication}} Made  parts made
 * @typedef {MadeFor & {problems: string[], fields: string[]}} Failed  why they could not be: in plain
 *   words, and the settings' fields named
 * @typedef {{controller: AbortController, started: number, timer: ReturnType<typeof setInterval> | null}} Job
 */

const SAVED = 'linkwright.print.v1';

/** The print settings the panel offers, as [path in the settings, label, help]; the others keep
 * their defaults (GET /api/fabricate/settings). Millimetres. @type {[string, string, string | null][]} */
const FIELDS = [
  ['link_width', 'Link width', 'how wide the printed links are'],
  ['link_thickness', 'Link thickness', 'how thick each link is'],
  ['pin_radius', 'Pin radius', 'the pins the parts turn on'],
  ['radial_clearance', 'Pin clearance', 'play between a pin and its hole: more if pins come out too tight'],
  ['axial_gap', 'Layer gap', 'play between stacked parts'],
  ['bed.width', 'Bed width', 'the usable size of your printer’s bed'],
  ['bed.depth', 'Bed depth', null],
];
const FACES = [['auto', 'Automatic'], ['one', 'Front face only'], ['both', 'Both faces']];
const BUSY_TEXT = 'Making the parts: placing pins and connectors, stacking the layers so nothing rubs, building the solids…';
const BUSY_TEXT_FULL = 'Making the workshop files…';

/** The downloads by what they are for: [heading, which file names]. @type {[string, (name: string) => boolean][]} */
const FILE_GROUPS = [
  ['Parts to print (STL)', (name) => name.endsWith('.stl')],
  ['Print beds (3MF)', (name) => name.endsWith('.3mf')],
  ['Laser cutting', (name) => name.startsWith('profiles.')],
  ['Profiles to cut (laser, CNC router, waterjet)', (name) => name.startsWith('profiles_')],
  ['Lists', (name) => name.endsWith('.csv')],
  ['Instructions', (name) => ['assembly.svg', 'fabrication.json', 'workshop_assembly.svg', 'workshop.json'].includes(name)],
];

/**
 * What a file other than a part is for (by its kind, for files this app does not name).
 * @param {string} name
 */
function purpose(name) {
  if (name === 'assembly.3mf') return 'every part, assembled';
  if (name.endsWith('.3mf')) return 'the parts laid out on one bed';
  if (name.startsWith('profiles.')) return 'outlines with holes';
  const stock = /^profiles_(.+)mm\.(dxf|svg)$/.exec(name);
  if (stock) return `the parts cut from ${stock[1]} mm stock, with their holes`;
  if (name === 'assembly.svg' || name === 'workshop_assembly.svg') return 'the layers and the order to assemble';
  if (name === 'fabrication.json') return 'parts, sizes and checks';
  if (name === 'workshop.json') return 'parts, loads, strength checks and bolts';
  if (name === 'cut_list.csv') return 'every part: stock, length, width, holes';
  if (name === 'bill_of_materials.csv') return 'stock, bolts, washers, spacers and springs to buy';
  /** @type {Record<string, string>} */
  const kinds = { csv: 'a table', dxf: 'outlines for CAD or cutting', svg: 'a drawing', json: 'data', pdf: 'a sheet to print' };
  return kinds[(name.split('.').pop() ?? '').toLowerCase()] || '';
}

/**
 * The value at a dotted `path` (`bed.width`) of nested settings.
 * @param {PrintSettings} obj
 * @param {string} path
 * @returns {unknown}
 */
const valueAt = (obj, path) => path.split('.').reduce((/** @type {any} */ o, k) => o?.[k], obj);

/**
 * Sets the value at a dotted `path` (`bed.width`) of nested settings.
 * @param {PrintSettings} obj
 * @param {string} path
 * @param {unknown} value
 */
function setAt(obj, path, value) {
  const keys = path.split('.');
  const last = keys.pop() ?? '';
  /** @type {any} */
  let o = obj;
  for (const k of keys) o = o[k] ??= {};
  o[last] = value;
}

/** @type {(n: number) => string} */
const kilobytes = (n) => (n < 1e6 ? `${Math.max(1, Math.round(n / 1000))} kB` : `${(n / 1e6).toFixed(1)} MB`);
/** @type {(n: number, one: string, many?: string) => string} */
const plural = (n, one, many = `${one}s`) => `${n} ${n === 1 ? one : many}`;

/**
 * What went wrong, in plain words: a bad print setting by its label in the panel, anything else as
 * the server says it (the server's messages already say what to change).
 * @param {{message: string, issues?: Issue[]}} e
 */
function problems(e) {
  const settings = (e.issues || []).filter((i) => i.field.startsWith('settings'));
  if (!settings.length) return [e.message];
  return settings.map((i) => {
    const path = i.field.replace(/^settings\.?/, '');
    const named = FIELDS.find(([p]) => p === path)?.[1] || (path === 'faces' ? 'Links on' : null);
    const label = named || (path ? path.replace(/[_.]/g, ' ').replace(/^./, (c) => c.toUpperCase()) : 'Print settings');
    return `${label}: ${i.message}`;
  });
}

/**
 * The print settings a saved form asks for: the defaults, changed by the fields filled in.
 * @param {PrintForm} print
 * @returns {PrintSettings}
 */
function settingsOf(print) {
  /** @type {PrintSettings} */
  const out = { faces: print.faces };
  for (const [path, value] of Object.entries(print.values)) {
    if (FIELDS.some(([p]) => p === path) && Number.isFinite(value)) setAt(out, path, value);
  }
  return out;
}

/** The print settings last saved in the panel: designs are asked to be printable with them. */
export function savedPrintSettings() {
  return settingsOf(loadSaved());
}

/**
 * The print settings panel as last saved (empty: the defaults).
 * @returns {PrintForm}
 */
function loadSaved() {
  try {
    const saved = JSON.parse(localStorage.getItem(SAVED) || 'null');
    if (saved && typeof saved.values === 'object') return { values: saved.values, faces: saved.faces || 'auto', springs: !!saved.springs };
  } catch {
    // Unavailable storage: start from the defaults.
  }
  return { values: {}, faces: 'auto' };
}

export class Fabricator {
  /**
   * `els`: the stage's 3D view (`view`, its `canvas`, `legend`) and the player's 3D toggle (`toggle`).
   * `results` is the Results object whose design is fabricated.
   * @param {Store} store
   * @param {Results} results
   * @param {{view: HTMLElement, canvas: HTMLCanvasElement, legend: HTMLElement, toggle: HTMLElement}} els
   */
  constructor(store, results, els) {
    this.store = store;
    this.results = results;
    this.els = els;
    this.print = loadSaved();
    /** @type {PrintSettings | null} the server's print settings, for the fields' placeholders */
    this.defaults = null;
    this.loadingDefaults = false;
    /** @type {Job | null} */
    this.job = null;
    /** @type {Made | null} */
    this.made = null;
    /** @type {Failed | null} */
    this.error = null;
    this.settingsOpen = false;
    this.show3d = false;
    this.shown = false;
    this.t = 0;
    /** @type {Preview3D | null} */
    this.preview = null;
    els.toggle.addEventListener('click', () => this.setShow3d(!this.show3d));
  }

  /**
   * How the design shown is to be built (the scene it was designed for says), read.
   * @returns {Build}
   */
  build() {
    const scene = this.results.result?.scene || this.store.scene;
    return parseBuild(scene.build ?? DEFAULT_BUILD) || { kind: 'model', scale: 'auto' };
  }

  /**
   * True when `x` (the parts made, an error) belongs to the design shown.
   * @param {MadeFor | null} x
   */
  isFor(x) {
    const r = this.results.result;
    return !!x && !!r && x.design === r.design && x.which === r.which;
  }

  /** The settings to send: the defaults, changed by the fields filled in. */
  settings() {
    return settingsOf(this.print);
  }

  /**
   * Print settings from a project file, kept as if typed here.
   * @param {PrintForm} print
   */
  usePrint(print) {
    this.print = { values: { ...print.values }, faces: typeof print.faces === 'string' ? print.faces : 'auto' };
    if ('springs' in print) this.print.springs = !!print.springs;
    this.saveSettings();
  }

  saveSettings() {
    try {
      localStorage.setItem(SAVED, JSON.stringify(this.print));
    } catch {
      // Private mode: the settings last until the page is closed.
    }
  }

  /** The Make parts button: asks the server for the parts of the design shown. */
  async run() {
    const r = this.results.result;
    if (this.job || !r?.design) return;
    /** @type {MadeFor} */
    const target = { design: r.design, which: r.which };
    const job = { controller: new AbortController(), started: performance.now(), timer: setInterval(() => this.tick(), 500) };
    this.job = job;
    this.error = null;
    this.made = null;
    this.store.changed('result');
    try {
      const springs = !!this.print.springs;
      const answer = await api.fabricate(r.scene, r.design, this.settings(), r.which, job.controller.signal, springs);
      // Parts for a design no longer shown (another scene opened, another design made) are dropped.
      if (!this.isFor(target)) return;
      this.made = { ...target, answer };
      const report = answer.report?.linkwright === 'fabrication/1' ? answer.report : null;
      if (answer.preview) this.show(answer.preview);
      const turn = this.preview?.available && answer.preview ? '; drag the 3D view to turn it' : '';
      const made = report?.totals && report.plates
        ? `Parts made: ${plural(report.totals.parts, 'part')} on ${plural(report.plates.length, 'print bed')}.`
        : `Made ${plural((answer.files || []).length, 'file')}.`;
      this.store.hint(`${made} Download them in the Result tab${turn}.`);
    } catch (e) {
      if (!this.isFor(target)) {
        // Not for the design shown any more: nothing to say about it.
      } else if (api.isAbort(e)) {
        this.store.hint('Making the parts was cancelled.');
      } else {
        const failure = api.errorOf(e);
        const error = { ...target, problems: problems(failure), fields: failure.issues.map((i) => i.field) };
        this.error = error;
        this.settingsOpen ||= failure.issues.some((i) => i.field.startsWith('settings'));
        this.store.hint(`Cannot make the ${this.build().kind === 'full' ? 'workshop files' : 'parts'}: ${error.problems[0]}`);
      }
    } finally {
      clearInterval(job.timer);
      this.job = null;
      this.store.changed('result');
    }
  }

  cancel() {
    this.job?.controller.abort();
  }

  /** Another scene was opened: stops the parts being made and forgets those made. */
  forget() {
    this.cancel();
    this.made = null;
    this.error = null;
    this.show3d = false;
  }

  /** Updates the seconds shown while the job runs. */
  tick() {
    const out = document.getElementById('fab-elapsed');
    if (out && this.job) out.textContent = `${Math.round((performance.now() - this.job.started) / 1000)} s`;
  }

  /**
   * Loads the 3D preview and shows it in place of the drawing (when the browser can draw it).
   * @param {Preview} preview
   */
  show(preview) {
    if (!this.preview) {
      this.preview = new Preview3D(this.els.canvas);
      this.preview.onLost = () => this.setShow3d(false);
    }
    if (!this.preview.available) return;
    const kinds = new Set(preview.parts.map(partKind));
    if (preview.springs?.length) kinds.add('spring');
    this.els.legend.replaceChildren(...Object.entries(ROLE_COLOURS).filter(([kind]) => kinds.has(kind))
      .map(([, [colour, label]]) => html('span', {}, [html('i', { style: `background:${colour}` }), label])));
    this.preview.load(preview);
    this.preview.setFraction(this.t);
    this.setShow3d(true);
  }

  /**
   * Shows the parts in 3D in place of the drawing, or the drawing again.
   * @param {boolean} on
   */
  setShow3d(on) {
    this.show3d = on;
    this.results.sync();
  }

  /**
   * Keeps the 3D view and its toggle in step with the result shown (called on every change).
   * @param {boolean} resultShown
   */
  sync(resultShown) {
    const preview = this.preview;
    const can = resultShown && this.isFor(this.made) && !!this.made?.answer.preview && !!preview?.available;
    const shown = can && this.show3d;
    this.els.toggle.hidden = !can;
    this.els.toggle.setAttribute('aria-pressed', String(shown));
    this.els.view.hidden = !shown;
    if (shown && !this.shown) preview?.request();
    this.shown = shown;
  }

  /**
   * The animation moved to fraction `t` of the motion.
   * @param {number} t
   */
  frame(t) {
    this.t = t;
    if (this.shown) this.preview?.setFraction(t);
  }

  /**
   * The fabrication part of the Result tab.
   * @param {HTMLElement} host
   */
  render(host) {
    if (!this.defaults && !this.loadingDefaults) {
      this.loadingDefaults = true;
      api.printDefaults().then((d) => { this.defaults = d; this.store.changed('result'); }).catch(() => {});
    }
    const full = this.build().kind === 'full';
    host.append(html('h3', { id: 'fab-heading', text: full ? 'Make it: full size' : 'Make it: 3D-printable parts' }));
    host.append(html('p', { class: 'note', text: full
      ? `${describe(buildWord(this.build()))}: the files a workshop needs to build it at its real size.`
      : 'Parts for a desktop 3D printer that snap together on pins, without screws or glue.' }));
    const error = this.isFor(this.error) ? this.error : null;
    // The print settings shape printed parts only; a full-size build's stock and bolts follow from its loads.
    if (!full) host.append(this.settingsForm(error));
    if (this.job) {
      host.append(html('div', { class: 'busy', role: 'status' }, [
        html('div', { class: 'bar indeterminate' }, [html('div')]),
        html('p', {}, [full ? BUSY_TEXT_FULL : BUSY_TEXT, ' ', html('span', { id: 'fab-elapsed', text: '0 s' })]),
        html('button', { id: 'btn-fab-cancel', text: 'Cancel', onclick: () => this.cancel() }),
      ]));
    } else {
      const again = this.isFor(this.made);
      const what = full ? 'the workshop files' : 'the parts';
      host.append(html('div', { class: 'inline' }, [
        html('button', {
          id: 'btn-fabricate', class: 'primary', text: again ? `Make ${what} again` : `⚙ Make ${what}`,
          title: full ? 'Ask for what a workshop needs to build this linkage at full size'
            : 'Build printable parts for this linkage with the print settings above',
          onclick: () => this.run(),
        }),
        html('label', { class: 'check', title: full ? 'Search the stock extension springs that balance the object and list them to buy'
          : 'Search the extension springs that balance the printed parts and give the parts hooks for them' }, [
          html('input', {
            type: 'checkbox', id: 'fab-springs', checked: !!this.print.springs,
            onchange: (e) => { this.print.springs = e.currentTarget.checked; this.saveSettings(); },
          }),
          full ? ' Counterbalance springs' : ' Hooks for counterbalance springs',
        ]),
      ]));
    }
    if (error) {
      host.append(html('div', { class: 'callout error fab-error' }, [
        html('b', { text: `Cannot make ${full ? 'the workshop files' : 'the parts'}` }),
        ...error.problems.map((text) => html('p', { text })),
      ]));
    }
    if (this.made && this.isFor(this.made) && !this.job) {
      if (this.preview && !this.preview.available) {
        host.append(html('p', { class: 'callout warn', text: 'This browser cannot show the parts in 3D (WebGL 2 is off or missing). '
          + 'The files are complete: open assembly.3mf in a slicer or a 3D viewer to see them assembled.' }));
      }
      host.append(...this.summary(this.made.answer));
    }
  }

  /**
   * The print settings, folded away until wanted; empty fields keep their defaults; the fields
   * `error` names are marked.
   * @param {Failed | null} error
   */
  settingsForm(error) {
    const bad = new Set(error?.fields || []);
    const fields = FIELDS.map(([path, label, help]) => {
      const value = this.print.values[path];
      const invalid = bad.has(`settings.${path}`) || (path === 'bed.width' && bad.has('settings.bed'));
      const input = html('input', {
        type: 'number', step: 'any', min: 0, 'data-key': `print-${path}`, 'aria-label': `${label} (mm)`,
        value: value === undefined ? '' : String(value),
        placeholder: this.defaults ? String(valueAt(this.defaults, path)) : '',
        class: invalid ? 'invalid' : null, 'aria-invalid': invalid ? 'true' : null,
        onchange: (e) => {
          const v = Number(e.currentTarget.value);
          if (e.currentTarget.value === '' || !Number.isFinite(v)) delete this.print.values[path];
          else this.print.values[path] = v;
          this.saveSettings();
        },
      });
      return html('div', { class: 'field' }, [html('label', { text: label }), input, html('span', { class: 'unit', text: 'mm' }),
        help ? html('small', { text: help }) : null]);
    });
    const faces = html('select', {
      'data-key': 'print-faces', 'aria-label': 'Faces',
      class: bad.has('settings.faces') ? 'invalid' : null,
      onchange: (e) => { this.print.faces = e.currentTarget.value; this.saveSettings(); },
    }, FACES.map(([v, t]) => html('option', { value: v, text: t, selected: this.print.faces === v })));
    const details = html('details', { class: 'print-settings', open: this.settingsOpen }, [
      html('summary', { text: 'Print settings' }),
      ...fields,
      html('div', { class: 'field' }, [html('label', { text: 'Links on' }), faces,
        html('small', { text: 'which faces of the bodies may carry links: automatic uses the front, and both when the links would collide' })]),
      html('button', {
        class: 'small', text: 'Reset to defaults',
        onclick: () => { this.print = { values: {}, faces: 'auto' }; this.saveSettings(); this.store.changed('result'); },
      }),
    ]);
    details.addEventListener('toggle', () => { this.settingsOpen = details.open; });
    return details;
  }

  /** What was made: how it is built, warnings, the numbers, the downloads and how to put it together.
   * Every part of the report is shown when the server sends it (a full-size build's report has other
   * parts than a printed model's).
   * @param {Fabrication} answer
   * @returns {Nodes}
   */
  summary(answer) {
    const report = answer.report;
    /** @type {Nodes} */
    const out = [];
    /** @type {(title: string, text: string, ...more: Node[]) => void} */
    const warn = (title, text, ...more) => {
      out.push(html('div', { class: 'callout warn' }, [html('b', { text: title }), html('p', { text }), ...more]));
    };
    // The scale the parts were made at, as the report says it.
    const build = this.build();
    const scale = report.linkwright === 'fabrication/1' ? report.scale : undefined;
    const made = typeof scale === 'string' && report.linkwright === 'fabrication/1'
      ? describe(`model:${scale}`, { modelMm: report.model_mm })
      : build.kind === 'full' ? describe(buildWord(build)) : null;
    if (made) out.push(html('p', { class: 'fab-scale', 'data-scale': scale ?? buildWord(build), text: made }));
    if (report.linkwright === 'workshop/1') return [...out, ...this.workshop(answer, report)];
    if (answer.used > 0 && this.made?.which !== answer.used - 1) {
      warn(`These are the parts of alternative ${answer.used}`,
        'The linkage shown cannot be printed with these settings (its parts would collide or not fit), so its first alternative that can is used.',
        html('button', {
          text: `Show alternative ${answer.used}`,
          onclick: () => {
            if (this.made) this.made.which = answer.used - 1;
            this.results.select(answer.used - 1);
          },
        }));
    }
    if (report.oversized?.length) {
      const names = report.oversized.map((o) => `${o.name} (${o.footprint_mm.map((v) => v.toFixed(0)).join(' × ')} mm)`);
      const side = Math.max(...report.oversized.map((o) => o.square_bed_mm));
      const scale = Math.min(...report.oversized.map((o) => o.max_scale));
      warn('Too large for the bed', `${names.join(', ')} ${names.length === 1 ? 'does' : 'do'} not fit on the bed in any direction: print on a bed of at least ${side.toFixed(0)} mm square (Bed width and depth above), or draw the object smaller (at most ${scale.toFixed(2)} of its size).`);
    }
    if (answer.checks_ok === false && report.checks) {
      const c = report.checks;
      warn('Some checks failed', Object.values(c).filter(Array.isArray).flat().join('; '));
    }
    /** @type {[string, string][]} */
    const rows = [];
    const parts = report.parts || [];
    /** @type {(role: string) => number} */
    const count = (role) => parts.filter((p) => p.role === role).length;
    // Bodies printed in halves or cut to fit the bed are several pieces of one body.
    const bodies = (this.results.result?.scene || this.store.scene).moving_bodies.length;
    const pieces = count('body') === bodies ? plural(bodies, 'moving body', 'moving bodies')
      : `${plural(count('body'), 'piece')} of ${plural(bodies, 'moving body', 'moving bodies')}`;
    const kinds = /** @type {[number, string][]} */ ([
      [count('link') + count('guide'), 'link'], [count('connector'), 'connector'], [count('spring_bracket'), 'spring bracket'],
    ]).filter(([n]) => n > 0).map(([n, one]) => plural(n, one));
    if (count('body')) kinds.push(pieces);
    if (count('ground')) kinds.push(plural(count('ground'), 'fixed piece'));
    if (report.totals) rows.push(['Parts', kinds.length ? `${report.totals.parts} (${kinds.join(', ')})` : String(report.totals.parts)]);
    const layers = report.layers;
    if (layers) rows.push(['Layers of links', layers.back ? `${layers.front} on the front face, ${layers.back} on the back` : String(layers.count)]);
    const s = report.settings;
    if (report.plates && s?.bed) rows.push(['Print beds', `${report.plates.length} of ${s.bed.width} × ${s.bed.depth} mm`]);
    const volume = report.totals?.volume_mm3, mass = report.totals?.mass_g;
    if (typeof volume === 'number' && Number.isFinite(volume)) rows.push(['Print volume', `${(volume / 1000).toFixed(1)} cm³`]);
    if (typeof mass === 'number' && Number.isFinite(mass) && s) {
      rows.push(['Mass (estimate)', `${mass.toFixed(0)} g at ${Math.round(s.fill_fraction * 100)}% fill`]);
    }
    if (rows.length) {
      out.push(html('table', { class: 'metrics fab-summary' },
        rows.map(([k, v]) => html('tr', {}, [html('th', { text: k }), html('td', { text: v })]))));
    }
    if (answer.balance) out.push(...this.springs(answer, answer.balance));
    out.push(...this.downloads(answer));
    if (report.assembly?.length) {
      // The engine's steps name a bracket put in place, not what it goes on: the app adds it.
      const brackets = bracketMounts(answer, this.naming());
      out.push(html('h3', { text: 'Putting it together' }));
      out.push(html('ol', { class: 'steps' }, report.assembly.map((step) => html('li', { text: withMounts(step, brackets) }))));
    }
    return out;
  }

  /**
   * A full-size build: what to cut from which stock, the bolts, what the builder should know, the
   * springs to buy, the files and the steps.
   * @param {Fabrication} answer
   * @param {WorkshopReport} report  its report
   * @returns {Nodes}
   */
  workshop(answer, report) {
    /** @type {Nodes} */
    const out = [];
    if (report.notes?.length) {
      out.push(html('div', { class: 'callout warn workshop-notes' }, [html('b', { text: 'Before you build' }),
        html('ul', {}, report.notes.map((note) => html('li', { text: note })))]));
    }
    const links = report.links || [];
    const stocks = [...new Set(links.map((l) => l.thickness_mm))].sort((a, b) => a - b);
    const bolts = (report.bolts || []).reduce((n, b) => n + b.count, 0);
    const mass = links.reduce((m, l) => m + l.mass_kg, 0);
    const rows = [
      ['Parts to cut', `${links.length}, from ${stocks.map((t) => `${t} mm`).join(', ')} ${report.material}`],
      ['Bolts', `${bolts} (${report.bolt?.size} at the joints)`],
      ['Layers of links', String((report.layers || []).length)],
      ['Links’ mass', `${mass.toFixed(mass < 10 ? 1 : 0)} kg`],
      ['Crank holds up to', `${report.peak_torque_nm.toFixed(1)} N·m`],
    ];
    out.push(html('table', { class: 'metrics fab-summary' },
      rows.map(([k, v]) => html('tr', {}, [html('th', { text: k }), html('td', { text: v })]))));
    if (answer.balance) {
      out.push(html('h3', { text: 'Counterbalance springs' }),
        html('p', { class: 'note', text: 'Stock springs, on the bill of materials; the assembly sheet says where each hangs.' }),
        springList(answer.balance, (this.results.result?.scene || this.store.scene)?.units || 'mm', this.naming()));
    }
    out.push(...this.downloads(answer));
    if (report.steps?.length) {
      out.push(html('h3', { text: 'Putting it together' }));
      out.push(html('ol', { class: 'steps' }, report.steps.map((step) => html('li', { text: step }))));
    }
    return out;
  }

  /**
   * The springs the parts are hooked for: what to buy, and where each hangs.
   * @param {Fabrication} answer
   * @param {import('./api.js').Balance} balance  its springs
   * @returns {Nodes}
   */
  springs(answer, balance) {
    const units = (this.results.result?.scene || this.store.scene)?.units || 'mm';
    /** @type {Nodes} */
    const out = [html('h3', { text: 'Counterbalance springs' })];
    if (balance.springs.length) {
      out.push(html('p', { class: 'note', text: `They lower the crank's peak torque by ${springCut(balance)}%. `
        + 'Each hangs beyond the links, on hooks printed on the parts (see Putting it together).' }));
    }
    const hooks = answer.report.linkwright === 'fabrication/1' ? answer.report.springs : null;
    out.push(springList(balance, units, this.naming(), hooks, bracketMounts(answer, this.naming())));
    return out;
  }

  /** What the springs' words name the parts by: the person's names in the scene, and the mechanism
   * shown (whose part names the engine's answer uses).
   * @returns {Naming}
   */
  naming() {
    return { scene: this.store.scene, mechanism: this.results.result?.mechanism ?? null };
  }

  /** The zip of everything, then every file by what it is for (the files this app does not group
   * last, as the server lists them).
   * @param {Fabrication} answer
   * @returns {Nodes}
   */
  downloads(answer) {
    /** @type {Nodes} */
    const out = [html('h3', { text: 'Downloads' })];
    if (answer.zip) {
      out.push(html('div', { class: 'inline' }, [this.link(answer.zip, `⬇ Everything (.zip, ${kilobytes(answer.zip.bytes)})`, 'button primary')]));
    }
    const printed = answer.report.linkwright === 'fabrication/1' ? answer.report.parts || [] : [];
    const parts = new Map(printed.filter((p) => p.file).map((p) => [p.file, p]));
    const meshes = new Map((answer.preview?.parts || []).map((p) => [p.name, p]));
    const brackets = bracketMounts(answer, this.naming());
    /** @type {(file: FabricationFile) => HTMLElement} */
    const describe = (file) => {
      const p = parts.get(file.name);
      if (!p) return html('small', { text: purpose(file.name) });
      const size = p.size_mm.map((v) => v.toFixed(0)).join(' × ');
      const mount = brackets.has(p.name) ? `, mounted on ${brackets.get(p.name)}` : '';
      return html('small', {}, [html('i', { class: 'swatch', style: `background:${partColour(meshes.get(p.name) || p)}` }),
        ` ${p.role.replace('_', ' ')}${mount}, ${size} mm, ${p.mass_g.toFixed(1)} g`]);
    };
    const files = answer.files || [];
    /** @type {[string, (name: string) => boolean][]} */
    const groups = [...FILE_GROUPS, ['Other files', (name) => !FILE_GROUPS.some(([, test]) => test(name))]];
    for (const [title, test] of groups) {
      const listed = files.filter((f) => test(f.name));
      if (listed.length) out.push(html('h4', { text: title }), html('ul', { class: 'files' }, listed.map((f) => html('li', {}, [this.link(f), describe(f)]))));
    }
    return out;
  }

  /** A download link for a file of the answer; a part's file is saved under the scene's name too
   * (`garbage_truck_crank.stl`), so that parts of several objects do not overwrite each other.
   * @param {FabricationFile} file
   * @param {string} [text]
   * @param {string} [cls]
   */
  link(file, text = file.name.split('/').pop(), cls = 'file') {
    const base = file.name.split('/').pop() ?? file.name;
    const scene = (this.results.result?.scene?.name || '').replace(/[^\w.-]+/g, '_');
    const saved = file.name.startsWith('parts/') && scene ? `${scene}_${base}` : base;
    return html('a', {
      class: cls, href: file.url, download: saved, 'data-file': file.name, text,
      title: Number.isFinite(file.bytes) ? `${file.name} · ${kilobytes(file.bytes)}` : file.name,
    });
  }
}
