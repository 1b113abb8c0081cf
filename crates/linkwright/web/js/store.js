// @ts-check
// The app's state and its undo history. Every change of the state goes through a method here. The
// scene (the document) changes only through `edit` or a `begin`/`update`/`end` gesture, each of which
// is one undo step; so does a design whose joints the person moved (`editResult`); everything else is
// view state.

/**
 * @typedef {import('./scene.js').Scene} Scene
 * @typedef {import('./scene.js').Selection} Selection
 * @typedef {import('./scene.js').ShapeKind} ShapeKind
 * @typedef {import('./api.js').Design} Design
 * @typedef {import('./api.js').Issue} Issue
 * @typedef {import('./api.js').Mechanism} Mechanism
 * @typedef {import('./api.js').Metrics} Metrics
 * @typedef {import('./api.js').Motion} Motion
 * @typedef {import('./api.js').Analysis} Analysis
 * @typedef {import('./api.js').CheckAnswer} CheckAnswer
 * @typedef {import('./api.js').Balance} Balance
 * @typedef {import('./api.js').Family} Family
 * @typedef {import('./api.js').LengthUnit} LengthUnit
 * @typedef {import('./api.js').Limits} Limits
 */

/**
 * What the person sees and does besides the scene.
 * @typedef {object} UiState
 * @property {Tool} tool  what a drag on the canvas does
 * @property {ShapeKind} kind  what the drawing tools draw
 * @property {Selection | null} selection
 * @property {number} pose  the current pose
 * @property {boolean} grid
 * @property {boolean} snap
 * @property {Tab} tab  the side panel's tab shown
 * @property {string} hint  the status line
 * @property {boolean} showResult  the design is shown moving (not the poses to edit)
 * @property {boolean} live  a moved pose is designed again at once
 * @property {boolean} paths  the joints' paths are drawn
 * @property {boolean} dimensions  the links' lengths are written on the drawing
 * @property {boolean} welcomeClosed
 *
 * @typedef {'select' | 'pan' | 'rect' | 'polygon' | 'ellipse' | 'path'} Tool
 * @typedef {'object' | 'settings' | 'result'} Tab
 * @typedef {'ui' | 'scene' | 'result' | 'hint' | 'families' | 'lengthUnits'} Change  what changed, for the listeners
 */

/**
 * A design result, the one shape `store.result` holds:
 * - `design`: the design/1 file the server answered; `scene`: the scene/1 file it was designed for;
 * - `key`: the geometry key of the scene when it was designed (a result is fresh while it matches);
 * - `warnings`: the scene's warnings the server accepted it with;
 * - `which`: the mechanism shown (null: the best design, k: alternative k), with its `mechanism`,
 *   `metrics` and `motion` from the design; `analysis`: its simulated motion (null until simulated),
 *   `verified`: the server's check of it (null until checked) and `balance`: its counterbalance
 *   springs (null until asked for). These change as another mechanism is shown; the rest does not
 *   (but for a body's mass, `Store.setBodyMass`).
 * @typedef {object} Result
 * @property {Design} design
 * @property {Scene} scene
 * @property {string} key
 * @property {Issue[]} warnings
 * @property {number | null} which
 * @property {Mechanism | null} mechanism
 * @property {Metrics | null} metrics
 * @property {Motion | null} motion
 * @property {Analysis | null} analysis
 * @property {CheckAnswer | null} verified
 * @property {Balance | null} balance
 */

/**
 * One step of the undo history: the scene before it (as JSON), the selection and pose, and for a
 * change of the design shown (`editResult`) the result it brings back and the one it takes back.
 * @typedef {{scene: string, label: string, ui: {selection: Selection | null, pose: number},
 *   result?: Result | null, undone?: Result | null}} UndoStep
 */

const HISTORY = 200;

/**
 * A new result, no mechanism shown yet (`Store.showMechanism`).
 * @param {{design: Design, scene: Scene, key: string, warnings?: Issue[]}} made
 * @returns {Result}
 */
export function newResult({ design, scene, key, warnings = [] }) {
  return {
    design, scene, key, warnings, which: null, mechanism: null, metrics: null, motion: null, analysis: null, verified: null, balance: null,
  };
}

/**
 * `result` (or null) as it is now, for an undo step: a result's mechanism shown, analysis, check and
 * springs are set anew as another mechanism is picked, while what they hold is replaced, not changed,
 * so a shallow copy keeps it as it is.
 * @param {Result | null | undefined} result
 * @returns {Result | null}
 */
function resultState(result) {
  return result ? { ...result } : null;
}

