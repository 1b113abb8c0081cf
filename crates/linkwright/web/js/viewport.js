// @ts-check
// The view onto the world: pan and zoom, and the map between world coordinates (y up, millimetres)
// and screen pixels (y down) of the canvas.

import { bounds } from './geom.js';

/** @typedef {import('./geom.js').Point} Point */

export class Viewport {
  constructor() {
    // Screen position of the world origin, and pixels per world unit.
    this.ox = 60;
    this.oy = 500;
    this.k = 3;
    this.width = 800;
    this.height = 600;
  }

  /**
   * The canvas is `width` × `height` pixels now.
   * @param {number} width
   * @param {number} height
   */
  resize(width, height) {
    this.width = width;
    this.height = height;
  }

  /**
   * The screen pixel of world point `p`.
   * @param {Point} p
   * @returns {Point}
   */
  toScreen(p) {
    return [this.ox + p[0] * this.k, this.oy - p[1] * this.k];
  }

  /**
   * The world point at screen pixel `s`.
   * @param {Point} s
   * @returns {Point}
   */
  toWorld(s) {
    return [(s[0] - this.ox) / this.k, (this.oy - s[1]) / this.k];
  }

  /** The SVG transform that draws world coordinates on screen. */
  transform() {
    return `matrix(${this.k},0,0,${-this.k},${this.ox},${this.oy})`;
  }

  /**
   * Moves the view by `dx`, `dy` pixels.
   * @param {number} dx
   * @param {number} dy
   */
  pan(dx, dy) {
    this.ox += dx;
    this.oy += dy;
  }

  /**
   * Zooms by `factor` keeping the world point under screen point `s` in place.
   * @param {Point} s
   * @param {number} factor
   */
  zoomAt(s, factor) {
    const k = Math.min(Math.max(this.k * factor, 0.02), 200);
    const w = this.toWorld(s);
    this.k = k;
    this.ox = s[0] - w[0] * k;
    this.oy = s[1] + w[1] * k;
  }

  /**
   * Shows all of `points` with a margin (a default view when there are none); `top` and `bottom`
   * margins may be wider.
   * @param {Point[]} points
   * @param {number} [margin]
   * @param {{top?: number, bottom?: number}} [edges]
   */
  fit(points, margin = 40, { top = margin, bottom = margin } = {}) {
    if (points.length === 0) {
      this.k = Math.min(this.width / 320, this.height / 220);
      this.ox = margin;
      this.oy = this.height - bottom;
      return;
    }
    const b = bounds(points);
    const w = Math.max(b.maxX - b.minX, 1e-6), h = Math.max(b.maxY - b.minY, 1e-6);
    this.k = Math.min((this.width - 2 * margin) / w, (this.height - top - bottom) / h);
    this.ox = (this.width - w * this.k) / 2 - b.minX * this.k;
    this.oy = top + (this.height - top - bottom + h * this.k) / 2 + b.minY * this.k;
  }

  /**
   * The grid spacing (world units) that keeps lines at least `minPx` apart: 1, 2 or 5 × 10ⁿ.
   * @param {number} [minPx]
   */
  gridStep(minPx = 14) {
    const raw = minPx / this.k;
    const p = 10 ** Math.floor(Math.log10(raw));
    for (const m of [1, 2, 5, 10]) if (m * p >= raw) return m * p;
    return 10 * p;
  }

  /**
   * The largest length of 1, 2 or 5 × 10ⁿ world units at most `maxPx` long on screen (a scale bar).
   * @param {number} maxPx
   */
  niceLength(maxPx) {
    const raw = maxPx / this.k;
    const p = 10 ** Math.floor(Math.log10(raw));
    return [5, 2, 1].map((m) => m * p).find((l) => l <= raw) ?? p;
  }

  /** The world box on screen. */
  visible() {
    const a = this.toWorld([0, this.height]), b = this.toWorld([this.width, 0]);
    return { minX: a[0], minY: a[1], maxX: b[0], maxY: b[1] };
  }
}
