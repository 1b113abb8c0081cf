// @ts-check
// The Result tab: why a design failed (each problem where it is on screen), or the design shown: its
// build, its check and pose errors, its metrics, its joints to type or pin, the alternatives to pick,
// the downloads, the parts to make (fabricate.js) and the analysis of its motion (result-plots.js).

import { fmt, pathBadge, poseErrors, poseTable, reachBadge } from './accuracy.js';
import { DEFAULT_BUILD, describe, describeRecord, parseBuild, suggestedScale } from './build.js';
import { bodyColour } from './canvas.js';
import { screenField, screenWords } from './fields.js';
import { bounds, placed } from './geom.js';
import { ENGINE_SETTINGS, poseCount, toFile } from './scene.js';
import { clear, html, points, svg } from './svg.js';

/**
 * @typedef {import('./geom.js').Point} Point
 * @typedef {import('./scene.js').Scene} Scene
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./store.js').Result} Result
 * @typedef {import('./api.js').Design} Design
 * @typedef {import('./api.js').DesignFound} DesignFound
 * @typedef {import('./api.js').BuildRecord} BuildRecord
 * @typedef {import('./api.js').Mechanism} Mechanism
 * @typedef {import('./api.js').Metrics} Metrics
 * @typedef {import('./api.js').Motion} Motion
 * @typedef {import('./api.js').Issue} Issue
 * @typedef {import('./result.js').Results} Results
 */
/**
 * @template {Element} E
 * @typedef {import('./svg.js').On<E>} On
 */

/**
 * What a person calls a design's linkage: the engine writes it (older files name the family only).
 * @param {Mechanism | null | undefined} m
 */
export function mechanismName(m) {
  if (!m) return '';
  return m.label || m.type.replace('_', '-');
}

export class ResultTab {
  /**
   * The Result tab of the design `store` shows; `results` runs designs and shows mechanisms.
   * @param {Store} store
   * @param {Results} results
   */
  constructor(store, results) {
    this.store = store;
    this.results = results;
  }

