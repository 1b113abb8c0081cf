// @ts-check
// Labels on the canvas that must stay readable: each, in order of importance, takes the first of the
// places offered to it that is on the canvas and covers no label placed before it and no mark that
// must be seen; one with no such place is hidden. A label keeps the place it had last time while that is free, so
// labels do not jump about as the linkage moves.

/** Room kept between two labels, pixels. */
const GAP = 2;

/**
 * @typedef {{x: number, y: number, w: number, h: number}} Box  A box on the screen, pixels.
 * @typedef {{element: SVGElement, key: string, box: Box, shifts: number[][]}} Label
 *   A label as drawn (`box`, where it is) with the shifts `[dx, dy]` it may be moved by, best first.
 */

/** @type {(a: Box, b: Box) => boolean} */
const overlap = (a, b) =>
  a.x < b.x + b.w + GAP && b.x < a.x + a.w + GAP && a.y < b.y + b.h + GAP && b.y < a.y + a.h + GAP;

/** @type {(a: Box, area: Box) => boolean} */
const inside = (a, area) => a.x >= area.x && a.y >= area.y && a.x + a.w <= area.x + area.w && a.y + a.h <= area.y + area.h;

/**
 * Places `labels` (most important first) in `area` among the `marks` (boxes they must not cover):
 * moves each to the first free place of its shifts, trying first the one it took before (`previous`,
 * keys to shift indices), and hides each that has none. Returns the shift index each label took.
 * @param {Label[]} labels
 * @param {Box} area
 * @param {Box[]} marks
 * @param {Map<string, number>} [previous]
 * @returns {Map<string, number>}
 */
export function placeLabels(labels, area, marks, previous = new Map()) {
  const taken = [...marks];
  const chosen = new Map();
  for (const label of labels) {
    const last = previous.get(label.key);
    const order = label.shifts.map((_, i) => i);
    if (last !== undefined && last < order.length) order.unshift(...order.splice(last, 1));
    const free = order.find((i) => {
      const [dx, dy] = label.shifts[i];
      const box = { ...label.box, x: label.box.x + dx, y: label.box.y + dy };
      return inside(box, area) && !taken.some((t) => overlap(box, t));
    });
    if (free === undefined) {
      label.element.setAttribute('display', 'none');
      continue;
    }
    const [dx, dy] = label.shifts[free];
    label.element.removeAttribute('display');
    if (dx || dy) label.element.setAttribute('transform', `translate(${dx},${dy})`);
    else label.element.removeAttribute('transform');
    taken.push({ ...label.box, x: label.box.x + dx, y: label.box.y + dy });
    chosen.set(label.key, free);
  }
  return chosen;
}

/**
 * Shifts that keep a label beside its place: as drawn, then a line up or down, then two.
 * @param {Box} box
 * @returns {number[][]}
 */
export function besideShifts(box) {
  const h = box.h + GAP;
  return [[0, 0], [0, -h], [0, h], [0, -2 * h], [0, 2 * h]];
}

/**
 * A pose's label, drawn to the right of the pose's number (`reach` pixels from its centre to the
 * label's start): there, or on the left, each also a line up or down.
 * @param {Box} box
 * @param {number} reach
 * @returns {number[][]}
 */
export function tagShifts(box, reach) {
  const h = box.h + GAP, left = -(box.w + 2 * reach);
  return [[0, 0], [left, 0], [0, -h], [0, h], [left, -h], [left, h]];
}
