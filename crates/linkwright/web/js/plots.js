// @ts-check
// Small SVG charts of a design's analysis: transmission angles over the motion, the error at each
// pose, and each loop's Grashof type.

import { bodyColour, PATH_COLOURS } from './canvas.js';
import { springCut } from './springs.js';
import { html, points, svg } from './svg.js';

/**
 * @typedef {import('./api.js').Analysis} Analysis
 * @typedef {import('./api.js').Balance} Balance
 * @typedef {import('./geom.js').Point} Point
 * @typedef {{element: HTMLElement, moveCursor: (crankDeg: number) => void}} CursorPlot  A chart
 *   against the crank angle, and how to move its cursor to the current frame.
 */

const W = 300, H = 150, PAD = { l: 40, r: 8, t: 14, b: 30 };

/**
 * Axes with horizontal grid lines at `yTicks`, labelled (`format`ted) with `unit`, and an x-axis
 * caption.
 * @param {string} xLabel
 * @param {string} unit
 * @param {number[]} yTicks
 * @param {(y: number) => number} scaleY
 * @param {(t: number) => string} [format]
 */
function axes(xLabel, unit, yTicks, scaleY, format = String) {
  const g = svg('g', { class: 'axes' });
  g.append(svg('line', { x1: PAD.l, y1: H - PAD.b, x2: W - PAD.r, y2: H - PAD.b }));
  g.append(svg('line', { x1: PAD.l, y1: PAD.t, x2: PAD.l, y2: H - PAD.b }));
  for (const t of yTicks) {
    const y = scaleY(t);
    g.append(svg('line', { class: 'tick', x1: PAD.l - 3, y1: y, x2: W - PAD.r, y2: y }));
    g.append(svg('text', { x: PAD.l - 5, y, dy: '0.35em', 'text-anchor': 'end', text: `${format(t)}${unit}` }));
  }
  g.append(svg('text', { x: (PAD.l + W - PAD.r) / 2, y: H - 4, 'text-anchor': 'middle', text: xLabel }));
  return g;
}

/**
 * Transmission angle (0–180°) of every dyad against the crank angle, with the forbidden bands near 0°
 * and 180° shaded, the comfortable band between them marked, the poses marked, and a cursor at the
 * current frame (returned for updates).
 * @param {Analysis} analysis
 * @returns {CursorPlot}
 */
export function transmissionPlot(analysis) {
  const frames = analysis.frames;
  const xs = frames.map((f) => f.crank_deg);
  const x0 = xs[0], x1 = xs[xs.length - 1] === x0 ? x0 + 1 : xs[xs.length - 1];
  /** @type {(x: number) => number} */
  const sx = (x) => PAD.l + ((x - x0) / (x1 - x0)) * (W - PAD.l - PAD.r);
  /** @type {(y: number) => number} */
  const sy = (y) => H - PAD.b - (y / 180) * (H - PAD.t - PAD.b);
  const bound = analysis.min_transmission_bound_deg;
  // Files analysed before the comfortable angle existed: no band.
  const comfortable = Math.max(bound, analysis.comfortable_transmission_deg ?? bound);
  const root = svg('svg', { viewBox: `0 0 ${W} ${H}`, class: 'plot', role: 'img', 'aria-label': 'transmission angles' });
  root.append(svg('rect', { class: 'comfort', x: PAD.l, y: sy(180 - comfortable), width: W - PAD.l - PAD.r, height: sy(comfortable) - sy(180 - comfortable) }));
  root.append(svg('rect', { class: 'band', x: PAD.l, y: sy(bound), width: W - PAD.l - PAD.r, height: sy(0) - sy(bound) }));
  root.append(svg('rect', { class: 'band', x: PAD.l, y: sy(180), width: W - PAD.l - PAD.r, height: sy(180 - bound) - sy(180) }));
  root.append(axes(`crank angle, ${x0.toFixed(0)}° to ${x1.toFixed(0)}°`, '°', [0, 45, 90, 135, 180], sy));
  for (const p of analysis.poses) {
    const x = sx(p.crank_deg);
    root.append(svg('line', { class: 'pose-mark', x1: x, y1: PAD.t, x2: x, y2: H - PAD.b }));
    root.append(svg('text', { class: 'pose-num', x, y: PAD.t - 4, 'text-anchor': 'middle', text: String(p.pose + 1) }));
  }
  analysis.dyads.forEach((d, i) => {
    const pts = frames.map((f) => /** @type {Point} */ ([sx(f.crank_deg), sy(f.transmission_deg[i])]));
    root.append(svg('polyline', { class: 'series', points: points(pts), stroke: PATH_COLOURS[i % PATH_COLOURS.length] }));
  });
  const cursor = svg('line', { class: 'cursor', x1: PAD.l, y1: PAD.t, x2: PAD.l, y2: H - PAD.b });
  root.append(cursor);
  const legend = html('div', { class: 'legend' }, analysis.dyads.map((d, i) =>
    html('span', {}, [html('i', { style: `background:${PATH_COLOURS[i % PATH_COLOURS.length]}` }), `at ${d.joint} (${d.from.join('–')})`])));
  const worst = analysis.min_transmission_deg;
  const comfortNote = comfortable > bound
    ? ` Green: the comfortable band, at least ${comfortable}° from a dead point${worst < comfortable ? ' (this design leaves it)' : ''}.`
    : '';
  const note = html('small', { text: `Red: closer than ${bound}° to a dead point.${comfortNote} Worst along the motion: ${worst.toFixed(1)}°.` });
  return {
    element: html('div', { class: 'chart' }, [root, legend, note]),
    moveCursor: (crankDeg) => {
      const x = String(sx(crankDeg));
      cursor.setAttribute('x1', x);
      cursor.setAttribute('x2', x);
    },
  };
}

