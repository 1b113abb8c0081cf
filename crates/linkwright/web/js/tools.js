// @ts-check
// What the pointer and the keyboard do on the canvas: select and move shapes and poses, edit vertices,
// rotate poses, draw rectangles, polygons and ellipses, pan and zoom.

import { formatDimension, GRAB_PX } from './canvas.js';
import { dist, ellipse, outlineProblem, rectangle, segmentDistance, smoothThrough, sub } from './geom.js';
import * as S from './scene.js';

/**
 * @typedef {import('./geom.js').Point} Point
 * @typedef {import('./geom.js').Pose} Pose
 * @typedef {import('./geom.js').Polygon} Polygon
 * @typedef {import('./geom.js').OutlineProblem} OutlineProblem
 * @typedef {import('./store.js').Store} Store
 * @typedef {import('./store.js').UiState} UiState
 * @typedef {import('./store.js').Tool} Tool
 * @typedef {import('./scene.js').ShapeKind} ShapeKind
 * @typedef {import('./scene.js').Selection} Selection
 * @typedef {import('./canvas.js').Canvas} Canvas
 * @typedef {import('./viewport.js').Viewport} Viewport
 */

/**
 * What the tools ask of the rest of the app.
 * @typedef {object} ToolActions
 * @property {() => void} redraw  draws the canvas again (a change of the view or the preview only)
 * @property {() => void} leaveResult  back from the design shown to the poses to edit
 * @property {() => boolean} liveResult  a design is shown and redesigned live as a pose moves
 * @property {() => void} poseEdited  a pose moved (live mode designs again)
 * @property {() => void} poseReleased  a pose dragged was let go
 * @property {(name: string) => boolean} beginJointDrag  starts moving a joint of the design shown (false: none shown)
 * @property {(w: Point) => void} moveJoint
 * @property {() => void} endJointDrag
 * @property {() => void} deleteSelection
 * @property {(w: Point) => void} [pointer]  where the pointer is, world coordinates
 */

/**
 * A drag under way: panning the view, spanning a box, moving a corner, a joint, a shape or turning a pose.
 * @typedef {{type: 'pan', last: Point} | {type: 'box', start: Point} | {type: 'vertex', v: number} | {type: 'joint'}
 *   | {type: 'move', start: Point, applied: Point} | {type: 'rotate'} | {type: 'stroke', body: number, points: Point[]}
 *   | {type: 'reshape', body: number, start: Point, points: Point[], poses: Pose[], grab: number}} Drag
 */

/** @type {Record<ShapeKind, string>} */
const KIND_NAMES = {
  fixed: 'a fixed body (a part that never moves)',
  moving: 'a moving body (a part the linkage will move)',
  region: 'the linkage region (where the joints should go)',
  avoid: 'an avoid region (no link may enter it)',
};

/** @type {Record<Tool, string>} */
export const TOOL_HINTS = {
  select: 'Select: click a shape to select it, drag to move it (a moving body: its current pose). Drag a square handle to move a corner, double-click an edge to add one, Delete removes. Drag a drawn path to bend it. Drag empty space to pan, scroll to zoom.',
  pan: 'Pan: drag to move the view, scroll (or + and −) to zoom. Press F to fit everything.',
  rect: 'Rectangle: drag to draw {kind}.',
  ellipse: 'Ellipse: drag to draw {kind}.',
  polygon: 'Polygon: click to place corners of {kind}; click the first corner, double-click or press Enter to close. Backspace removes the last corner, Esc cancels.',
  path: 'Path: press on the point of a moving body that should follow a curve (a foot, a pen tip), then draw the curve without letting go; or click that point, then click points along the curve. End where you started for a loop the crank goes round.',
};

/** A stroke's points are kept this far apart on screen, pixels. */
const STROKE_STEP_PX = 3;
/** A stroke ending this close to its start (screen pixels, or this share of its size) is a loop. */
const LOOP_CLOSE_PX = 16;
const LOOP_CLOSE_SHARE = 0.08;
/** Points of the smooth curve between two clicked points of a path. */
const CLICKED_PATH_STEPS = 12;
const CLICKED_PATH_HINT = 'Path by points: click points along the curve. Click the first point to close a loop; double-click or press Enter to end an open path. Backspace removes the last point, Esc cancels.';

