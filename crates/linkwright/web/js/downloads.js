// @ts-check
// The design shown as files: its design/1 file, the server's pictures of it (the design sheet, the
// animation) and its motion as drawn on the canvas, an animated GIF or a WebM video.

import * as api from './api.js';
import { TRAVEL_SECONDS } from './player.js';
import { captureFrames, encodeGif, recordWebm } from './record.js';

/**
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./api.js').Design} Design
 * @typedef {import('./player.js').Player} Player
 */

/** Frames of an exported motion (20 a second over one travel). */
const EXPORT_FRAMES = 60;

/**
 * The design file with the mechanism shown (`which`: null for the best) as its design, the others
 * after it as alternatives, the former best first: what a person viewing an alternative downloads.
 * @param {Design} d
 * @param {number | null} which
 * @returns {Design}
 */
export function designShown(d, which) {
  const shown = which === null ? null : d.alternatives?.[which];
  if (!shown || d.status !== 'ok') return d;
  const best = { mechanism: d.mechanism, motion: d.motion, metrics: d.metrics };
  return { ...d, ...shown, alternatives: [best, ...d.alternatives.filter((_, i) => i !== which)] };
}

export class ResultDownloads {
  /**
   * Files of the design `store` shows, its motion recorded as `player` plays it; `save(blob, name)`
   * offers a file.
   * @param {Store} store
   * @param {Player} player
   * @param {(blob: Blob, name: string) => void} save
   */
  constructor(store, player, save) {
    this.store = store;
    this.player = player;
    this.save = save;
    /** A motion is being recorded. */
    this.exporting = false;
  }

  /** The file name the scene gives its downloads (as it is named now: it may have been renamed since it was designed). */
  baseName() {
    return (this.store.scene.name || 'design').replace(/[^\w.-]+/g, '_');
  }

  /**
   * The design/1 file of the mechanism shown, or the server's picture of it (`design`: the sheet,
   * `animation`: the animated SVG).
   * @param {'json' | 'design' | 'animation'} kind
   */
  async download(kind) {
    const r = this.store.result;
    if (!r) return;
    const base = this.baseName();
    if (kind === 'json') {
      const file = JSON.stringify(designShown(r.design, r.which), null, 2);
      this.save(new Blob([file], { type: 'application/json' }), `${base}.design.json`);
      return;
    }
    try {
      const blob = await api.render(r.scene, r.design, kind, r.which);
      this.save(blob, `${base}.${kind}.svg`);
    } catch (e) {
      this.store.hint(`Cannot make the picture: ${api.errorOf(e).message}`);
    }
  }

  /**
   * The motion as shown on the canvas, one travel from the first pose to the last, as an animated GIF
   * or a WebM video of TRAVEL_SECONDS.
   * @param {'gif' | 'webm'} kind
   */
  async exportMotion(kind) {
    const r = this.store.result;
    const frames = r?.analysis?.frames;
    const canvas = this.player.canvas;
    if (!frames?.length || !canvas.showingResult() || this.exporting) {
      this.store.hint('Show the design first (▶ Show the design), then export its motion.');
      return;
    }
    this.exporting = true;
    const base = this.baseName();
    const count = Math.min(EXPORT_FRAMES, frames.length);
    /** @type {(i: number) => import('./api.js').Frame} */
    const frameAt = (i) => frames[Math.round((i * (frames.length - 1)) / Math.max(count - 1, 1))];
    const wasPlaying = this.player.playing;
    this.player.setPlaying(false);
    /** @type {(i: number) => void} */
    const show = (i) => canvas.renderResultFrame(frameAt(i));
    this.store.hint(`Recording the motion (${count} frames)…`);
    try {
      if (kind === 'gif') {
        const { frames: images } = await captureFrames(canvas.root, count, show);
        const delay = Math.max(2, Math.round((100 * TRAVEL_SECONDS) / count));
        this.save(new Blob([encodeGif(images, delay)], { type: 'image/gif' }), `${base}.motion.gif`);
      } else {
        const video = await recordWebm(canvas.root, count, count / TRAVEL_SECONDS, show);
        if (!video) throw new Error('this browser cannot record WebM video; the GIF works everywhere');
        this.save(video, `${base}.motion.webm`);
      }
      this.store.hint(`Saved the motion as ${kind === 'gif' ? 'an animated GIF' : 'a WebM video'}.`);
    } catch (e) {
      this.store.hint(`Cannot record the motion: ${api.errorOf(e).message}`);
    } finally {
      this.exporting = false;
      this.player.drawFrame();
      if (wasPlaying) this.player.setPlaying(true);
    }
  }
}