export class Store {
  /** @param {Scene} scene */
  constructor(scene) {
    this.scene = scene;
    /** @type {UiState} */
    this.ui = {
      tool: 'select',
      kind: 'fixed',
      selection: null,
      pose: 0,
      grid: true,
      snap: true,
      tab: 'object',
      hint: '',
      showResult: false,
      live: false,
      paths: true,
      dimensions: true,
      welcomeClosed: false,
    };
    /** @type {Family[]} the engine's mechanism families (GET /api/families), once loaded */
    this.families = [];
    /** @type {LengthUnit[]} the length units the engine reads (GET /api/units), once loaded */
    this.lengthUnits = [];
    /** @type {Limits | null} the engine's limits on a scene (GET /api/status), once loaded */
    this.limits = null;
    /** @type {Result | null} */
    this.result = null;
    /** @type {UndoStep[]} */
    this.undoStack = [];
    /** @type {UndoStep[]} */
    this.redoStack = [];
    /** @type {Set<(what: Set<Change>) => void>} */
    this.listeners = new Set();
    /** @type {{label: string, before: string} | null} the gesture under way: its undo label and the scene before it */
    this.gesture = null;
    /** @type {Set<Change> | null} what changed since the listeners were last told */
    this.pending = null;
    this.scheduled = false;
  }

  /**
   * Calls `fn` with what changed, once per animation frame with changes; returns the unsubscribe.
   * @param {(what: Set<Change>) => void} fn
   */
  subscribe(fn) {
    this.listeners.add(fn);
    return () => this.listeners.delete(fn);
  }

  /**
   * Tells every listener, once per animation frame. `what` names what changed.
   * @param {Change} [what]
   */
  changed(what = 'ui') {
    this.pending = new Set([...(this.pending || []), what]);
    if (this.scheduled) return;
    this.scheduled = true;
    requestAnimationFrame(() => {
      this.scheduled = false;
      const pending = this.pending || new Set();
      this.pending = null;
      for (const fn of this.listeners) fn(pending);
    });
  }

  /**
   * One undoable change of the scene, named `label` in the undo history. `fn(scene)` may return false
   * to say nothing changed; its answer is returned.
   * @template T
   * @param {string} label
   * @param {(scene: Scene) => T} fn
   * @returns {T}
   */
  edit(label, fn) {
    const before = JSON.stringify(this.scene);
    const out = fn(this.scene);
    if (out === false || JSON.stringify(this.scene) === before) return out;
    this.push(before, label);
    this.changed('scene');
    return out;
  }

  /**
   * Starts a gesture (a drag): its updates become one undo step at `end`.
   * @param {string} label
   */
  begin(label) {
    this.gesture = { label, before: JSON.stringify(this.scene) };
  }

  /**
   * A change of the scene within the gesture.
   * @param {(scene: Scene) => void} fn
   */
  update(fn) {
    fn(this.scene);
    this.changed('scene');
  }

  /** Ends the gesture: one undo step, when it changed the scene. */
  end() {
    if (!this.gesture) return;
    const { label, before } = this.gesture;
    this.gesture = null;
    if (JSON.stringify(this.scene) !== before) {
      this.push(before, label);
      this.changed('scene');
    }
  }

  /**
   * Replaces the whole scene (open, example, new), undoably.
   * @param {Scene} scene
   * @param {string} label
   */
  replace(scene, label) {
    this.push(JSON.stringify(this.scene), label);
    this.scene = scene;
    this.ui.selection = null;
    this.ui.pose = 0;
    this.changed('scene');
  }

  /**
   * One undoable change of the design shown (its joints moved): `before` is the result it replaced.
   * The step keeps both results as they are now, so that undo and redo bring back exactly these
   * two, whatever is shown (or picked, or redesigned) in between.
   * @param {string} label
   * @param {Result} before
   */
  editResult(label, before) {
    this.undoStack.push({
      scene: JSON.stringify(this.scene), label, ui: this.uiSnapshot(), result: resultState(before), undone: resultState(this.result),
    });
    if (this.undoStack.length > HISTORY) this.undoStack.shift();
    this.redoStack = [];
    this.changed('result');
  }

  /**
   * A step of the scene onto the undo history (`before`: the scene as JSON); redo starts anew.
   * @param {string} before
   * @param {string} label
   */
  push(before, label) {
    this.undoStack.push({ scene: before, label, ui: this.uiSnapshot() });
    if (this.undoStack.length > HISTORY) this.undoStack.shift();
    this.redoStack = [];
  }

  /** What an undo step brings back besides the scene. */
  uiSnapshot() {
    return { selection: this.ui.selection, pose: this.ui.pose };
  }

  canUndo() { return this.undoStack.length > 0; }
  canRedo() { return this.redoStack.length > 0; }

  /** Takes back the last step: its label, or null when there is none. */
  undo() {
    const step = this.undoStack.pop();
    if (!step) return null;
    this.redoStack.push(this.opposite(step));
    this.restore(step);
    return step.label;
  }

  /** Does again the last step taken back: its label, or null when there is none. */
  redo() {
    const step = this.redoStack.pop();
    if (!step) return null;
    this.undoStack.push(this.opposite(step));
    this.restore(step);
    return step.label;
  }