/** A drawn shape narrower than this on screen is refused, pixels: as a rectangle or an ellipse dragged
 * less far, it would be a line, no part. */
const MIN_SHAPE_PX = 4;

/** What the status line says when the corners placed cannot be the shape: what is wrong, and what to
 * do about it (the corners stay, so the person goes on from them).
 * @param {OutlineProblem} problem
 * @param {ShapeKind} kind
 * @param {string} units
 */
function outlineHint(problem, kind, units) {
  const what = kind === 'fixed' || kind === 'moving' ? 'A body' : 'A region';
  const needs = `${what} needs at least three corners that are not on one line`;
  const more = 'Backspace removes the last corner, Esc cancels';
  if (problem.kind === 'few') return `${needs}: click more corners, then close it. (${more}.)`;
  if (problem.kind === 'flat') {
    const how = problem.width > 0 ? `these are almost on one line (${formatDimension(problem.width)} ${units} across)` : 'these are on one line';
    return `${needs}: ${how}. Click a corner away from the line, then close it. (${more}.)`;
  }
  const [i, j] = problem.sides;
  return `The outline crosses itself (side ${i + 1} crosses side ${j + 1}): place the corners in order around the shape. (${more}.)`;
}

/**
 * The status line's words for the tool chosen (and what it draws).
 * @param {UiState} ui
 */
export function toolHint(ui) {
  return TOOL_HINTS[ui.tool].replace('{kind}', KIND_NAMES[ui.kind]);
}

/**
 * The element under the pointer, or its nearest ancestor, that matches `selector`.
 * @param {Event} e
 * @param {string} selector
 * @returns {HTMLElement | SVGElement | null}
 */
function targetOf(e, selector) {
  const found = e.target instanceof Element ? e.target.closest(selector) : null;
  return found instanceof HTMLElement || found instanceof SVGElement ? found : null;
}

export class Tools {
  /**
   * Listens to the pointer on the canvas `root`.
   * @param {SVGSVGElement} root
   * @param {Store} store
   * @param {Canvas} canvas
   * @param {Viewport} view
   * @param {ToolActions} actions
   */
  constructor(root, store, canvas, view, actions) {
    this.root = root;
    this.store = store;
    this.canvas = canvas;
    this.view = view;
    this.actions = actions;
    /** @type {Drag | null} */
    this.drag = null;
    /** @type {Point[]} the corners of the polygon being drawn */
    this.polygon = [];
    /** @type {{body: number, points: Point[]} | null} a path being drawn by clicked points, from a point of `body` */
    this.clicked = null;
    this.space = false; // Space is held: a drag pans
    this.spacePanned = false; // and one did, so letting Space go does not also play or pause
    root.addEventListener('pointerdown', (e) => this.down(e));
    root.addEventListener('pointermove', (e) => this.move(e));
    root.addEventListener('pointerup', (e) => this.up(e));
    root.addEventListener('pointercancel', (e) => this.up(e));
    root.addEventListener('dblclick', (e) => this.dblclick(e));
    root.addEventListener('wheel', (e) => this.wheel(e), { passive: false });
    root.addEventListener('contextmenu', (e) => e.preventDefault());
  }

  /**
   * The pointer's place on the canvas, pixels.
   * @param {MouseEvent} e
   * @returns {Point}
   */
  screen(e) {
    const r = this.root.getBoundingClientRect();
    return [e.clientX - r.left, e.clientY - r.top];
  }

  /**
   * The world point under the pointer, on the grid when snapping is on (Alt turns it off).
   * @param {MouseEvent} e
   * @returns {Point}
   */
  snapped(e) {
    const w = this.view.toWorld(this.screen(e));
    if (!this.store.ui.snap || e.altKey) return w;
    const step = this.view.gridStep();
    return [Math.round(w[0] / step) * step, Math.round(w[1] / step) * step];
  }

