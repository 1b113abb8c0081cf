// @ts-check
// The drawing: grid, scene, onion-skinned poses, the designed linkage in motion, selection handles and
// the shape being drawn. Everything is drawn in screen pixels from world coordinates (y up) through
// the viewport, so strokes and handles keep their size at any zoom.

import { poseErrors, fmt } from './accuracy.js';
import { centroid, placed, toWorld } from './geom.js';
import { besideShifts, placeLabels, tagShifts } from './labels.js';
import { clear, points, svg } from './svg.js';

/**
 * @typedef {import('./geom.js').Point} Point
 * @typedef {import('./geom.js').Pose} Pose
 * @typedef {import('./geom.js').Polygon} Polygon
 * @typedef {import('./scene.js').MovingBody} MovingBody
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./viewport.js').Viewport} Viewport
 */

/**
 * The linkage at one moment of the motion, world coordinates: the joints (as the analysis names
 * them), the moving bodies' poses, the crank angle and the counterbalance springs' ends.
 * @typedef {{crank_deg: number, joints: Point[], bodies: Pose[], springs?: SpringAt[]}} FrameAt
 * @typedef {{kind: 'extension' | 'torsion', ends: Point[]}} SpringAt
 * @typedef {{points: Point[], cursor?: Point | null, kind: string, closed: boolean, stroke?: boolean}} DrawingPreview
 *   The shape being drawn: its corners so far (world), where the pointer is, what it will be, and
 *   whether it is closed (a box) or still growing (a polygon).
 * @typedef {{name: string, at: Point, message: string}} RejectedJoint  Where a moved joint was asked
 *   to go when the linkage cannot follow it there, and why.
 */

export const BODY_COLOURS = ['#e67e22', '#2e9e4f', '#8e5cc2', '#a0522d', '#d6489b', '#1aa3b8', '#a6a61e'];
export const PATH_COLOURS = ['#1b9e77', '#d95f02', '#7570b3', '#e7298a', '#66a61e', '#c79a00', '#a6761d', '#555555'];
/** Moving body `b`'s colour. @type {(b: number) => string} */
export const bodyColour = (b) => BODY_COLOURS[b % BODY_COLOURS.length];

/** Pixels from a vertex within which it is grabbed. */
export const GRAB_PX = 9;
/** Distance of the rotate handle beyond the body, pixels. */
const ROTATE_PX = 28;
/** Outlines with more corners than this (curves) get no corner handles. */
const MAX_VERTEX_HANDLES = 16;
/** From the centre of a pose's number to the start of the label beside it, pixels (the number's disc has a radius of 9). */
const TAG_REACH = 13;
/** Width of the rulers along the canvas' top and left edges, pixels. */
const RULER_PX = 18;

/**
 * A length for a label: as many decimals as `resolution` (the smallest step shown) needs, no more.
 * @param {number} value
 * @param {number} [resolution]
 */
export function formatLength(value, resolution = Math.abs(value)) {
  const decimals = Math.max(0, Math.min(4, -Math.floor(Math.log10(Math.abs(resolution) || 1) + 1e-9)));
  const text = (Math.abs(value) < resolution * 1e-6 ? 0 : value).toFixed(decimals);
  return text === '-0' ? '0' : text;
}

/**
 * A length with three significant figures (whole units from 100 up).
 * @param {number} value
 */
export function formatDimension(value) {
  const a = Math.abs(value);
  return value.toFixed(a >= 100 ? 0 : a >= 10 ? 1 : a >= 1 ? 2 : 3);
}

/** The drawing's layers, bottom first. */
const LAYERS = /** @type {const} */ (['grid', 'scene', 'resultStatic', 'resultDynamic', 'dimensions', 'overlay', 'rulers']);

