// @ts-check
// The Result tab's counterbalance springs: the Suggest springs button, the request for the springs
// that take the weight off the crank, and the springs found, in words (springs.js) and on the canvas.

import * as api from './api.js';
import { NO_SPRING, springCut, springList } from './springs.js';
import { html } from './svg.js';

/**
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./store.js').Result} Result
 */

export class SpringsPanel {
  /**
   * Suggests springs for the design `store` shows; `redraw()` draws the animation frame again (the
   * springs are drawn on it).
   * @param {Store} store
   * @param {() => void} redraw
   */
  constructor(store, redraw) {
    this.store = store;
    this.redraw = redraw;
    /** A request for springs is on its way. */
    this.balancing = false;
  }

  /**
   * The springs section of the Result tab for result `r`: the springs found, or the button to ask.
   * @param {HTMLElement} host
   * @param {Result} r
   */
  render(host, r) {
    host.append(html('h3', { text: 'Counterbalance springs' }));
    if (r.balance) host.append(springList(r.balance, this.store.scene.units || 'mm', { scene: this.store.scene, mechanism: r.mechanism }));
    else {
      host.append(html('button', {
        text: 'Suggest springs', 'data-action': 'springs', disabled: this.balancing ? '' : null,
        title: 'one or two springs that take the weight off the crank: their rate, length and where to hook them',
        onclick: () => this.suggestSprings(),
      }));
    }
  }

  /** Asks for the springs that balance the mechanism shown; they are drawn and listed when they come. */
  async suggestSprings() {
    const r = this.store.result;
    if (!r?.analysis || this.balancing) return;
    const which = r.which;
    this.balancing = true;
    this.store.hint('Looking for counterbalance springs…');
    try {
      const answer = await api.balance(r.scene, r.design, which);
      // Springs for a mechanism no longer shown are dropped.
      if (this.store.answerResult(r, which, { balance: answer })) {
        this.store.hint(answer.springs.length
          ? `Springs found: the peak torque drops by ${springCut(answer)}%.`
          : NO_SPRING);
      }
    } catch (e) {
      this.store.hint(`Cannot suggest springs: ${api.errorOf(e).message}`);
    } finally {
      this.balancing = false;
      this.redraw();
      this.store.changed('result');
    }
  }
}