/**
 * The largest vertex error of every body at every pose, as bars.
 * @param {Analysis} analysis
 * @param {import('./scene.js').Scene} scene
 */
export function errorPlot(analysis, scene) {
  const poses = analysis.poses;
  const bodies = scene.moving_bodies.length;
  const max = Math.max(1e-9, ...poses.flatMap((p) => p.bodies.map((b) => b.max_vertex)));
  const top = niceCeil(max);
  /** @type {(y: number) => number} */
  const sy = (y) => H - PAD.b - (y / top) * (H - PAD.t - PAD.b);
  const root = svg('svg', { viewBox: `0 0 ${W} ${H}`, class: 'plot', role: 'img', 'aria-label': 'error at each pose' });
  // The unit goes in the caption: beside every tick, a tiny error's label ("5e-10 mm") would not fit.
  root.append(axes(`pose (off by, ${scene.units || 'mm'})`, '', [0, top / 2, top], sy, tick));
  const slot = (W - PAD.l - PAD.r) / poses.length;
  const bar = Math.min(28, (slot * 0.7) / Math.max(bodies, 1));
  poses.forEach((p, i) => {
    const cx = PAD.l + slot * (i + 0.5);
    p.bodies.forEach((b, k) => {
      const x = cx - (bar * bodies) / 2 + k * bar;
      const y = sy(b.max_vertex);
      root.append(svg('rect', { class: 'bar', x, y, width: bar - 2, height: Math.max(H - PAD.b - y, 0.5), fill: bodyColour(k) }, [
        svg('title', { text: `pose ${i + 1}, ${scene.moving_bodies[k]?.name}: off by up to ${b.max_vertex.toFixed(2)}, turned ${b.angle_deg.toFixed(2)}° too far` }),
      ]));
    });
    root.append(svg('text', { x: cx, y: H - PAD.b + 12, 'text-anchor': 'middle', text: String(i + 1) }));
  });
  const worst = Math.max(...poses.flatMap((p) => p.bodies.map((b) => Math.abs(b.angle_deg))));
  return html('div', { class: 'chart' }, [root, html('small', {
    text: `How far each body's outline is from where it was drawn, at each pose (largest corner distance). Largest angle miss: ${worst.toFixed(2)}°.`,
  })]);
}

/**
 * A tick's number in at most five characters: 0, 0.05, 250, 2e+4, 5e-10.
 * @param {number} t
 */
function tick(t) {
  if (t === 0) return '0';
  const plain = String(+t.toPrecision(3));
  return plain.length <= 5 ? plain : t.toExponential(0);
}

/**
 * 1, 2 or 5 × 10ⁿ at or above `x`.
 * @param {number} x
 */
function niceCeil(x) {
  const p = 10 ** Math.floor(Math.log10(x));
  for (const m of [1, 2, 5, 10]) if (m * p >= x) return m * p;
  return 10 * p;
}