  /**
   * Draws the Result tab into `host`.
   * @param {HTMLElement} host
   */
  render(host) {
    clear(host);
    const r = this.store.result;
    const failed = this.results.error;
    // An error speaks of the scene it came from: after an edit or an undo it may not hold.
    const error = failed && (!failed.scene || failed.scene === JSON.stringify(toFile(this.store.scene))) ? failed : null;
    if (error) {
      // Each problem once, where it is on screen; clicking one that names a shape selects it.
      /** @type {(i: Issue) => HTMLLIElement} */
      const item = (i) => {
        const at = screenField(i.field, this.store.scene);
        const selection = at.selection;
        const select = selection ? () => this.store.setUi({ selection, pose: at.pose ?? this.store.ui.pose, tab: 'object' }) : null;
        return html('li', { class: i.severity ?? null }, [
          select ? html('a', { href: '#', text: at.text, onclick: (e) => { e.preventDefault(); select(); } }) : html('b', { text: at.text }),
          `: ${screenWords(i.message, this.store.scene, this.store.families)}`,
        ]);
      };
      host.append(html('div', { class: 'callout error' }, [
        html('b', { text: 'Cannot design this yet' }),
        error.issues.length ? html('ul', {}, error.issues.map(item)) : html('p', { text: error.message }),
      ]));
    }
    if (!r) {
      if (!error) host.append(html('p', { class: 'empty', text: 'No design yet. Draw a fixed body, a moving body and its poses, then press “Design linkage”.' }));
      return;
    }
    const d = r.design;
    // While a live redesign follows a dragged pose, the next design is on its way: no warning.
    const live = this.results.live;
    const following = this.store.ui.live && (live.liveBusy || live.heldPose != null);
    if (!this.results.fresh() && !following) {
      host.append(html('div', { class: 'callout warn', 'data-stale': '', text: 'The drawing changed since this design. Press “Design linkage” to update it.' }));
    }
    if (d.status !== 'ok') {
      host.append(html('div', { class: 'callout warn' }, [
        html('b', { text: 'No linkage found' }),
        html('p', { class: 'reason', text: screenWords(d.reason || '', this.store.scene, this.store.families) }),
        // When the drawing's size does not suit the build, the reason says so first.
        /does not suit the build/.test(d.reason || '') ? this.buildActions(d.build, d.reason) : null,
      ]));
      host.append(...this.buildLines(d));
      host.append(statsLine(d));
      return;
    }
    const m = r.metrics || d.metrics;
    const mechanism = r.mechanism || d.mechanism;
    host.append(html('h3', { text: r.which === null ? `Best design: ${mechanismName(d.mechanism)}` : `Alternative ${r.which + 1}: ${mechanismName(r.mechanism)}` }));
    host.append(...this.buildLines(d));
    // The check says whether the linkage is sound; the pose errors (a path's distance, for a path
    // design, and its poses' errors when it has more than where it starts) say how closely it does
    // the job.
    const path = m.path_error;
    const errors = path && poseCount(r.scene) < 2 ? null : poseErrors(m, r.analysis, r.scene);
    if (r.verified && !r.verified.ok) {
      host.append(html('div', { class: 'callout error' }, r.verified.violations.map((v) => html('p', { text: `${v.constraint}: ${v.message}` }))));
    } else if (r.verified) {
      host.append(path
        ? pathBadge(path, r.scene)
        : errors
        ? reachBadge(errors, r.scene)
        : html('p', { class: 'badge verified', text: 'Re-simulated independently: no hard constraint is violated (the poses are not measured yet)' }));
    }
    if (errors) host.append(poseTable(errors, r.scene));
    host.append(html('table', { class: 'metrics' }, /** @type {[string, string][]} */ ([
      ['Cost (lower is better)', m.cost.toFixed(3)],
      ['Accuracy (mean squared error)', m.accuracy.toPrecision(3)],
      ['Smoothness (path/chord)', m.smoothness.toFixed(3)],
      ['Distance from region', m.location.toFixed(2)],
      ['Mean link length', m.size.toFixed(1)],
      ['Worst transmission angle', transmissionWords(m, r.motion || d.motion, r.scene)],
    ]).map(([k, v]) => html('tr', {}, [html('th', { text: k }), html('td', { text: v })]))));
    host.append(statsLine(d));
    for (const w of r.warnings || []) host.append(html('p', { class: 'note', text: `Note: ${w.field}: ${w.message}` }));
    host.append(html('h3', { text: 'Joints' }), this.jointTable(mechanism));

    /** @type {(number | null)[]} */
    const options = [null, ...d.alternatives.map((_, i) => i)];
    if (options.length > 1) {
      host.append(html('h3', { text: 'Alternatives' }));
      host.append(html('div', { class: 'thumbs' }, options.map((w) => this.thumbnail(r, d, w))));
    }
    host.append(html('h3', { text: 'Downloads' }));
    host.append(html('div', { class: 'inline' }, [
      html('button', { text: 'Design JSON', title: 'the design/1 file', onclick: () => this.results.downloads.download('json') }),
      html('button', { text: 'Animation SVG', title: 'open it in a browser to watch the motion', onclick: () => this.results.downloads.download('animation') }),
      html('button', { text: 'Design sheet SVG', onclick: () => this.results.downloads.download('design') }),
      html('button', { text: 'Motion GIF', 'data-export': 'gif', title: 'the motion as shown, an animated picture', onclick: () => this.results.downloads.exportMotion('gif') }),
      html('button', { text: 'Motion video', 'data-export': 'webm', title: 'the motion as shown, a WebM video', onclick: () => this.results.downloads.exportMotion('webm') }),
    ]));
    this.results.fab?.render(host);
    if (r.analysis) {
      this.results.plots.render(host, r, r.analysis);
      this.results.player.drawFrame();
    }
  }

  /**
   * How the design is built, from its file's `build` record: “Printed model at 1:10 (auto), 214 × 180
   * mm” or “Full size, plywood”; when it cannot be built so, a warning with the engine's reason and
   * buttons that change the build and design again; when the scene now asks for another build, a note.
   * @param {Design} d
   * @returns {HTMLElement[]}
   */
  buildLines(d) {
    const record = d.build;
    const text = describeRecord(record);
    if (!record || !text) return [];
    /** @type {HTMLElement[]} */
    const out = [html('p', { class: 'build-line', 'data-build': record.checked, text })];
    if (d.status === 'ok' && record.buildable === false) {
      const model = parseBuild(record.checked);
      const scale = model?.kind === 'model' ? model.scale : record.checked;
      const reason = (record.reason || '').replace(/^./, (c) => c.toUpperCase());
      out.push(html('div', { class: 'callout warn', 'data-unbuildable': 'true', role: 'status' }, [
        html('b', { text: `This linkage cannot be printed at ${scale}` }),
        reason ? html('p', { text: /[.!?]$/.test(reason) ? reason : `${reason}.` }) : null,
        this.buildActions(record, record.reason),
      ]));
    }
    const now = parseBuild(this.store.scene.build ?? DEFAULT_BUILD);
    const asked = parseBuild(record.asked);
    if (now && asked && JSON.stringify(now) !== JSON.stringify(asked)) {
      out.push(html('p', { class: 'note', 'data-build-changed': 'true',
        text: `Settings › Build is now “${describe(this.store.scene.build ?? DEFAULT_BUILD)}”: press “Design linkage” to design for it.` }));
    }
    return out;
  }