  /**
   * Chooses the tool a drag on the canvas uses.
   * @param {Tool} tool
   */
  setTool(tool) {
    this.cancelDrawing();
    this.store.setUi({ tool });
    this.store.hint(toolHint(this.store.ui));
  }

  /** Drops the polygon or clicked path being drawn. */
  cancelDrawing() {
    this.polygon = [];
    this.clicked = null;
    this.canvas.preview = null;
    this.actions.redraw();
  }

  /** @param {PointerEvent} e */
  down(e) {
    this.root.setPointerCapture?.(e.pointerId);
    const s = this.screen(e);
    const ui = this.store.ui;
    if (e.button === 1 || e.button === 2 || this.space || ui.tool === 'pan') {
      if (this.space) this.spacePanned = true;
      this.drag = { type: 'pan', last: s };
      return;
    }
    if (e.button !== 0) return;
    if (ui.tool === 'select') return this.selectDown(e, s);
    this.actions.leaveResult();
    if (ui.tool === 'path') {
      if (this.clicked) return this.clickPathPoint(s);
      const hit = targetOf(e, '[data-kind=moving]');
      if (!hit) {
        this.store.hint('Press on a moving body, at the point that should follow the curve, then draw the curve.');
        return;
      }
      this.drag = { type: 'stroke', body: Number(hit.dataset.index), points: [this.view.toWorld(s)] };
      return;
    }
    if (ui.tool === 'rect' || ui.tool === 'ellipse') {
      this.drag = { type: 'box', start: this.snapped(e) };
      return;
    }
    if (ui.tool === 'polygon') {
      const w = this.snapped(e);
      const first = this.polygon[0];
      // Clicking the first corner closes the outline (with too few corners, the hint says so).
      if (first && this.polygon.length >= 2 && dist(this.view.toScreen(first), s) <= GRAB_PX) {
        this.finishPolygon();
        return;
      }
      const last = this.polygon[this.polygon.length - 1];
      if (!last || dist(this.view.toScreen(last), s) > 2) this.polygon.push(w);
      this.canvas.preview = { points: this.polygon, cursor: w, kind: ui.kind, closed: false };
      this.actions.redraw();
    }
  }

  /**
   * A press with the select tool at screen point `s`: on a handle, a joint, a shape, or empty space.
   * @param {PointerEvent} e
   * @param {Point} s
   */
  selectDown(e, s) {
    const ui = this.store.ui;
    const handle = targetOf(e, '[data-handle]');
    if (handle && ui.selection) {
      if (handle.dataset.handle === 'vertex') {
        const v = Number(handle.dataset.vertex);
        this.store.setUi({ selection: { ...ui.selection, vertex: v } });
        this.store.begin('move a corner');
        this.drag = { type: 'vertex', v };
      } else if (handle.dataset.handle === 'rotate') {
        this.store.begin('rotate a pose');
        this.drag = { type: 'rotate' };
      }
      return;
    }
    const path = targetOf(e, '.drawn-path');
    const reshaped = path && this.store.scene.moving_bodies[Number(path.dataset.body)];
    if (path && reshaped?.path) {
      // The drawn path bends where it is grabbed, less and less farther along it; in live mode the
      // linkage shown stays and is redesigned as the path bends.
      if (!this.actions.liveResult()) this.actions.leaveResult();
      const w = this.view.toWorld(s);
      const points = reshaped.path.points.map((p) => /** @type {Point} */ ([...p]));
      const grab = S.nearestPathPoint(this.store.scene, Number(path.dataset.body), w);
      this.store.begin('reshape the path');
      this.drag = { type: 'reshape', body: Number(path.dataset.body), start: w, points, poses: reshaped.poses.map((p) => /** @type {Pose} */ ([...p])), grab };
      this.store.hint('Reshaping the path: the part near where you grabbed it follows the pointer. Undo (Ctrl+Z) puts it back.');
      return;
    }
    const joint = targetOf(e, '[data-joint]');
    if (joint) {
      // A joint of the design shown moves with the pointer, the linkage judged again as it goes.
      if (this.actions.beginJointDrag(joint.dataset.joint ?? '')) {
        this.drag = { type: 'joint' };
      } else {
        this.store.hint(`Joint ${joint.dataset.joint} of the design: show the design (▶) to move its joints.`);
        this.drag = { type: 'pan', last: s };
      }
      return;
    }
    const shape = targetOf(e, '[data-kind]');
    if (shape) {
      // In live mode the linkage keeps moving while a pose is dragged (and is redesigned).
      if (!(this.actions.liveResult() && shape.dataset.kind === 'moving')) this.actions.leaveResult();
      /** @type {Selection} */
      const sel = { kind: /** @type {ShapeKind} */ (shape.dataset.kind), index: Number(shape.dataset.index) };
      /** @type {Partial<UiState>} */
      const patch = { selection: sel };
      if (shape.dataset.pose !== undefined) patch.pose = Number(shape.dataset.pose);
      this.store.setUi(patch);
      this.store.begin(sel.kind === 'moving' ? `move pose ${(patch.pose ?? ui.pose) + 1}` : 'move a shape');
      this.drag = { type: 'move', start: this.snapped(e), applied: [0, 0] };
      this.store.hint(sel.kind === 'moving'
        ? `Pose ${this.store.ui.pose + 1} of ${this.store.scene.moving_bodies[sel.index].name}: drag to move it, drag the round handle to turn it. The numbered copies are its other poses.`
        : toolHint(ui));
      return;
    }
    this.store.setUi({ selection: null });
    this.drag = { type: 'pan', last: s };
  }