export class Canvas {
  /**
   * Draws into the SVG element `root` what `store` holds, through `viewport`.
   * @param {SVGSVGElement} root
   * @param {Store} store
   * @param {Viewport} viewport
   */
  constructor(root, store, viewport) {
    this.root = root;
    this.store = store;
    this.view = viewport;
    /** @type {DrawingPreview | null} */
    this.preview = null;
    /** @type {Record<typeof LAYERS[number], SVGGElement>} */
    this.layers = /** @type {Record<typeof LAYERS[number], SVGGElement>} */ (
      Object.fromEntries(LAYERS.map((name) => [name, svg('g', { class: `layer-${name}` })])));
    for (const name of LAYERS) root.append(this.layers[name]);
    /** @type {FrameAt | null} the result frame drawn now */
    this.frame = null;
    this.resultShown = false;
    /** @type {RejectedJoint | null} */
    this.rejectedJoint = null;
    /** @type {Map<string, number>} where each label was put last (labels.js) */
    this.labelPlaces = new Map();
  }

  /**
   * The screen pixel of world point `p`.
   * @param {Point} p
   */
  s(p) {
    return this.view.toScreen(p);
  }

  /** Redraws everything. */
  render() {
    this.renderGrid();
    this.renderScene();
    this.renderResultStatic();
    this.drawResultFrame(this.frame);
    this.renderOverlay();
    this.renderRulers();
    this.layoutLabels();
  }

  renderGrid() {
    const g = clear(this.layers.grid);
    if (!this.store.ui.grid) return;
    const v = this.view, step = v.gridStep(), box = v.visible();
    const lines = [];
    const major = step * 5;
    /** @type {(x: number) => string} */
    const kind = (x) => (Math.abs(x) < step / 2 ? 'axis' : Math.abs(x / major - Math.round(x / major)) < 1e-6 ? 'major' : 'minor');
    for (let x = Math.ceil(box.minX / step) * step; x <= box.maxX; x += step) {
      const sx = v.toScreen([x, 0])[0];
      lines.push(svg('line', { x1: sx, y1: 0, x2: sx, y2: v.height, class: `grid-${kind(x)}` }));
    }
    for (let y = Math.ceil(box.minY / step) * step; y <= box.maxY; y += step) {
      const sy = v.toScreen([0, y])[1];
      lines.push(svg('line', { x1: 0, y1: sy, x2: v.width, y2: sy, class: `grid-${kind(y)}` }));
    }
    g.append(...lines);
  }

  /** Rulers along the top and left edges, in the scene's units, and a scale bar: always shown, so the
   * drawing's true size is never in doubt. */
  renderRulers() {
    const g = clear(this.layers.rulers);
    const v = this.view, units = this.store.scene.units || 'mm';
    // Labelled ticks at least 60 px apart (room for a number), minor ticks at a fifth of that.
    const step = v.gridStep(60), minor = step / 5, box = v.visible();
    /** @type {SVGElement[]} */
    const out = [
      svg('rect', { class: 'ruler', x: 0, y: 0, width: v.width, height: RULER_PX }),
      svg('rect', { class: 'ruler', x: 0, y: 0, width: RULER_PX, height: v.height }),
    ];
    for (let x = Math.ceil(box.minX / minor) * minor; x <= box.maxX; x += minor) {
      const sx = v.toScreen([x, 0])[0], labelled = Math.abs(x / step - Math.round(x / step)) < 1e-6;
      if (sx < RULER_PX) continue;
      out.push(svg('line', { class: 'ruler-tick', x1: sx, y1: RULER_PX, x2: sx, y2: RULER_PX - (labelled ? 8 : 4) }));
      if (labelled) out.push(svg('text', { class: 'ruler-label', x: sx + 2, y: 10, text: formatLength(x, step) }));
    }
    for (let y = Math.ceil(box.minY / minor) * minor; y <= box.maxY; y += minor) {
      const sy = v.toScreen([0, y])[1], labelled = Math.abs(y / step - Math.round(y / step)) < 1e-6;
      if (sy < RULER_PX) continue;
      out.push(svg('line', { class: 'ruler-tick', x1: RULER_PX, y1: sy, x2: RULER_PX - (labelled ? 8 : 4), y2: sy }));
      // Written upwards from the tick, so none near the corner.
      if (labelled && sy > RULER_PX + 30) {
        out.push(svg('text', { class: 'ruler-label', x: 10, y: sy - 2, transform: `rotate(-90 10 ${sy - 2})`, text: formatLength(y, step) }));
      }
    }
    // The corner names the unit.
    out.push(svg('rect', { class: 'ruler corner', x: 0, y: 0, width: RULER_PX, height: RULER_PX }));
    out.push(svg('text', { class: 'ruler-units', x: RULER_PX / 2, y: RULER_PX / 2, 'text-anchor': 'middle', dy: '0.35em', text: units }));
    // The scale bar, top right (the player covers the bottom while a design plays).
    const length = v.niceLength(120);
    const px = length * v.k, x1 = v.width - 14, y0 = RULER_PX + 24;
    out.push(svg('g', { class: 'scale-bar', 'data-length': length }, [
      svg('path', { d: `M${x1 - px},${y0 - 5} v5 h${px} v-5` }),
      svg('text', { x: x1 - px / 2, y: y0 - 8, 'text-anchor': 'middle', text: `${formatLength(length, length)} ${units}` }),
    ]));
    g.append(...out);
  }