  /**
   * Buttons that set the build and design again: the scale the engine's reason suggests (when it
   * names one), the automatic scale (when another was asked for) and full size.
   * @param {BuildRecord | undefined} record
   * @param {string | undefined} reason
   */
  buildActions(record, reason) {
    const asked = parseBuild(record?.asked ?? DEFAULT_BUILD);
    const checked = parseBuild(record?.checked ?? '');
    const suggested = suggestedScale(reason);
    /** @type {[string, string, string][]} */
    const choices = [];
    if (suggested && suggested !== (checked?.kind === 'model' ? checked.scale : undefined)) choices.push(['scale', `model:${suggested}`, `Print at ${suggested} and redesign`]);
    if (asked?.kind === 'model' && asked.scale !== 'auto') choices.push(['auto', 'model:auto', 'Auto scale and redesign']);
    if (asked?.kind !== 'full') choices.push(['full', 'full:plywood', 'Build it full size and redesign']);
    return html('div', { class: 'inline actions' }, choices.map(([action, word, text]) => html('button', {
      text, 'data-build-action': action, title: `Settings › Build: ${describe(word)}; then design again`,
      onclick: () => this.rebuildAs(word),
    })));
  }

  /**
   * Sets the scene's build (one undo step, as in Settings) and designs again.
   * @param {string} word
   */
  rebuildAs(word) {
    if (this.results.controller) return;
    this.store.edit(`build ${word}`, (s) => { s.build = word; });
    this.store.hint(`Build: ${describe(word)}. Designing again…`);
    this.results.run();
  }

  /**
   * The joints of the mechanism shown at the first pose: type a place to move one (as a drag does),
   * tick Pin to keep it there in the next design.
   * @param {Mechanism} mechanism
   */
  jointTable(mechanism) {
    const units = this.store.scene.units || 'mm';
    const pinned = this.store.scene.pinned_joints || {};
    /** @type {(name: string) => HTMLTableRowElement} */
    const row = (name) => {
      const [x, y] = mechanism.joints[name];
      // Where the joint is now: a move answered since this table was drawn counts (a click may
      // come before the table is drawn again).
      /** @type {() => Point} */
      const now = () => [...(this.store.result?.mechanism || mechanism).joints[name]];
      /** @type {(axis: 0 | 1) => (e: On<HTMLInputElement>) => void} */
      const place = (axis) => (e) => {
        const v = Number(e.currentTarget.value);
        if (e.currentTarget.value.trim() === '' || !Number.isFinite(v)) return;
        const p = now();
        p[axis] = v;
        this.results.joints.placeJoints({ [name]: p });
      };
      /** @type {(e: On<HTMLInputElement>) => void} */
      const pin = (e) => {
        const on = e.currentTarget.checked;
        this.store.edit(`${on ? 'pin' : 'unpin'} joint ${name}`, (s) => {
          const pins = { ...(s.pinned_joints || {}) };
          if (on) pins[name] = now(); else delete pins[name];
          if (Object.keys(pins).length) s.pinned_joints = pins; else delete s.pinned_joints;
        });
        this.store.hint(on
          ? `Joint ${name} is pinned where it is: the next design keeps it there.`
          : `Joint ${name} is free again.`);
      };
      return html('tr', {}, [
        html('th', { text: name }),
        html('td', {}, [html('input', { type: 'number', step: 'any', value: fmt(x), 'data-joint-x': name, 'aria-label': `${name} x (${units})`, onchange: place(0) })]),
        html('td', {}, [html('input', { type: 'number', step: 'any', value: fmt(y), 'data-joint-y': name, 'aria-label': `${name} y (${units})`, onchange: place(1) })]),
        html('td', {}, [html('label', {}, [html('input', { type: 'checkbox', checked: name in pinned, 'data-pin': name, onchange: pin }), ' pin'])]),
      ]);
    };
    return html('table', { class: 'joint-table', title: `Joint places at the first pose, ${units}. Drag a joint on the canvas, or type here.` }, [
      html('tr', {}, [html('th', { text: 'joint' }), html('th', { text: `x (${units})` }), html('th', { text: `y (${units})` }), html('th', { text: '' })]),
      ...Object.keys(mechanism.joints).sort().map(row),
    ]);
  }