  /** @param {PointerEvent} e */
  move(e) {
    const s = this.screen(e);
    const w = this.view.toWorld(s);
    this.actions.pointer?.(w);
    const d = this.drag;
    const ui = this.store.ui;
    if (!d) {
      if (ui.tool === 'polygon' && this.polygon.length) {
        this.canvas.preview = { points: this.polygon, cursor: this.snapped(e), kind: ui.kind, closed: false };
        this.actions.redraw();
      }
      if (ui.tool === 'path' && this.clicked) {
        this.canvas.preview = { points: this.clicked.points, cursor: w, kind: 'moving', closed: false };
        this.actions.redraw();
      }
      return;
    }
    switch (d.type) {
      case 'pan':
        this.view.pan(s[0] - d.last[0], s[1] - d.last[1]);
        d.last = s;
        this.actions.redraw();
        break;
      case 'box': {
        const end = this.snapped(e);
        const pts = ui.tool === 'rect' ? rectangle(d.start, end) : ellipse(d.start, end);
        this.canvas.preview = { points: pts, kind: ui.kind, closed: true };
        this.actions.redraw();
        break;
      }
      case 'vertex': {
        const sel = ui.selection;
        if (sel) this.store.update((sc) => S.moveVertex(sc, sel, d.v, this.snapped(e), ui.pose));
        break;
      }
      case 'stroke': {
        // Freehand, never snapped: the curve is what the hand draws.
        const last = this.view.toScreen(d.points[d.points.length - 1]);
        if (dist(last, s) >= STROKE_STEP_PX) d.points.push(w);
        this.canvas.preview = { points: d.points, kind: 'moving', closed: false, stroke: true };
        this.actions.redraw();
        break;
      }
      case 'reshape':
        this.store.update((sc) => S.reshapePath(sc, d.body, d.points, d.poses, d.grab, sub(w, d.start)));
        this.actions.poseEdited();
        break;
      case 'joint':
        // Not snapped: a linkage answers to small moves, and a grid step can be too far for it.
        this.actions.moveJoint(w);
        break;
      case 'move': {
        const sel = ui.selection;
        const total = sub(this.snapped(e), d.start);
        const delta = sub(total, d.applied);
        d.applied = total;
        if (sel && (delta[0] || delta[1])) {
          this.store.update((sc) => S.translate(sc, sel, delta, ui.pose));
          if (sel.kind === 'moving') this.actions.poseEdited();
        }
        break;
      }
      case 'rotate': {
        const sel = ui.selection;
        if (!sel) break;
        const b = this.store.scene.moving_bodies[sel.index];
        const pose = b.poses[ui.pose];
        const v = sub(w, [pose[0], pose[1]]);
        let deg = (Math.atan2(v[1], v[0]) * 180) / Math.PI - 90;
        const step = e.shiftKey ? 15 : ui.snap && !e.altKey ? 5 : 0;
        if (step) deg = Math.round(deg / step) * step;
        // Keep the angle continuous with the previous value (poses may wind past ±180°).
        const prev = pose[2];
        deg += 360 * Math.round((prev - deg) / 360);
        this.store.update((sc) => S.setPoseAngle(sc, sel.index, ui.pose, deg));
        this.actions.poseEdited();
        this.store.hint(`Pose ${ui.pose + 1}: ${deg.toFixed(1)}° (Shift: steps of 15°, Alt: free)`);
        break;
      }
      default:
        break;
    }
  }