  /** The step that takes back `step`: the scene now, and for a change of the design shown, the
   * design `step` took back (not whatever is shown now: a design made or picked since is not the
   * step's).
   * @param {UndoStep} step
   * @returns {UndoStep}
   */
  opposite(step) {
    /** @type {UndoStep} */
    const back = { scene: JSON.stringify(this.scene), label: step.label, ui: this.uiSnapshot() };
    if ('result' in step) Object.assign(back, { result: step.undone, undone: step.result });
    return back;
  }

  /**
   * Brings back what `step` kept.
   * @param {UndoStep} step
   */
  restore(step) {
    if ('result' in step) {
      // A copy: the result shown changes as another mechanism is picked, the step's must not.
      this.result = resultState(step.result);
      this.changed('result');
    }
    this.scene = JSON.parse(step.scene);
    this.ui.selection = step.ui.selection;
    this.ui.pose = step.ui.pose;
    this.clampSelection();
    this.changed('scene');
  }

  /** Keeps the selection and the current pose pointing at things that exist. */
  clampSelection() {
    const s = this.scene;
    const n = s.moving_bodies.length ? s.moving_bodies[0].poses.length : 0;
    this.ui.pose = Math.max(0, Math.min(this.ui.pose, Math.max(n - 1, 0)));
    const sel = this.ui.selection;
    if (!sel) return;
    const exists = {
      fixed: () => sel.index < s.fixed_bodies.length,
      moving: () => sel.index < s.moving_bodies.length,
      region: () => !!s.linkage_region,
      avoid: () => sel.index < (s.avoid_regions || []).length,
    }[sel.kind];
    if (!exists || !exists()) this.ui.selection = null;
  }

  /**
   * The engine's mechanism families, loaded.
   * @param {Family[]} families
   */
  setFamilies(families) {
    this.families = families;
    this.changed('families');
  }

  /**
   * The length units the engine reads, loaded.
   * @param {LengthUnit[]} units
   */
  setLengthUnits(units) {
    this.lengthUnits = units;
    this.changed('lengthUnits');
  }

  /**
   * The engine's limits on a scene, loaded.
   * @param {Limits} limits
   */
  setLimits(limits) {
    this.limits = limits;
    this.changed('ui');
  }

  /**
   * Puts up `result` (see `newResult`; null: none) as the design shown. The listeners are told by the
   * caller once it can be drawn: a new result's motion comes with its analysis (`answerResult`), and
   * until then the drawing keeps the one shown before rather than blinking.
   * @param {Result | null} result
   */
  setResult(result) {
    this.result = result;
  }

  /**
   * Shows mechanism `which` of the result (null: the design itself, k: its alternative k): its
   * mechanism, metrics and motion. Its analysis and springs were of the mechanism shown before, so
   * they go, and so does the check when another mechanism is picked. Told as `setResult` is.
   * @param {number | null} which
   */
  showMechanism(which) {
    const r = this.result;
    if (!r) return;
    const d = r.design;
    const shown = which === null ? d : d.alternatives[which];
    if (r.which !== which) r.verified = null;
    Object.assign(r, {
      which, mechanism: shown?.mechanism ?? null, metrics: shown?.metrics ?? null, motion: shown?.motion ?? null, analysis: null, balance: null,
    });
  }

  /**
   * True while `result` is the one shown, with mechanism `which`: an answer asked for it still
   * belongs to what is on screen.
   * @param {Result} result
   * @param {number | null} which
   */
  isShown(result, which) {
    return this.result === result && result.which === which;
  }

  /**
   * What the server answered for `result`'s mechanism `which` (its `analysis`, the `verified` check,
   * the `balance` springs), kept when they are still shown; false (and dropped) when another design or
   * mechanism is shown by now.
   * @param {Result} result
   * @param {number | null} which
   * @param {{analysis?: Analysis, verified?: CheckAnswer, balance?: Balance}} answer
   */
  answerResult(result, which, answer) {
    if (!this.isShown(result, which)) return false;
    Object.assign(result, answer);
    this.changed('result');
    return true;
  }

  /**
   * Moving body `index`'s mass in kilograms (null: weighed in its material), as one undo step of the
   * scene; the scene `result` was designed for takes it too, since a mass changes no geometry: the
   * design stays and is weighed again.
   * @param {Result} result
   * @param {number} index
   * @param {number | null} massKg
   */
  setBodyMass(result, index, massKg) {
    /** @param {import('./scene.js').MovingBody} body */
    const set = (body) => {
      if (massKg === null) delete body.mass_kg;
      else body.mass_kg = massKg;
    };
    this.edit(`mass of ${result.scene.moving_bodies[index].name}`, (s) => { set(s.moving_bodies[index]); });
    set(result.scene.moving_bodies[index]);
  }

  /**
   * Changes what the person sees (not the scene: no undo step).
   * @param {Partial<UiState>} patch
   */
  setUi(patch) {
    Object.assign(this.ui, patch);
    this.changed('ui');
  }

  /**
   * Says `text` in the status line.
   * @param {string} text
   */
  hint(text) {
    this.ui.hint = text;
    this.changed('hint');
  }
}