  /**
   * A polygon of world points, drawn.
   * @param {Polygon} world
   * @param {Record<string, unknown>} attrs
   */
  poly(world, attrs) {
    return svg('polygon', { points: points(world.map((p) => this.s(p))), ...attrs });
  }

  /** True while a fresh design is shown (then poses are all drawn as skins and bodies move). */
  showingResult() {
    return this.resultShown;
  }

  renderScene() {
    const g = clear(this.layers.scene);
    const { scene, ui } = this.store;
    if (scene.linkage_region) {
      g.append(this.poly(scene.linkage_region, { class: 'region', 'data-kind': 'region', 'data-index': 0 }));
    }
    (scene.avoid_regions || []).forEach((r, i) => {
      g.append(this.poly(r, { class: 'avoid', 'data-kind': 'avoid', 'data-index': i }));
    });
    scene.fixed_bodies.forEach((b, i) => {
      g.append(this.poly(b.polygon, { class: 'fixed', 'data-kind': 'fixed', 'data-index': i }));
    });
    // A body's drawn path (path synthesis: its tracer should follow it), under the bodies.
    scene.moving_bodies.forEach((b, i) => {
      const path = b.path;
      if (!path || !Array.isArray(path.points) || path.points.length < 2) return;
      const tag = path.closed ? 'polygon' : 'polyline';
      g.append(svg(tag, { class: 'drawn-path', points: points(path.points.map((p) => this.s(p))), 'data-body': i }));
      // The points the tracer must pass exactly: rings on the path, numbered as the Object tab lists them.
      for (const k of path.exact || []) {
        const p = path.points[k];
        if (!p) continue;
        const [x, y] = this.s(p);
        g.append(svg('circle', { class: 'exact-point', cx: x, cy: y, r: 5, 'data-body': i, 'data-point': k }));
      }
    });
    const result = this.showingResult();
    // Onion skins first, then every body at the current pose on top.
    scene.moving_bodies.forEach((b, i) => {
      b.poses.forEach((pose, p) => {
        if (p === ui.pose && !result) return;
        g.append(this.poly(placed(b.polygon, pose), {
          class: 'skin', style: `--c:${bodyColour(i)}`, 'data-kind': 'moving', 'data-index': i, 'data-pose': p,
        }));
      });
    });
    if (!result) {
      scene.moving_bodies.forEach((b, i) => {
        const pose = b.poses[ui.pose];
        if (!pose) return;
        g.append(this.poly(placed(b.polygon, pose), {
          class: 'moving', style: `--c:${bodyColour(i)}`, 'data-kind': 'moving', 'data-index': i, 'data-pose': ui.pose,
        }));
      });
    }
  }