  /**
   * A small picture of mechanism `which` of result `r` (its design `d`, a linkage found) at its first
   * pose, to pick it.
   * @param {Result} r
   * @param {DesignFound} d
   * @param {number | null} which
   */
  thumbnail(r, d, which) {
    const m = which === null ? d.mechanism : d.alternatives[which].mechanism;
    const metrics = which === null ? d.metrics : d.alternatives[which].metrics;
    const scene = r.scene;
    const bodies = scene.moving_bodies.map((b) => placed(b.polygon, b.poses[0]));
    const joints = m.joints;
    // Framed on the linkage, with a quarter of its extent around it: next to a large body a small
    // linkage would be a few pixels, and the alternatives would all look alike. The bodies are cut.
    const jb = bounds(Object.values(joints));
    const margin = 0.25 * Math.max(jb.maxX - jb.minX, jb.maxY - jb.minY, 1e-9);
    const bb = { minX: jb.minX - margin, maxX: jb.maxX + margin, minY: jb.minY - margin, maxY: jb.maxY + margin };
    const w = 84, h = 54;
    const k = Math.min(w / (bb.maxX - bb.minX), h / (bb.maxY - bb.minY));
    // Centred both ways.
    const [cx, cy] = [(bb.minX + bb.maxX) / 2, (bb.minY + bb.maxY) / 2];
    /** @type {(p: Point) => Point} */
    const s = (p) => [w / 2 + (p[0] - cx) * k, h / 2 - (p[1] - cy) * k];
    const pic = svg('svg', { viewBox: `0 0 ${w} ${h}`, width: w, height: h });
    for (const b of scene.fixed_bodies) pic.append(svg('polygon', { class: 'fixed', points: points(b.polygon.map(s)) }));
    bodies.forEach((b, i) => pic.append(svg('polygon', { class: 'moving', style: `--c:${bodyColour(i)}`, points: points(b.map(s)) })));
    for (const part of m.parts.filter((p) => p.kind === 'link')) {
      const pts = part.joints.filter((n) => joints[n]).map((n) => s(joints[n]));
      pic.append(svg(pts.length > 2 ? 'polygon' : 'polyline', { class: 'link thin', points: points(pts) }));
    }
    for (const p of Object.values(joints)) {
      const q = s(p);
      pic.append(svg('circle', { class: 'joint', cx: q[0], cy: q[1], r: 2 }));
    }
    const label = which === null ? 'Best' : `#${which + 1}`;
    return html('button', {
      class: r.which === which ? 'thumb selected' : 'thumb',
      title: `${label}: ${mechanismName(m)}, cost ${metrics.cost.toFixed(3)}${worstMiss(metrics, r.scene)}`,
      'data-which': which === null ? 'best' : String(which),
      onclick: async () => {
        await this.results.select(which);
        if (this.store.result?.design !== d || this.store.result.which !== which) return;
        this.results.verify();
        const m = which === null ? d.mechanism : d.alternatives[which].mechanism;
        this.store.hint(`${which === null ? 'Best design' : `Alternative ${which + 1}`}: ${mechanismName(m)}, cost ${metrics.cost.toFixed(2)}.`);
      },
    }, [pic, html('span', { text: `${label} · ${metrics.cost.toFixed(2)}` })]);
  }
}

/**
 * The largest pose miss a design file states for a mechanism (files before it was added do not).
 * @param {Metrics} metrics
 * @param {Scene} scene
 */
function worstMiss(metrics, scene) {
  const w = metrics.worst_pose_error;
  if (!w || !Number.isFinite(w.position) || !Number.isFinite(w.angle_deg)) return '';
  return `, poses missed by at most ${fmt(w.position)} ${scene.units || 'mm'} and ${fmt(Math.abs(w.angle_deg))}°`;
}

/**
 * The worst transmission angle, where along the motion it is, and whether it leaves the comfortable band.
 * @param {Metrics} m
 * @param {Motion} motion
 * @param {Scene} scene
 */
function transmissionWords(m, motion, scene) {
  let text = `${m.min_transmission_deg.toFixed(1)}°`;
  const at = m.min_transmission_crank_deg;
  const span = motion ? motion.crank_end_deg - motion.crank_start_deg : 0;
  if (typeof at === 'number' && Number.isFinite(at) && span !== 0) {
    const share = Math.min(1, Math.max(0, (at - motion.crank_start_deg) / span));
    text += ` at ${Math.round(100 * share)}% of the motion`;
  }
  const comfortable = scene.settings?.comfortable_transmission_deg ?? ENGINE_SETTINGS.comfortable_transmission_deg;
  if (m.min_transmission_deg < comfortable) text += `, under the comfortable ${comfortable}°`;
  return text;
}

/**
 * How the search went: valid samples of all, the time and the seed.
 * @param {Design} d
 */
function statsLine(d) {
  const s = d.stats;
  return html('p', { class: 'note', text: `${s.valid} valid of ${s.samples} samples in ${s.seconds.total.toFixed(1)} s, seed ${s.seed}.` });
}