  /** @param {PointerEvent} e */
  up(e) {
    const d = this.drag;
    this.drag = null;
    if (!d) return;
    if (d.type === 'box') {
      const end = this.snapped(e);
      const a = this.view.toScreen(d.start), b = this.view.toScreen(end);
      this.canvas.preview = null;
      if (Math.abs(a[0] - b[0]) < 4 || Math.abs(a[1] - b[1]) < 4) {
        this.store.hint('Drag (press, move, release) to draw the shape.');
        this.actions.redraw();
        return;
      }
      const pts = this.store.ui.tool === 'rect' ? rectangle(d.start, end) : ellipse(d.start, end);
      this.addShape(pts);
    } else if (d.type === 'reshape') {
      this.store.end();
      this.actions.poseReleased();
    } else if (d.type === 'vertex' || d.type === 'move' || d.type === 'rotate') {
      this.store.end();
      this.actions.poseReleased();
    } else if (d.type === 'joint') {
      this.actions.endJointDrag();
    } else if (d.type === 'stroke') {
      this.canvas.preview = null;
      // A click rather than a stroke begins a path drawn by clicked points.
      if (d.points.length < 3) {
        this.clicked = { body: d.body, points: [d.points[0]] };
        this.canvas.preview = { points: this.clicked.points, cursor: null, kind: 'moving', closed: false };
        this.actions.redraw();
        this.store.hint(CLICKED_PATH_HINT);
        return;
      }
      this.finishStroke(d.body, d.points);
    }
  }

  /**
   * A click at screen point `s` while a path is drawn by clicked points: on its first point, closes
   * it into a loop; elsewhere, adds a point.
   * @param {Point} s
   */
  clickPathPoint(s) {
    const c = this.clicked;
    if (!c) return;
    const first = this.view.toScreen(c.points[0]);
    if (c.points.length >= 3 && dist(first, s) <= GRAB_PX) {
      this.finishClickedPath(true);
      return;
    }
    const last = this.view.toScreen(c.points[c.points.length - 1]);
    if (dist(last, s) > 2) c.points.push(this.view.toWorld(s));
    this.canvas.preview = { points: c.points, cursor: null, kind: 'moving', closed: false };
    this.actions.redraw();
  }

  /**
   * Ends the path drawn by clicked points: a smooth curve through them, a loop when `closed`.
   * @param {boolean} closed
   */
  finishClickedPath(closed) {
    const c = this.clicked;
    if (!c) return;
    const least = closed ? 3 : 2;
    if (c.points.length < least) {
      const more = least - c.points.length;
      this.store.hint(`Click ${more} more point${more > 1 ? 's' : ''} along the curve first (Esc cancels).`);
      return;
    }
    this.clicked = null;
    this.canvas.preview = null;
    const curve = smoothThrough(c.points, closed, CLICKED_PATH_STEPS);
    this.finishStroke(c.body, closed ? [...curve, curve[0]] : curve, closed);
  }

