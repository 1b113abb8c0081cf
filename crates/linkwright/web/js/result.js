// @ts-check
// Running a design (with live progress and cancel) and showing its result: which mechanism is shown,
// its motion analysis and its independent check. The parts of the result's screen are modules of
// their own, made and held here: the animation (player.js), the Result tab (result-tab.js) with its
// plots (result-plots.js) and springs (springs-panel.js), the downloads (downloads.js), joints moved
// directly (joint-edit.js) and the live redesign (live.js).

import * as api from './api.js';
import { parseBuild } from './build.js';
import { savedPrintSettings } from './fabricate.js';
import { JointEditor } from './joint-edit.js';
import { LiveRedesign } from './live.js';
import { Player } from './player.js';
import { ResultDownloads, designShown } from './downloads.js';
import { ResultPlots } from './result-plots.js';
import { mechanismName, ResultTab } from './result-tab.js';
import { geometryKey, toFile } from './scene.js';
import { SpringsPanel } from './springs-panel.js';
import { newResult } from './store.js';

/**
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./store.js').Result} Result
 * @typedef {import('./canvas.js').Canvas} Canvas
 * @typedef {import('./api.js').Analysis} Analysis
 * @typedef {import('./api.js').Issue} Issue
 * @typedef {import('./api.js').StreamEvent} StreamEvent
 * @typedef {import('./fabricate.js').Fabricator} Fabricator
 * @typedef {import('./player.js').PlayerElements} PlayerElements
 */

/**
 * The page's controls of the result: the design job's progress bar (`job`, `jobFill`, `jobText`),
 * the Design and Cancel buttons, the player bar, the Joint paths, Dimensions and Live redesign
 * options, and the Show the design button.
 * @typedef {PlayerElements & {job: HTMLElement, jobFill: HTMLElement, jobText: HTMLElement,
 *   design: HTMLButtonElement, cancel: HTMLElement, paths: HTMLInputElement, dims: HTMLInputElement,
 *   live: HTMLInputElement, show: HTMLElement}} ResultElements
 */

/**
 * Why the last design failed: the server's message and issues, and the scene (as JSON) it was asked
 * for (none: the failure was not of a scene, but of the analysis of a design shown).
 * @typedef {{message: string, issues: Issue[], scene?: string}} DesignError
 */

const STAGES = /** @type {Record<string, string>} */ ({ sampling: 'Sampling linkages', collision: 'Checking collisions', refining: 'Refining the best' });

/**
 * A family's label from the engine's list (its file word until the list is loaded).
 * @param {Store} store
 * @param {string} id
 */
function familyLabel(store, id) {
  const family = store.families.find((f) => f.id === id);
  return family ? family.label : id;
}

export class Results {
  /**
   * Designs the scene of `store` and shows the result on `canvas` and in the page's controls `els`;
   * `save(blob, name)` offers a file.
   * @param {Store} store
   * @param {Canvas} canvas
   * @param {ResultElements} els
   * @param {(blob: Blob, name: string) => void} save
   */
  constructor(store, canvas, els, save) {
    this.store = store;
    this.canvas = canvas;
    this.els = els;
    /** Frames the view (set by the app). */
    this.fitView = () => {};
    /** @type {AbortController | null} the design running */
    this.controller = null;
    /** Counts the scenes opened: an answer for an earlier one is dropped. */
    this.epoch = 0;
    /** @type {DesignError | null} */
    this.error = null;
    /** @type {Issue[]} the warnings the running design's scene was accepted with */
    this.warnings = [];
    /** @type {Fabricator | null} adds its part to the Result tab and follows the animation */
    this.fab = null;
    this.player = new Player(store, canvas, els);
    this.joints = new JointEditor(store, canvas, this.player);
    this.live = new LiveRedesign(store, this.player, this);
    this.springs = new SpringsPanel(store, () => this.player.drawFrame());
    this.plots = new ResultPlots(store, this.springs, (r) => this.select(r.which, { keep: true }));
    this.tab = new ResultTab(store, this);
    this.downloads = new ResultDownloads(store, this.player, save);
    this.player.onFrame = (frame, fraction) => {
      this.plots.moveCursor(frame.crank_deg);
      this.fab?.frame(fraction);
    };
    els.design.addEventListener('click', () => this.run());
    this.designTitle = els.design.title;
    els.cancel.addEventListener('click', () => this.cancel());
    els.paths.addEventListener('change', () => this.store.setUi({ paths: els.paths.checked }));
    els.dims.addEventListener('change', () => this.store.setUi({ dimensions: els.dims.checked }));
    els.live.addEventListener('change', () => {
      this.store.setUi({ live: els.live.checked });
      this.store.hint(els.live.checked
        ? 'Live: drag a numbered pose (or its round handle) and the linkage is redesigned as you go.'
        : 'Live redesign is off.');
    });
    els.show.addEventListener('click', () => this.enter());
  }