  /** Joint paths and the slider guide of the shown design. */
  renderResultStatic() {
    const g = clear(this.layers.resultStatic);
    const r = this.store.result;
    if (!this.resultShown || !r?.analysis) return;
    const a = r.analysis;
    const fixed = new Set(a.fixed_joints);
    if (this.store.ui.paths !== false) {
      a.joint_names.forEach((name, j) => {
        if (fixed.has(name)) return;
        const pts = a.frames.map((f) => this.s(f.joints[j]));
        g.append(svg('polyline', { class: 'joint-path', points: points(pts), stroke: PATH_COLOURS[j % PATH_COLOURS.length] }));
      });
    }
    // The curve each path body's tracer traces along the motion.
    this.store.scene.moving_bodies.forEach((b, i) => {
      const tracer = b.path?.tracer;
      if (!tracer) return;
      const traced = a.frames.filter((f) => f.bodies[i]).map((f) => this.s(toWorld(f.bodies[i], tracer)));
      g.append(svg('polyline', { class: 'traced-path', points: points(traced), 'data-body': i }));
    });
    const slider = r.mechanism?.slider;
    if (slider) {
      const d = slider.direction, p = slider.point;
      /** @type {(t: number) => Point} */
      const at = (t) => this.s([p[0] + d[0] * t, p[1] + d[1] * t]);
      const [s0, s1] = slider.stroke;
      const pad = 0.1 * Math.abs(s1 - s0);
      const [a0, a1] = [at(s0 - pad), at(s1 + pad)];
      g.append(svg('line', { class: 'guide', x1: a0[0], y1: a0[1], x2: a1[0], y2: a1[1] }));
    }
  }

  /**
   * The bodies and the linkage at one frame, its labels kept apart; null hides them.
   * @param {FrameAt | null} frame
   */
  renderResultFrame(frame) {
    this.drawResultFrame(frame);
    this.layoutLabels();
  }

  /**
   * The bodies and the linkage at one frame (the labels as they fall).
   * @param {FrameAt | null} frame
   */
  drawResultFrame(frame) {
    this.frame = frame;
    this.renderDimensions(frame);
    const g = clear(this.layers.resultDynamic);
    const r = this.store.result;
    if (!frame || !this.resultShown || !r?.analysis) return;
    const { scene } = this.store;
    const a = r.analysis;
    const index = new Map(a.joint_names.map((n, j) => [n, j]));
    /** @type {(name: string) => Point} */
    const at = (name) => this.s(frame.joints[index.get(name) ?? -1]);
    scene.moving_bodies.forEach((b, i) => {
      const pose = frame.bodies[i];
      if (pose) g.append(this.poly(placed(b.polygon, pose), { class: 'moving animated', style: `--c:${bodyColour(i)}` }));
    });
    const m = r.mechanism;
    if (!m) return;
    const driver = m.driver;
    for (const part of m.parts) {
      if (part.kind === 'link') {
        const pts = part.joints.filter((n) => index.has(n)).map(at);
        const crank = part.joints.includes(driver.pivot) && part.joints.includes(driver.tip);
        if (pts.length === 2) {
          g.append(svg('line', { class: crank ? 'link crank' : 'link', x1: pts[0][0], y1: pts[0][1], x2: pts[1][0], y2: pts[1][1] }));
        } else if (pts.length > 2) {
          g.append(svg('polygon', { class: 'link ternary', points: points(pts) }));
        }
      } else if (part.kind === 'body') {
        // A bracket from the body to its joints, so joints outside the outline are seen to be fixed to it.
        const pts = part.joints.filter((n) => index.has(n)).map(at);
        const k = part.body ?? -1;
        const pose = frame.bodies[k];
        const body = scene.moving_bodies[k];
        if (pose && body) {
          const c = this.s(toWorld(pose, centroid(body.polygon)));
          for (const p of pts) {
            g.append(svg('line', { class: 'bracket', x1: c[0], y1: c[1], x2: p[0], y2: p[1], style: `--c:${bodyColour(k)}` }));
          }
        }
      }
    }
    if (m.slider && index.has(m.slider.joint)) {
      const p = at(m.slider.joint), d = m.slider.direction;
      const deg = (-Math.atan2(d[1], d[0]) * 180) / Math.PI;
      g.append(svg('rect', { class: 'slider-block', x: -12, y: -7, width: 24, height: 14, transform: `translate(${p[0]},${p[1]}) rotate(${deg})` }));
    }
    for (const name of a.fixed_joints) {
      const p = at(name);
      g.append(svg('path', { class: 'ground', d: `M${p[0]},${p[1]} l-9,14 h18 z` }));
    }
    for (const spring of frame.springs || []) g.append(this.spring(spring));
    const pinned = this.store.scene.pinned_joints || {};
    a.joint_names.forEach((name) => {
      const p = at(name);
      g.append(svg('circle', { class: name in pinned ? 'joint pinned' : 'joint', cx: p[0], cy: p[1], r: 4.5, 'data-joint': name }));
    });
    // Where a moved joint was asked to go when the linkage cannot follow it there, and why.
    const no = this.rejectedJoint;
    if (no) {
      const p = this.s(no.at);
      g.append(svg('circle', { class: 'joint rejected', cx: p[0], cy: p[1], r: 6, 'data-rejected': no.name }));
      g.append(svg('text', { class: 'rejected-label', x: p[0] + 10, y: p[1] - 10, text: no.message }));
    }
  }

