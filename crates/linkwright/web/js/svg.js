// @ts-check
// Building SVG and HTML elements without string concatenation (names and numbers from files never
// become markup).

const SVG_NS = 'http://www.w3.org/2000/svg';

/**
 * An event on an element, which its listener was added to (`currentTarget`).
 * @template {Element} E
 * @template {Event} [V=Event]
 * @typedef {V & {currentTarget: E}} On
 */

/**
 * An HTML element's attributes: `text` sets its text, `on…` functions become listeners (each given its
 * event, with the element as `currentTarget`), `value` sets a field's value, `true` is an attribute
 * without a value, and `null`, `undefined` and `false` leave one out.
 * @template {Element} E
 * @typedef {{
 *   text?: string | number | null,
 *   onclick?: (e: On<E, MouseEvent>) => void,
 *   onchange?: (e: On<E>) => void,
 *   oninput?: (e: On<E>) => void,
 *   onkeydown?: (e: On<E, KeyboardEvent>) => void,
 *   [attribute: string]: unknown,
 * }} Attributes
 */

/** Children of an element: nodes and text; null and undefined are left out. @typedef {(Node | string | null | undefined)[]} Children */

/**
 * An SVG element with attributes and children.
 * @template {keyof SVGElementTagNameMap} K
 * @param {K} tag
 * @param {Record<string, unknown>} [attrs]
 * @param {Children} [children]
 * @returns {SVGElementTagNameMap[K]}
 */
export function svg(tag, attrs = {}, children = []) {
  const e = document.createElementNS(SVG_NS, tag);
  setAttrs(e, attrs);
  for (const c of children) if (c) e.append(c);
  return e;
}

/**
 * An HTML element with attributes (see `Attributes`) and children.
 * @template {keyof HTMLElementTagNameMap} K
 * @param {K} tag
 * @param {Attributes<HTMLElementTagNameMap[K]>} [attrs]
 * @param {Children} [children]
 * @returns {HTMLElementTagNameMap[K]}
 */
export function html(tag, attrs = {}, children = []) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === 'text') e.textContent = String(v);
    else if (k.startsWith('on') && typeof v === 'function') e.addEventListener(k.slice(2), /** @type {EventListener} */ (v));
    else if (k === 'value' && 'value' in e) e.value = String(v);
    else e.setAttribute(k, v === true ? '' : String(v));
  }
  for (const c of children) if (c !== null && c !== undefined) e.append(c);
  return e;
}

/**
 * Sets attributes of `e` (`text` sets its text; null, undefined and false are left out).
 * @template {Element} E
 * @param {E} e
 * @param {Record<string, unknown>} attrs
 * @returns {E}
 */
export function setAttrs(e, attrs) {
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === 'text') e.textContent = String(v);
    else e.setAttribute(k, String(v));
  }
  return e;
}

/** SVG `points` text of a list of [x, y]. @type {(pts: import('./geom.js').Point[]) => string} */
export const points = (pts) => pts.map((p) => `${p[0].toFixed(3)},${p[1].toFixed(3)}`).join(' ');

/**
 * Removes every child of `e`.
 * @template {Element} E
 * @param {E} e
 * @returns {E}
 */
export function clear(e) {
  while (e.firstChild) e.firstChild.remove();
  return e;
}