  /**
   * A freehand stroke from a point of moving body `body` made its path: a loop when it ends near
   * where it began.
   * @param {number} body
   * @param {Point[]} stroke
   * @param {boolean} [loop]  a loop whatever the gap between its ends (a clicked path closed)
   */
  finishStroke(body, stroke, loop) {
    const screen = stroke.map((p) => this.view.toScreen(p));
    const xs = screen.map((p) => p[0]), ys = screen.map((p) => p[1]);
    const extent = Math.hypot(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys));
    if (stroke.length < 3 || extent < 4 * LOOP_CLOSE_PX) {
      this.store.hint('Draw the curve further: press on the moving body and move without letting go.');
      this.actions.redraw();
      return;
    }
    const gap = dist(screen[0], screen[screen.length - 1]);
    const closed = loop ?? gap <= Math.max(LOOP_CLOSE_PX, LOOP_CLOSE_SHARE * extent);
    const pose = this.store.ui.pose;
    const done = this.store.edit('draw a path', (sc) => S.setPath(sc, body, pose, stroke, closed));
    if (done === false) {
      this.store.hint('A path is followed by a linkage of one moving body: remove the others, or design them in a scene of their own.');
      this.actions.redraw();
      return;
    }
    this.store.setUi({ pose: 0, selection: { kind: 'moving', index: body } });
    this.store.hint(closed
      ? 'Loop drawn: the linkage will carry the point round it once per turn of the crank. Design to see it.'
      : 'Path drawn: the linkage will carry the point from its start to its end. Design to see it.');
  }

  /** @param {MouseEvent} e */
  dblclick(e) {
    const ui = this.store.ui;
    if (ui.tool === 'polygon') {
      if (this.polygon.length) this.finishPolygon();
      return;
    }
    if (ui.tool === 'path') {
      // The double-click's second press added its point again; clickPathPoint skipped it.
      if (this.clicked) this.finishClickedPath(false);
      return;
    }
    const body = ui.tool === 'select' ? this.pathUnder(this.screen(e)) : -1;
    if (body >= 0) {
      // A double-click on the drawn path marks the point there as one to pass exactly, or unmarks it.
      const point = S.nearestPathPoint(this.store.scene, body, this.view.toWorld(this.screen(e)));
      const on = !this.store.scene.moving_bodies[body].path?.exact?.includes(point);
      this.store.edit(on ? 'mark a path point exact' : 'unmark an exact path point', (sc) => S.setExact(sc, body, point, on));
      this.store.hint(on
        ? `Point ${point + 1} of the path is exact: the linkage's tracer must pass it. Double-click it again to free it.`
        : `Point ${point + 1} of the path is free again.`);
      return;
    }
    const sel = ui.selection;
    if (ui.tool !== 'select' || !sel) return;
    const world = this.canvas.selectionWorld();
    if (!world) return;
    const s = this.screen(e);
    /** @type {{d: number, i: number} | null} */
    let best = null;
    for (const [i, p] of world.entries()) {
      const q = world[(i + 1) % world.length];
      const { d } = segmentDistance(s, this.view.toScreen(p), this.view.toScreen(q));
      if (d <= GRAB_PX && (!best || d < best.d)) best = { d, i };
    }
    if (best) {
      const w = this.snapped(e), after = best.i;
      this.store.edit('add a corner', (sc) => S.insertVertex(sc, sel, after, w, ui.pose));
      this.store.setUi({ selection: { ...sel, vertex: after + 1 } });
    }
  }

  /**
   * The moving body whose drawn path passes within grabbing reach of screen point `s`, or -1. (By
   * geometry, not the event's target: a double-click's presses capture the pointer for a drag.)
   * @param {Point} s
   */
  pathUnder(s) {
    const w = this.view.toWorld(s);
    return this.store.scene.moving_bodies.findIndex((b) => !!b.path?.points.length && dist(this.view.toScreen(S.onPath(b.path, w)), s) <= GRAB_PX);
  }

  /** @param {WheelEvent} e */
  wheel(e) {
    e.preventDefault();
    const factor = Math.exp(-e.deltaY * (e.deltaMode === 1 ? 0.05 : 0.0015));
    this.view.zoomAt(this.screen(e), factor);
    this.actions.redraw();
  }

  /** Closes the outline being drawn: adds the shape, or, when its corners cannot be one (too few, on
   * one line or nearly, crossing), keeps them and says in the status line what is wrong and what to do. */
  finishPolygon() {
    // A corner placed twice in a row, or the first placed again to close, counts once.
    const pts = this.polygon.filter((p, i, all) => i === 0 || dist(p, all[i - 1]) > 1e-9);
    if (pts.length > 1 && dist(pts[0], pts[pts.length - 1]) <= 1e-9) pts.pop();
    const problem = outlineProblem(pts, MIN_SHAPE_PX / this.view.k);
    if (problem) {
      this.polygon = pts;
      this.canvas.preview = pts.length ? { points: pts, cursor: null, kind: this.store.ui.kind, closed: false } : null;
      this.actions.redraw();
      this.store.hint(outlineHint(problem, this.store.ui.kind, this.store.scene.units || 'mm'));
      return;
    }
    this.polygon = [];
    this.canvas.preview = null;
    this.addShape(pts);
  }

  /**
   * Adds the shape drawn (world coordinates) as what the drawing tools draw, selected.
   * @param {Polygon} world
   */
  addShape(world) {
    const kind = this.store.ui.kind;
    const sel = this.store.edit(`draw ${kind === 'region' ? 'the linkage region' : `a ${kind} shape`}`, (sc) => S.addShape(sc, kind, world));
    if (!sel) return;
    this.store.setUi({ selection: sel });
    if (kind === 'moving') {
      const body = this.store.scene.moving_bodies[sel.index];
      this.store.setUi({ tool: 'select', pose: body.poses.length - 1 });
      this.store.hint(`Moving body drawn. Pose ${body.poses.length} is a copy: drag it to where the part should end up, and turn it with its round handle. Add poses in between with "Insert pose".`);
    } else if (kind === 'fixed') {
      this.store.hint('Fixed body drawn. Draw more parts, or switch "Draw" to Moving body to draw the part that moves.');
    } else if (kind === 'region') {
      this.store.hint('Linkage region drawn: the joints will be placed in or near it.');
    } else {
      this.store.hint('Avoid region drawn: no link will enter it.');
    }
  }

  /**
   * Keyboard shortcuts on the canvas; returns true when the key was used.
   * @param {KeyboardEvent} e
   */
  key(e) {
    const ui = this.store.ui;
    if (ui.tool === 'path' && this.clicked) {
      const c = this.clicked;
      if (e.key === 'Enter') { this.finishClickedPath(false); return true; }
      if (e.key === 'Escape') { this.cancelDrawing(); return true; }
      if (e.key === 'Backspace') {
        if (c.points.length > 1) c.points.pop();
        this.canvas.preview = { points: c.points, cursor: null, kind: 'moving', closed: false };
        this.actions.redraw();
        return true;
      }
    }
    if (ui.tool === 'polygon' && this.polygon.length) {
      if (e.key === 'Enter') { this.finishPolygon(); return true; }
      if (e.key === 'Escape') { this.cancelDrawing(); return true; }
      if (e.key === 'Backspace') {
        this.polygon.pop();
        const preview = this.canvas.preview;
        this.canvas.preview = this.polygon.length && preview ? { ...preview, points: this.polygon } : null;
        this.actions.redraw();
        return true;
      }
    }
    if ((e.key === 'Delete' || e.key === 'Backspace') && ui.selection) {
      this.actions.deleteSelection();
      return true;
    }
    if (e.key === 'Escape') {
      this.store.setUi({ selection: null });
      return true;
    }
    const sel = ui.selection;
    if (e.key.startsWith('Arrow') && sel) {
      const step = e.shiftKey ? this.view.gridStep() * 10 : this.view.gridStep();
      /** @type {Record<string, Point>} */
      const deltas = { ArrowLeft: [-step, 0], ArrowRight: [step, 0], ArrowUp: [0, step], ArrowDown: [0, -step] };
      const delta = deltas[e.key];
      this.actions.leaveResult();
      this.store.edit('nudge', (sc) => S.translate(sc, sel, delta, ui.pose));
      return true;
    }
    return false;
  }
}