  /** A counterbalance spring at a frame: an extension spring as a coil between its hooks, a torsion
   * spring as a spiral at its pivot with an arm to the part it winds with.
   * @param {SpringAt} spring
   */
  spring({ kind, ends }) {
    const [a, b] = ends.map((p) => this.s(p));
    const d = [b[0] - a[0], b[1] - a[1]], length = Math.hypot(d[0], d[1]) || 1;
    const u = [d[0] / length, d[1] / length], n = [-u[1], u[0]];
    if (kind === 'extension') {
      // Straight hooks at both ends, a zigzag of fixed width between them.
      const turns = 12, hook = Math.min(10, length * 0.15), width = 5;
      /** @type {Point[]} */
      const pts = [a, [a[0] + u[0] * hook, a[1] + u[1] * hook]];
      for (let k = 1; k < 2 * turns; k++) {
        const t = hook + ((length - 2 * hook) * k) / (2 * turns), side = k % 2 ? width : -width;
        pts.push([a[0] + u[0] * t + n[0] * side, a[1] + u[1] * t + n[1] * side]);
      }
      pts.push([b[0] - u[0] * hook, b[1] - u[1] * hook], b);
      return svg('polyline', { class: 'spring', points: points(pts), 'data-spring': kind });
    }
    /** @type {Point[]} */
    const spiral = [];
    for (let k = 0; k <= 48; k++) {
      const angle = Math.atan2(u[1], u[0]) + (k / 48) * 4 * Math.PI, radius = 3 + (k / 48) * 9;
      spiral.push([a[0] + Math.cos(angle) * radius, a[1] + Math.sin(angle) * radius]);
    }
    return svg('g', { class: 'spring', 'data-spring': kind }, [
      svg('polyline', { points: points(spiral) }),
      svg('line', { x1: spiral[48][0], y1: spiral[48][1], x2: a[0] + u[0] * Math.min(length, 30), y2: a[1] + u[1] * Math.min(length, 30) }),
    ]);
  }