/**
 * The torque the crank needs to hold the parts against gravity, against the crank angle, with the
 * poses marked, zero drawn, and a cursor at the current frame (returned for updates); with the
 * springs of `balance`, the torque with them too.
 * @param {Analysis} analysis  the motion (its poses are marked)
 * @param {import('./api.js').Torque} t  its torque
 * @param {Balance | null} [balance]
 * @returns {CursorPlot}
 */
export function torquePlot(analysis, t, balance = null) {
  const xs = t.crank_deg;
  const x0 = xs[0], x1 = xs[xs.length - 1] === x0 ? x0 + 1 : xs[xs.length - 1];
  // A printed model needs thousandths of a newton-metre: N·mm reads better there.
  const [unit, factor] = t.peak_nm < 1 ? ['N·mm', 1000] : ['N·m', 1];
  const top = niceCeil(Math.max(t.peak_nm * factor, 1e-9));
  /** @type {(x: number) => number} */
  const sx = (x) => PAD.l + ((x - x0) / (x1 - x0)) * (W - PAD.l - PAD.r);
  /** @type {(y: number) => number} */
  const sy = (y) => PAD.t + ((top - y) / (2 * top)) * (H - PAD.t - PAD.b);
  const root = svg('svg', { viewBox: `0 0 ${W} ${H}`, class: 'plot', role: 'img', 'aria-label': 'torque to drive the crank' });
  root.append(axes(`crank angle, ${x0.toFixed(0)}° to ${x1.toFixed(0)}°`, '', [-top, 0, top].map((v) => +v.toPrecision(3)), sy));
  root.append(svg('line', { class: 'zero', x1: PAD.l, y1: sy(0), x2: W - PAD.r, y2: sy(0) }));
  for (const p of analysis.poses) {
    const x = sx(p.crank_deg);
    root.append(svg('line', { class: 'pose-mark', x1: x, y1: PAD.t, x2: x, y2: H - PAD.b }));
    root.append(svg('text', { class: 'pose-num', x, y: PAD.t - 4, 'text-anchor': 'middle', text: String(p.pose + 1) }));
  }
  const pts = xs.map((x, k) => /** @type {Point} */ ([sx(x), sy(t.torque_nm[k] * factor)]));
  root.append(svg('polyline', { class: 'series torque', points: points(pts), stroke: PATH_COLOURS[0] }));
  const balanced = balance?.torque_with_springs_nm;
  if (balance && balanced?.length === xs.length && balance.springs.length) {
    const with_ = xs.map((x, k) => /** @type {Point} */ ([sx(x), sy(balanced[k] * factor)]));
    root.append(svg('polyline', { class: 'series torque balanced', points: points(with_), stroke: PATH_COLOURS[1] }));
  }
  const cursor = svg('line', { class: 'cursor', x1: PAD.l, y1: PAD.t, x2: PAD.l, y2: H - PAD.b });
  root.append(cursor);
  const mass = t.parts.reduce((m, p) => m + p.mass_kg, 0);
  const note = html('small', {
    'data-peak': t.peak_nm,
    text: `In ${unit}: positive lifts the parts as the crank advances. Peak ${(t.peak_nm * factor).toPrecision(3)} ${unit} at crank ${t.peak_crank_deg.toFixed(0)}°, ` +
      `${(mass * 1000).toPrecision(3)} g moving (printed parts, or the masses the scene gives).` +
      (balance?.springs.length
        ? ` With the springs (the second line): peak ${(balance.peak_with_springs_nm * factor).toPrecision(3)} ${unit}, ` +
          `${springCut(balance)}% lower.`
        : ''),
  });
  return {
    element: html('div', { class: 'chart' }, [root, note]),
    moveCursor: (crankDeg) => {
      const x = String(sx(crankDeg));
      cursor.setAttribute('x1', x);
      cursor.setAttribute('x2', x);
    },
  };
}

/**
 * Each loop with its Grashof type and link lengths.
 * @param {Analysis} analysis
 */
export function loopList(analysis) {
  return html('ul', { class: 'loops' }, analysis.loops.map((l) => html('li', {}, [
    html('b', { text: l.name }), ' ',
    html('span', { class: l.grashof ? 'badge ok' : 'badge', text: l.grashof ? 'Grashof' : 'non-Grashof' }),
    html('div', { text: l.description }),
    html('small', { text: l.links.map((k) => `${k.role} ${k.joints.join('–')} ${k.length.toFixed(1)}`).join(' · ') }),
  ])));
}
