// @ts-check
// Editing the design shown directly: a joint dragged on the canvas (or typed in the Result tab's
// joint table) goes where it is put, the server simulating and checking the moved linkage as it goes;
// the move is one undo step.

import { poseErrors, reachText } from './accuracy.js';
import * as api from './api.js';
import { newResult } from './store.js';

/**
 * @typedef {import('./geom.js').Point} Point
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./store.js').Result} Result
 * @typedef {import('./canvas.js').Canvas} Canvas
 * @typedef {import('./player.js').Player} Player
 */

/**
 * A joint being moved: its name, the result before the move, the place to ask for next (null: none
 * waiting), whether a place was taken, and whether the drag has ended.
 * @typedef {{name: string, before: Result, target: Point | null, moved: boolean, ended: boolean}} JointDrag
 */

/** `text` with its first letter in lower case, to go on after a colon. @type {(text: string) => string} */
const lowerFirst = (text) => text.charAt(0).toLowerCase() + text.slice(1);

export class JointEditor {
  /**
   * Moves joints of the design `store` shows, drawn on `canvas` and played by `player`.
   * @param {Store} store
   * @param {Canvas} canvas
   * @param {Player} player
   */
  constructor(store, canvas, player) {
    this.store = store;
    this.canvas = canvas;
    this.player = player;
    /** @type {JointDrag | null} */
    this.jointDrag = null;
    /** A request for the moved linkage is on its way. */
    this.editBusy = false;
  }

  /**
   * Starts moving joint `name` of the design shown, if one is shown: the animation goes to the
   * first pose (where a design gives its joints) and waits there.
   * @param {string} name
   */
  beginJointDrag(name) {
    const r = this.store.result;
    if (!this.canvas.showingResult() || !r?.analysis || !r.mechanism?.joints?.[name]) return false;
    this.player.setPlaying(false);
    this.player.goTo(0);
    this.player.drawFrame();
    this.jointDrag = { name, before: r, target: null, moved: false, ended: false };
    this.store.hint(`Joint ${name}: drag it; the linkage is simulated and checked again as it moves (Ctrl+Z undoes).`);
    return true;
  }

  /**
   * The joint being moved goes to world point `w` (at the first pose).
   * @param {Point} w
   */
  moveJoint(w) {
    if (!this.jointDrag) return;
    this.jointDrag.target = w;
    if (!this.editBusy) this.runEdit(this.jointDrag);
  }

  endJointDrag() {
    if (!this.jointDrag) return;
    this.jointDrag.ended = true;
    if (!this.editBusy) this.finishJointDrag();
  }

  /**
   * Moves joints of the design shown (`{name: [x, y]}`), as one undoable step.
   * @param {Record<string, Point>} joints
   */
  async placeJoints(joints) {
    const r = this.store.result;
    if (!r?.mechanism) return;
    const [name] = Object.keys(joints);
    this.jointDrag = { name, before: r, target: joints[name], moved: false, ended: true };
    if (!this.editBusy) await this.runEdit(this.jointDrag);
  }

  /**
   * Asks the server for the moved linkage, one request at a time; a place given meanwhile is sent
   * next (only the newest). Each answer that still makes the motion becomes the design shown (a
   * design of its own, checked); one that does not leaves the last good design up, the joint drawn
   * red where it was asked to go, and the reason in the hint.
   * @param {JointDrag} drag
   */
  async runEdit(drag) {
    this.editBusy = true;
    const base = drag.before;
    while (drag.target) {
      const w = drag.target;
      drag.target = null;
      try {
        const answer = await api.edit(base.scene, base.design, base.which, { [drag.name]: w });
        if (answer.design && answer.analysis) {
          const { mechanism, motion, metrics } = answer.design;
          this.store.setResult({
            ...newResult({ design: answer.design, scene: base.scene, key: base.key, warnings: base.warnings }),
            mechanism, motion, metrics, analysis: answer.analysis,
            verified: { ok: answer.violations.length === 0, violations: answer.violations },
          });
          this.canvas.rejectedJoint = null;
          drag.moved = true;
          const broken = answer.violations[0];
          // Sound, the moved linkage may still miss a pose: the status line says so, as the badge does.
          const errors = poseErrors(answer.design.metrics, answer.analysis, base.scene);
          const place = `Joint ${drag.name} at (${w[0].toFixed(1)}, ${w[1].toFixed(1)})`;
          this.store.hint(broken
            ? `${place}: ${broken.constraint}: ${broken.message}`
            : errors && !errors.reached
              ? `${place}: the linkage works, but ${lowerFirst(reachText(errors, base.scene))}.`
              : `${place}: every hard constraint holds (cost ${answer.design.metrics.cost.toFixed(3)}).`);
        } else {
          const message = answer.rejected?.message ?? 'the linkage cannot follow it there';
          this.canvas.rejectedJoint = { name: drag.name, at: w, message };
          this.store.hint(`Joint ${drag.name} cannot go to (${w[0].toFixed(1)}, ${w[1].toFixed(1)}): ${message}.`);
        }
      } catch (e) {
        this.store.hint(`Cannot move joint ${drag.name}: ${api.errorOf(e).message}`);
      }
      this.player.goTo(0);
      this.player.drawFrame();
      this.store.changed('result');
    }
    this.editBusy = false;
    if (drag.ended) this.finishJointDrag();
  }

  /** The drag has ended and its last answer is in: the move becomes one undo step. */
  finishJointDrag() {
    const drag = this.jointDrag;
    this.jointDrag = null;
    this.canvas.rejectedJoint = null;
    if (drag?.moved) this.store.editResult(`move joint ${drag.name}`, drag.before);
    this.player.drawFrame();
  }
}
