// @ts-check
// Live redesign: while the person drags a pose with Live redesign on, the linkage is designed again
// from the last good design (a warm start, fast), one request at a time, and the design shown waits
// where it reaches the pose being dragged.

import * as api from './api.js';
import { savedPrintSettings } from './fabricate.js';
import { geometryKey, toFile } from './scene.js';
import { newResult } from './store.js';

/**
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./api.js').Design} Design
 * @typedef {import('./api.js').Analysis} Analysis
 * @typedef {import('./scene.js').Scene} Scene
 * @typedef {import('./player.js').Player} Player
 * @typedef {import('./result.js').Results} Results
 */

export class LiveRedesign {
  /**
   * Designs again for `results` as poses of `store`'s scene move, holding `player` at the pose dragged.
   * @param {Store} store
   * @param {Player} player
   * @param {Results} results
   */
  constructor(store, player, results) {
    this.store = store;
    this.player = player;
    this.results = results;
    /** @type {number | null} the pose a live drag holds the animation at */
    this.heldPose = null;
    /** A live redesign is on its way. */
    this.liveBusy = false;
    /** A pose moved while it was: one more redesign follows. */
    this.livePending = false;
    /** @type {Scene | null} the scene the last live request answered (a design or not), for whoever waits on it */
    this.liveAnswered = null;
    /** @type {Design | null} the last design found, the next one's warm start */
    this.good = null;
  }

  /**
   * Live mode: after a pose was moved, designs again from the last good design (a warm start, fast),
   * at most one request at a time; edits made meanwhile are picked up by one more run.
   */
  poseEdited() {
    if (!this.store.ui.live || this.results.controller || !this.lastGood()) return;
    // While a pose is dragged the design shown waits where it reaches that pose, so the person sees
    // the two meet as they move it (and the page leaves the cores to the redesign); it plays again
    // when the pose is let go.
    this.heldPose = this.store.ui.pose;
    this.player.pauseAt(this.heldPose);
    if (this.liveBusy) {
      this.livePending = true;
      return;
    }
    this.runLive();
  }

  /** A pose dragged in live mode was let go: the design shown plays again. */
  poseReleased() {
    if (this.heldPose == null) return;
    this.heldPose = null;
    if (this.player.canvas.showingResult()) this.player.setPlaying(true);
  }

  /** The last design found (kept while none is shown), or null. */
  lastGood() {
    const r = this.store.result;
    if (r?.design?.status === 'ok') this.good = r.design;
    return this.good;
  }

  /** Another scene was opened: a redesign on its way is not for it. */
  forget() {
    this.livePending = false;
    this.good = null;
  }

  async runLive() {
    this.liveBusy = true;
    this.livePending = false;
    const scene = toFile(this.store.scene);
    const key = geometryKey(this.store.scene);
    const epoch = this.results.epoch;
    const path = scene.moving_bodies.some((b) => b.path);
    try {
      // The motion analysis comes with the design: one round trip less per step of the drag.
      /** @type {Analysis | null} */
      let analysis = null;
      // The design that follows the one shown, not the cheapest: a small drag moves the linkage a little.
      const request = { scene, from: this.lastGood(), print_settings: savedPrintSettings(), analysis: true, follow: true };
      const design = await api.designStream(request, (event) => { if (event.name === 'analysis') analysis = event.data; });
      if (epoch !== this.results.epoch) {
        // Another scene was opened: this answer is not for it.
      } else if (design?.status === 'ok') {
        this.store.setResult(newResult({ design, scene, key }));
        await this.results.select(null, { keep: true, analysis });
        this.results.verify();
        this.store.hint(`Live: redesigned for the moved ${path ? 'path' : 'pose'} (cost ${design.metrics.cost.toFixed(2)}).`);
      } else if (design) {
        this.store.hint(path
          ? 'Live: no linkage follows the path as it is now; bend it back a little, or press Design linkage.'
          : 'Live: no linkage reaches the poses as they are now; move the pose back a little, or press Design linkage.');
      }
    } catch (e) {
      if (epoch === this.results.epoch) this.store.hint(`Live: ${api.errorOf(e).message}`);
    }
    this.liveAnswered = scene;
    this.liveBusy = false;
    if (this.livePending) this.runLive();
    else {
      this.results.sync();
      this.store.changed('result');
    }
  }
}