  get result() {
    return this.store.result;
  }

  /** True when the shown design was made for the drawing as it is now. */
  fresh() {
    const r = this.result;
    return !!r && r.key === geometryKey(this.store.scene);
  }

  /** Shows the animation (when there is a fresh design). */
  enter() {
    if (!this.fresh() || !this.result?.analysis) return;
    this.store.setUi({ showResult: true, selection: null });
    this.player.setPlaying(true);
  }

  /** Keeps the canvas and the player in step with the state (called on every change). */
  sync() {
    // In live mode the last design stays up while the next one is computed for the edited poses.
    const current = this.fresh() || (this.store.ui.live && this.live.liveBusy);
    const show = !!this.store.ui.showResult && current && !!this.result?.analysis;
    this.canvas.resultShown = show;
    this.els.player.hidden = !show;
    this.els.show.hidden = show || !this.fresh() || !this.result?.analysis;
    if (!show) this.player.setPlaying(false);
    this.fab?.sync(show);
    // While a design runs, its progress bar and Cancel take the Design button's place.
    this.els.design.hidden = !!this.controller;
    const nothingMoves = this.store.scene.moving_bodies.length === 0;
    this.els.design.disabled = nothingMoves;
    this.els.design.title = nothingMoves ? 'Draw a moving body first: a linkage needs something to move' : this.designTitle;
  }

  /** The Design button: streams progress, then shows the design. */
  async run() {
    if (this.controller || this.store.scene.moving_bodies.length === 0) return;
    const scene = toFile(this.store.scene);
    const key = geometryKey(this.store.scene);
    const controller = new AbortController();
    this.controller = controller;
    // A design answers the scene it was asked for: another scene opened meanwhile drops it.
    const epoch = this.epoch;
    this.error = null;
    this.progress({ fraction: 0, text: 'Starting…' });
    this.sync();
    try {
      const request = { scene, print_settings: savedPrintSettings() };
      const design = await api.designStream(request, (event) => this.onEvent(event), controller.signal);
      if (epoch !== this.epoch) return;
      if (design) {
        this.store.setResult(newResult({ design, scene, key, warnings: this.warnings }));
        await this.select(null);
        if (epoch !== this.epoch) return;
        this.store.setUi({ tab: 'result' });
        if (design.status === 'ok') {
          this.fitView();
          const checked = parseBuild(design.build?.checked);
          this.store.hint(design.build?.buildable === false
            ? `Designed, but it cannot be printed at ${checked?.kind === 'model' ? checked.scale : design.build.checked}: the Result tab says why and what to do.`
            : `Done. Best design: ${mechanismName(design.mechanism)}. Press Pause or drag the slider to study it; try an alternative on the right.`);
          this.verify();
        } else {
          this.store.hint('No linkage found: the Result tab says why and what to change.');
        }
      } else {
        this.store.hint('Design cancelled.');
      }
    } catch (e) {
      if (epoch !== this.epoch) return;
      const { message, issues } = api.errorOf(e);
      this.error = { message, issues, scene: JSON.stringify(scene) };
      this.store.setUi({ tab: 'result' });
      this.store.hint(issues.length ? 'Cannot design this yet: the Result tab lists what to change.' : `Cannot design: ${message}`);
    } finally {
      if (this.controller === controller) {
        this.controller = null;
        this.progress(null);
      }
      this.sync();
      this.store.changed('result');
    }
  }

