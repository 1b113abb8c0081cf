// @ts-check
// The animation of the design shown: play and pause, the scrub bar and the speed, where along the
// motion it is (a fractional frame, interpolated between the analysis' frames), and going to the
// frame where the design reaches a pose.

import { placed } from './geom.js';

/**
 * @typedef {import('./geom.js').Point} Point
 * @typedef {import('./geom.js').Pose} Pose
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./canvas.js').Canvas} Canvas
 * @typedef {import('./canvas.js').FrameAt} FrameAt
 * @typedef {{player: HTMLElement, play: HTMLElement, scrub: HTMLInputElement, readout: HTMLElement,
 *   speed: HTMLSelectElement, edit: HTMLElement}} PlayerElements
 *   The player bar: its Play button, scrub bar, crank readout, speed menu and Edit drawing button.
 */

/** Seconds one way through the motion at speed 1. */
export const TRAVEL_SECONDS = 3;

export class Player {
  /**
   * Plays the design `store` shows on `canvas`, with the controls `els`.
   * @param {Store} store
   * @param {Canvas} canvas
   * @param {PlayerElements} els
   */
  constructor(store, canvas, els) {
    this.store = store;
    this.canvas = canvas;
    this.els = els;
    /** Where along the motion the animation is: a fractional frame. */
    this.pos = 0;
    /** Which way it goes: 1 forward, −1 back (it goes to and fro). */
    this.dir = 1;
    this.playing = false;
    this.speed = 1;
    /** @type {number | null} the time of the last animation frame drawn, ms */
    this.last = null;
    /** @type {number | null} the animation frame asked for */
    this.raf = null;
    /**
     * Told of every frame drawn, with its fraction of the motion (0 the first pose, 1 the last): the
     * plots' cursors and the 3D view follow the animation.
     * @type {(frame: FrameAt, fraction: number) => void}
     */
    this.onFrame = () => {};
    els.play.addEventListener('click', () => this.setPlaying(!this.playing));
    els.scrub.addEventListener('input', () => {
      this.setPlaying(false);
      this.pos = (Number(els.scrub.value) / 1000) * (this.frameCount() - 1);
      this.drawFrame();
    });
    els.speed.addEventListener('change', () => { this.speed = Number(els.speed.value) || 1; });
    els.edit.addEventListener('click', () => this.leave());
  }

  /** The motion analysis of the design shown, or null. */
  analysis() {
    return this.store.result?.analysis ?? null;
  }

  frameCount() {
    return this.analysis()?.frames.length || 0;
  }

  /**
   * While the result is shown, moves its animation to input pose `i` and pauses there; false when
   * no result is shown (the pose bar then selects the pose for editing).
   * @param {number} i
   */
  showPose(i) {
    if (!this.store.ui.showResult || !this.pauseAt(i)) return false;
    this.store.setUi({ pose: i });
    this.store.hint(`Pose ${i + 1}, as the design reaches it. Press Play to move on, or Edit drawing to change the poses.`);
    return true;
  }

  /**
   * Pauses the animation where the design shown reaches input pose `i`; false when it has no such pose.
   * @param {number} i
   */
  pauseAt(i) {
    const pose = this.analysis()?.poses?.[i];
    if (!pose) return false;
    this.setPlaying(false);
    this.pos = pose.frame;
    this.drawFrame();
    return true;
  }

  /**
   * Every point the motion shown passes (its bodies and joints at each frame), to frame the view by;
   * none when no design is shown.
   * @returns {Point[]}
   */
  motionPoints() {
    const r = this.store.result;
    if (!this.store.ui.showResult || !r?.analysis) return [];
    const bodies = r.scene.moving_bodies;
    return r.analysis.frames.flatMap((f) => [...f.joints, ...f.bodies.flatMap((pose, k) => placed(bodies[k].polygon, pose))]);
  }

  /** Back to editing: the animation stops and the poses are editable again. */
  leave() {
    if (!this.store.ui.showResult) return;
    this.setPlaying(false);
    this.store.setUi({ showResult: false });
  }

