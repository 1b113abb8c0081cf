// @ts-check
// The Result tab's analysis of the mechanism shown: the transmission angles and the torque over the
// motion (with cursors that follow the animation), the masses the torque weighs (editable for a
// full-size build), the counterbalance springs, the error at each pose and the loops.

import { DEFAULT_BUILD, parseBuild } from './build.js';
import { errorPlot, loopList, torquePlot, transmissionPlot } from './plots.js';
import { html } from './svg.js';

/**
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./store.js').Result} Result
 * @typedef {import('./build.js').Build} Build
 * @typedef {import('./plots.js').CursorPlot} CursorPlot
 * @typedef {import('./springs-panel.js').SpringsPanel} SpringsPanel
 */

/** A mass in kilograms to three figures (a printed part weighs grams, a bed tens of kilograms). @type {(kg: number) => string} */
const kilograms = (kg) => String(Number(kg.toPrecision(3)));

/** A model's scale (`A:B` or `auto`), or undefined for a full-size build or none. @type {(b: Build | null) => string | undefined} */
const scaleOf = (b) => (b?.kind === 'model' ? b.scale : undefined);

export class ResultPlots {
  /**
   * The analysis of the design `store` shows; `springs` is the springs section, `reweigh(r)` shows
   * result `r`'s mechanism again with its masses weighed anew.
   * @param {Store} store
   * @param {SpringsPanel} springs
   * @param {(r: Result) => Promise<void>} reweigh
   */
  constructor(store, springs, reweigh) {
    this.store = store;
    this.springs = springs;
    this.reweigh = reweigh;
    /** @type {CursorPlot | null} */
    this.transmission = null;
    /** @type {CursorPlot | null} */
    this.torque = null;
  }

  /** Another mechanism is shown: the plots drawn were of the one before. */
  forget() {
    this.transmission = null;
    this.torque = null;
  }

  /**
   * Moves the plots' cursors to crank angle `crankDeg` (the animation's frame).
   * @param {number} crankDeg
   */
  moveCursor(crankDeg) {
    this.transmission?.moveCursor(crankDeg);
    this.torque?.moveCursor(crankDeg);
  }

  /**
   * The analysis section of the Result tab for result `r`, whose motion is analysed.
   * @param {HTMLElement} host
   * @param {Result} r
   * @param {import('./api.js').Analysis} a  its analysis
   */
  render(host, r, a) {
    this.transmission = transmissionPlot(a);
    host.append(html('h3', { text: 'Transmission angles over the motion' }), this.transmission.element);
    this.torque = a.torque ? torquePlot(a, a.torque, r.balance) : null;
    if (this.torque) {
      host.append(html('h3', { text: 'Torque to drive the crank' }), this.torque.element, this.massTable(r, a));
      this.springs.render(host, r);
    }
    host.append(html('h3', { text: 'Error at each pose' }), errorPlot(a, r.scene));
    host.append(html('h3', { text: 'Loops' }), loopList(a));
  }

  /**
   * Each moving body's mass, as the torque weighs it. A printed model's bodies weigh what their print
   * does at the model's scale (the real object's mass does not count); a full-size build's weigh the
   * scene's `mass_kg`, editable here (empty: its material's weight), and the torque is computed again
   * at once.
   * @param {Result} r
   * @param {import('./api.js').Analysis} a  its analysis
   */
  massTable(r, a) {
    const parts = a.torque?.parts || [];
    const build = parseBuild(r.scene.build ?? DEFAULT_BUILD);
    const material = build?.kind === 'full' ? build.material : null;
    /** @type {(i: number) => {mass_kg: number} | undefined} */
    const weighed = (i) => {
      const part = r.mechanism?.parts.find((p) => p.kind === 'body' && p.body === i);
      return parts.find((p) => p.name === part?.name);
    };
    const rows = r.scene.moving_bodies.map((body, i) => {
      const mass = weighed(i)?.mass_kg;
      if (material === null) {
        return html('tr', {}, [html('th', { text: body.name }), html('td', { 'data-printed-mass': i, text: mass === undefined ? '–' : `${kilograms(mass)} kg` })]);
      }
      /** @param {import('./svg.js').On<HTMLInputElement>} e */
      const change = (e) => {
        const text = e.currentTarget.value.trim(), v = Number(text);
        if (text !== '' && !(Number.isFinite(v) && v > 0 && v <= 1e5)) {
          this.store.hint('A mass is a number of kilograms, more than 0 and at most 100000; leave it empty to weigh the body in its material.');
          return;
        }
        // The design stays (a mass changes no geometry): its torque is weighed again, and springs
        // found for the old masses are dropped (the status line says so).
        this.store.setBodyMass(r, i, text === '' ? null : v);
        const hadSprings = !!r.balance;
        this.reweigh(r).then(() => this.store.hint(`${body.name} weighs ${text === '' ? 'what its material does' : `${v} kg`} now: the torque is weighed again${hadSprings ? '; the springs were for the old masses, so press Suggest springs again' : ''}.`));
      };
      return html('tr', {}, [
        html('th', { text: body.name }),
        // Empty, the field shows what the body weighs in its material: the number alone, so that it
        // fits (the note below names the material).
        html('td', {}, [html('input', {
          type: 'number', min: '0', step: 'any', 'data-mass': i, 'aria-label': `mass of ${body.name}, kg`,
          value: body.mass_kg ?? '', placeholder: mass === undefined ? '' : kilograms(mass),
          title: `Empty: ${body.name} weighs ${mass === undefined ? 'what it does' : `${kilograms(mass)} kg`} in ${material}`,
          onchange: change,
        }), ' kg']),
      ]);
    });
    // The scale the model is weighed at: the one the design was checked at (an auto scale decided).
    const checked = scaleOf(parseBuild(r.design.build?.checked)) ?? scaleOf(build);
    const note = material !== null
      ? `The real masses: type a body’s, or leave it empty to weigh it in ${material} (the grey number).`
      : `As printed${checked && checked !== 'auto' ? ` at ${checked}` : ''}: a printed model weighs what its parts do. A body’s real mass counts when it is built full size (Settings › Build).`;
    return html('div', {}, [
      html('table', { class: 'masses' }, [html('tr', {}, [html('th', { text: 'Body' }), html('th', { text: 'Mass' })]), ...rows]),
      html('p', { class: 'note', 'data-masses': material !== null ? 'real' : 'printed', text: note }),
    ]);
  }
}