  cancel() {
    this.controller?.abort();
  }

  /**
   * Forgets the design and any error (a new scene was opened); a design, a live redesign or parts
   * still being made for the scene before are stopped, and what they answer is dropped.
   */
  clear() {
    this.epoch += 1;
    this.controller?.abort();
    this.controller = null;
    this.progress(null);
    this.live.forget();
    this.fab?.forget();
    this.store.setResult(null);
    this.error = null;
    this.player.setPlaying(false);
    this.store.changed('result');
  }

  /**
   * The running design's progress, as the server tells it.
   * @param {StreamEvent} event
   */
  onEvent(event) {
    if (event.name === 'accepted') this.warnings = event.data.warnings || [];
    if (event.name === 'queued') this.progress({ fraction: 0, text: 'Waiting for the server (another design is running)…' });
    if (event.name === 'started') this.progress({ fraction: 0, text: 'Starting…' });
    if (event.name === 'progress') {
      const data = event.data;
      const pct = Math.round(data.fraction * 100);
      const best = data.best_cost == null ? '' : ` · best cost ${data.best_cost.toFixed(3)}`;
      this.progress({ fraction: data.fraction, text: `${STAGES[data.stage] || data.stage} (${familyLabel(this.store, data.mechanism)}) ${pct}%${best}` });
    }
  }

  /**
   * Shows the progress bar at `p` (its fraction done and what it says), or hides it (null).
   * @param {{fraction: number, text: string} | null} p
   */
  progress(p) {
    const { job, jobFill, jobText } = this.els;
    job.hidden = !p;
    if (!p) return;
    jobFill.style.width = `${Math.round(p.fraction * 100)}%`;
    jobText.textContent = p.text;
  }

  /**
   * Shows mechanism `which` (null: the design itself) of the current result; `analysis`, its motion
   * analysis when it came with the design; with `keep`, the animation stays where it was (a live
   * redesign, a mass weighed anew) and so does the selection.
   * @param {number | null} which
   * @param {{keep?: boolean, analysis?: Analysis | null}} [options]
   */
  async select(which, { keep = false, analysis = null } = {}) {
    const r = this.result;
    if (!r) return;
    this.store.showMechanism(which);
    const d = r.design;
    this.plots.forget();
    if (d.status !== 'ok' || !r.mechanism) {
      this.store.changed('result');
      return;
    }
    try {
      const before = this.player.frameCount();
      const got = analysis || await api.simulate(r.scene, d, which);
      // Another design (or mechanism) shown meanwhile: this analysis is not for it.
      if (!this.store.answerResult(r, which, { analysis: got })) return;
      const heldPose = this.live.heldPose;
      const held = keep && heldPose != null ? got.poses?.[heldPose] : null;
      if (held) {
        this.player.goTo(held.frame);
      } else if (keep && before > 1) {
        // The same place along the motion, in the new design's frames.
        this.player.goTo(Math.min((this.player.pos / (before - 1)) * (got.frames.length - 1), got.frames.length - 1));
      } else {
        this.player.goTo(0, { fromStart: true });
      }
      // A live result arrives while a pose is being dragged: that drag keeps its pose.
      this.store.setUi(keep ? { showResult: true } : { showResult: true, selection: null });
      this.sync();
      this.player.drawFrame();
      this.player.setPlaying(!held);
    } catch (e) {
      if (!this.store.isShown(r, which)) return;
      this.error = api.errorOf(e);
    }
    this.store.changed('result');
  }

  /**
   * Checks the mechanism shown independently (the server's verifier). The verifier reads a design's own
   * mechanism only, so an alternative is checked as the design of a file of its own.
   */
  async verify() {
    const r = this.result;
    if (!r) return;
    const which = r.which;
    /** @type {import('./api.js').CheckAnswer} */
    let answer;
    try {
      answer = await api.check(r.scene, designShown(r.design, which));
    } catch (e) {
      answer = { ok: false, violations: [{ constraint: 'check', message: api.errorOf(e).message }] };
    }
    // Dropped when another design or mechanism is shown by now.
    this.store.answerResult(r, which, { verified: answer });
  }
}