  /** Plays or pauses the design shown (nothing when none is). */
  togglePlaying() {
    if (this.store.ui.showResult && this.analysis()) this.setPlaying(!this.playing);
  }

  /**
   * Plays (when the motion has frames to play) or pauses.
   * @param {boolean} on
   */
  setPlaying(on) {
    if (on && this.frameCount() < 2) on = false;
    this.playing = on;
    this.els.play.textContent = on ? '❚❚ Pause' : '▶ Play';
    this.els.play.setAttribute('aria-pressed', String(on));
    if (on && !this.raf) {
      this.last = null;
      this.raf = requestAnimationFrame((t) => this.tick(t));
    }
  }

  /**
   * One animation frame: moves on by the time since the last, at the speed chosen, turning at the ends.
   * @param {number} t  the frame's time, ms
   */
  tick(t) {
    this.raf = null;
    if (!this.playing) return;
    const n = this.frameCount();
    if (this.last !== null && n > 1) {
      const dt = Math.min((t - this.last) / 1000, 0.1);
      this.pos += (this.dir * dt * this.speed * (n - 1)) / TRAVEL_SECONDS;
      if (this.pos >= n - 1) { this.pos = n - 1; this.dir = -1; }
      if (this.pos <= 0) { this.pos = 0; this.dir = 1; }
      this.drawFrame();
    }
    this.last = t;
    this.raf = requestAnimationFrame((u) => this.tick(u));
  }

  /**
   * Moves the animation to fractional frame `pos`, to be drawn by the next `drawFrame` (with
   * `fromStart`, it goes forward from there).
   * @param {number} pos
   * @param {{fromStart?: boolean}} [options]
   */
  goTo(pos, { fromStart = false } = {}) {
    this.pos = pos;
    if (fromStart) this.dir = 1;
  }

  /**
   * The configuration at fractional frame `pos`, interpolated between neighbouring frames.
   * @param {import('./api.js').Analysis} analysis
   * @param {number} pos
   * @returns {FrameAt}
   */
  frameAt(analysis, pos) {
    const frames = analysis.frames;
    const i = Math.max(0, Math.min(frames.length - 1, Math.floor(pos)));
    const j = Math.min(frames.length - 1, i + 1);
    const t = Math.max(0, Math.min(1, pos - i));
    const a = frames[i], b = frames[j];
    /** @type {(x: number, y: number) => number} */
    const mix = (x, y) => x + (y - x) * t;
    const springs = (this.store.result?.balance?.springs || []).filter((s) => s.ends[j]).map((s) => ({
      kind: s.kind,
      ends: [0, 1].map((e) => /** @type {Point} */ ([mix(s.ends[i][e][0], s.ends[j][e][0]), mix(s.ends[i][e][1], s.ends[j][e][1])])),
    }));
    return {
      springs,
      crank_deg: mix(a.crank_deg, b.crank_deg),
      joints: a.joints.map((p, k) => /** @type {Point} */ ([mix(p[0], b.joints[k][0]), mix(p[1], b.joints[k][1])])),
      bodies: a.bodies.map((p, k) => /** @type {Pose} */ ([mix(p[0], b.bodies[k][0]), mix(p[1], b.bodies[k][1]), mix(p[2], b.bodies[k][2])])),
    };
  }

  /** Draws the frame the animation is at, and moves the controls and the followers (`onFrame`) with it. */
  drawFrame() {
    const analysis = this.analysis();
    if (!analysis) return;
    const frame = this.frameAt(analysis, this.pos);
    this.canvas.renderResultFrame(frame);
    const n = this.frameCount();
    this.els.scrub.value = String(n > 1 ? Math.round((this.pos / (n - 1)) * 1000) : 0);
    this.els.readout.textContent = `crank ${frame.crank_deg.toFixed(1)}°`;
    this.canvas.root.dataset.crank = frame.crank_deg.toFixed(3);
    const frames = analysis.frames, first = frames[0].crank_deg, last = frames[n - 1].crank_deg;
    this.onFrame(frame, last === first ? 0 : (frame.crank_deg - first) / (last - first));
  }
}