  /** Each link's length at its middle and each ground pivot's position beside it, in the scene's
   * units, from the design's own joints (lengths do not change along the motion).
   * @param {FrameAt | null} frame
   */
  renderDimensions(frame) {
    const g = clear(this.layers.dimensions);
    const r = this.store.result;
    const m = r?.mechanism;
    if (!frame || !this.resultShown || !r?.analysis || !m || this.store.ui.dimensions === false) return;
    const index = new Map(r.analysis.joint_names.map((n, j) => [n, j]));
    /** @type {(name: string) => Point} */
    const at = (name) => this.s(frame.joints[index.get(name) ?? -1]);
    const units = this.store.scene.units || 'mm';
    /** @type {(p: Point, text: string, cls: string, attrs?: Record<string, unknown>) => SVGTextElement} */
    const label = (p, text, cls, attrs = {}) => svg('text', { class: cls, x: p[0], y: p[1], text, ...attrs });
    for (const part of m.parts) {
      if (part.kind !== 'link') continue;
      const names = part.joints.filter((n) => index.has(n) && m.joints[n]);
      // A binary link has one side; a ternary link three.
      const sides = names.length === 2 ? [[names[0], names[1]]] : names.map((n, i) => [n, names[(i + 1) % names.length]]);
      /** @type {Point} */
      let normal;
      for (const [a, b] of sides) {
        const [pa, pb] = [at(a), at(b)];
        const length = Math.hypot(m.joints[a][0] - m.joints[b][0], m.joints[a][1] - m.joints[b][1]);
        // Beside the link's middle, on the side away from the screen's top left, upright.
        const mid = [(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2];
        const len = Math.hypot(pb[0] - pa[0], pb[1] - pa[1]) || 1;
        normal = [-(pb[1] - pa[1]) / len, (pb[0] - pa[0]) / len];
        if (normal[1] < 0) normal = [-normal[0], -normal[1]];
        g.append(label([mid[0] + normal[0] * 12, mid[1] + normal[1] * 12], `${formatDimension(length)} ${units}`, 'dimension', {
          'text-anchor': 'middle', dy: '0.35em', 'data-link': `${a}-${b}`, 'data-length': length, 'data-label': `link ${a}-${b}`,
        }));
      }
    }
    for (const name of r.analysis.fixed_joints) {
      const q = m.joints[name];
      if (!q || !index.has(name)) continue;
      const p = at(name);
      g.append(label([p[0] + 12, p[1] + 26], `${name} (${formatDimension(q[0])}, ${formatDimension(q[1])})`, 'dimension pivot', {
        'data-pivot': name, 'data-label': `pivot ${name}`,
      }));
    }
  }

  /** The selection, the poses' numbers (and misses) and the shape being drawn. */
  renderOverlay() {
    const g = clear(this.layers.overlay);
    const { scene, ui } = this.store;
    this.renderSelection(g);
    // While a design is shown, how far it misses each pose, beside the pose's number.
    const r = this.store.result;
    // (A path design's one pose is where it starts: its badge gives the path's distance instead.)
    const shown = this.showingResult() && r && (!r.metrics?.path_error || (scene.moving_bodies[0]?.poses.length ?? 0) > 1);
    const misses = shown ? poseErrors(r.metrics, r.analysis, scene) : null;
    const units = scene.units || 'mm';
    // Pose numbers on every copy of every moving body.
    scene.moving_bodies.forEach((b, i) => {
      b.poses.forEach((pose, p) => {
        const c = this.s(toWorld(pose, centroid(b.polygon)));
        const current = p === ui.pose && !this.showingResult();
        const miss = misses?.rows.find((row) => row.pose === p && row.body === i);
        g.append(svg('g', { class: current ? 'pose-tag current' : 'pose-tag', transform: `translate(${c[0]},${c[1]})`, style: `--c:${bodyColour(i)}` }, [
          svg('circle', { r: 9 }),
          svg('text', { 'text-anchor': 'middle', dy: '0.35em', text: String(p + 1) }),
          miss ? svg('text', {
            class: 'pose-miss', x: TAG_REACH, dy: '0.35em', 'data-pose': p, 'data-body': i, 'data-label': `miss ${i} ${p}`,
            text: `off by ${fmt(miss.position)} ${units}, ${fmt(miss.angle)}°`,
          }) : null,
        ]));
      });
    });
    this.renderPreview(g);
  }

  /**
   * Keeps the labels on the drawing from covering each other and the poses' numbers (labels.js): how
   * far each pose is missed comes first, then where the ground pivots are, then the links' lengths; a
   * label with no free place near its own is left out (the Result tab lists them all).
   */
  layoutLabels() {
    /** @type {(layer: SVGGElement, selector: string) => SVGElement[]} */
    const labelsIn = (layer, selector) => [...layer.querySelectorAll(selector)].filter((e) => e instanceof SVGElement);
    const misses = labelsIn(this.layers.overlay, '.pose-miss');
    const pivots = labelsIn(this.layers.dimensions, '.dimension.pivot');
    const links = labelsIn(this.layers.dimensions, '.dimension:not(.pivot)');
    const all = [...misses, ...pivots, ...links];
    if (!all.length) return;
    // Measured where they are drawn (all writes first, then all reads: one layout).
    for (const e of all) {
      e.removeAttribute('transform');
      e.removeAttribute('display');
    }
    /** @type {(e: Element) => import('./labels.js').Box} */
    const box = (e) => {
      const r = e.getBoundingClientRect();
      return { x: r.left, y: r.top, w: r.width, h: r.height };
    };
    const marks = [...this.layers.overlay.querySelectorAll('.pose-tag circle')].map(box);
    // The canvas within its rulers.
    const r = this.root.getBoundingClientRect();
    const area = { x: r.left + RULER_PX, y: r.top + RULER_PX, w: r.width - RULER_PX, h: r.height - RULER_PX };
    const labels = all.map((element) => {
      const b = box(element);
      const shifts = element.classList.contains('pose-miss') ? tagShifts(b, TAG_REACH) : besideShifts(b);
      return { element, key: element.dataset.label ?? '', box: b, shifts };
    });
    this.labelPlaces = placeLabels(labels, area, marks, this.labelPlaces);
  }

  /**
   * Outline, vertex handles and (for a moving body) the rotate handle of the selection.
   * @param {SVGGElement} g
   */
  renderSelection(g) {
    const { scene, ui } = this.store;
    const sel = ui.selection;
    if (!sel || (this.showingResult() && !this.store.ui.live)) return;
    const world = this.selectionWorld();
    if (!world) return;
    const scr = world.map((p) => this.s(p));
    g.append(svg('polygon', { class: 'selection', points: points(scr) }));
    // A curve (an ellipse is 32 corners) would bristle with handles: it moves and turns as a whole.
    const corners = scr.length <= MAX_VERTEX_HANDLES ? scr : [];
    corners.forEach((p, v) => {
      const active = sel.vertex === v;
      g.append(svg('rect', {
        class: active ? 'vertex active' : 'vertex', x: p[0] - 5, y: p[1] - 5, width: 10, height: 10,
        'data-handle': 'vertex', 'data-vertex': v,
      }));
    });
    if (sel.kind === 'moving') {
      const b = scene.moving_bodies[sel.index];
      const pose = b.poses[ui.pose];
      const { origin, handle } = this.rotateHandle(b, pose);
      g.append(svg('line', { class: 'rotate-stem', x1: origin[0], y1: origin[1], x2: handle[0], y2: handle[1] }));
      g.append(svg('circle', { class: 'rotate-handle', cx: handle[0], cy: handle[1], r: 7, 'data-handle': 'rotate' }));
      g.append(svg('path', { class: 'origin', d: `M${origin[0] - 6},${origin[1]} h12 M${origin[0]},${origin[1] - 6} v12` }));
    }
  }

  /**
   * Screen positions of a moving body's pose origin and its rotate handle (along the body's own up).
   * @param {MovingBody} body
   * @param {Pose} pose
   * @returns {{origin: Point, handle: Point}}
   */
  rotateHandle(body, pose) {
    const origin = this.s([pose[0], pose[1]]);
    const reach = Math.max(...body.polygon.map((m) => Math.hypot(m[0], m[1]))) * this.view.k + ROTATE_PX;
    const up = toWorld([0, 0, pose[2]], [0, 1]);
    return { origin, handle: [origin[0] + up[0] * reach, origin[1] - up[1] * reach] };
  }

  /**
   * The selected shape's outline in world coordinates (a moving body at the current pose).
   * @returns {Polygon | null | undefined}
   */
  selectionWorld() {
    const { scene, ui } = this.store;
    const sel = ui.selection;
    switch (sel?.kind) {
      case 'fixed': return scene.fixed_bodies[sel.index]?.polygon;
      case 'moving': {
        const b = scene.moving_bodies[sel.index];
        return b && b.poses[ui.pose] ? placed(b.polygon, b.poses[ui.pose]) : null;
      }
      case 'region': return scene.linkage_region;
      case 'avoid': return scene.avoid_regions?.[sel.index];
      default: return null;
    }
  }

  /**
   * The shape being drawn.
   * @param {SVGGElement} g
   */
  renderPreview(g) {
    const pv = this.preview;
    if (!pv || pv.points.length === 0) return;
    const pts = pv.points.map((p) => this.s(p));
    const cls = `preview preview-${pv.kind}`;
    if (pv.closed) g.append(svg('polygon', { class: cls, points: points(pts) }));
    else {
      const all = pv.cursor ? [...pts, this.s(pv.cursor)] : pts;
      g.append(svg('polyline', { class: cls, points: points(all) }));
      // A freehand stroke shows where it starts, not every point the pointer passed.
      if (pv.stroke) {
        g.append(svg('circle', { class: 'preview-start', cx: pts[0][0], cy: pts[0][1], r: 6 }));
        return;
      }
      pts.forEach((p, i) => g.append(svg('circle', { class: i === 0 ? 'preview-start' : 'preview-dot', cx: p[0], cy: p[1], r: i === 0 ? 6 : 3 })));
    }
  }
}
