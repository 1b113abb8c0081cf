// The app's state and its undo history. Every change of the state goes through a method here. The
// scene (the document) changes only through `edit` or a `begin`/`update`/`end` gesture, each of which
// is one undo step; so does a design whose joints the person moved (`editResult`); everything else is
// view state.

const HISTORY = 200;

/**
 * A design result, the one shape `store.result` holds:
 * - `design`: the design/1 file the server answered; `scene`: the scene/1 file it was designed for;
 * - `key`: the geometry key of the scene when it was designed (a result is fresh while it matches);
 * - `warnings`: the scene's warnings the server accepted it with;
 * - `which`: the mechanism shown (null: the best design, k: alternative k), `analysis`: its simulated
 *   motion (null until simulated) and `verified`: the server's check of it (null until checked).
 *   These three change as another mechanism is shown; the rest never changes.
 */
export function newResult({ design, scene, key, warnings = [] }) {
  return { design, scene, key, warnings, which: null, analysis: null, verified: null };
}

/** `result` (or null) as it is now, for an undo step: a result's mechanism shown, analysis, check and
 * springs are set anew as another mechanism is picked, while what they hold is replaced, not changed,
 * so a shallow copy keeps it as it is. */
function resultState(result) {
  return result && { ...result };
}

export class Store {
  constructor(scene) {
    this.scene = scene;
    this.ui = {
      tool: 'select', // select | pan | rect | polygon | ellipse
      kind: 'fixed', // what the drawing tools draw: fixed | moving | region | avoid
      selection: null, // {kind, index, vertex?}
      pose: 0, // the current pose
      grid: true,
      snap: true,
      tab: 'object',
      hint: '',
    };
    this.families = []; // the engine's mechanism families (GET /api/families), once loaded
    this.limits = null; // the engine's limits on a scene (GET /api/status), once loaded
    this.result = null; // a design result (see `newResult`), or null
    this.undoStack = [];
    this.redoStack = [];
    this.listeners = new Set();
    this.gesture = null;
    this.scheduled = false;
  }

  subscribe(fn) {
    this.listeners.add(fn);
    return () => this.listeners.delete(fn);
  }

  /** Tells every listener, once per animation frame. `what` names what changed. */
  changed(what = 'ui') {
    this.pending = new Set([...(this.pending || []), what]);
    if (this.scheduled) return;
    this.scheduled = true;
    requestAnimationFrame(() => {
      this.scheduled = false;
      const pending = this.pending;
      this.pending = null;
      for (const fn of this.listeners) fn(pending);
    });
  }

  /** One undoable change of the scene. `fn(scene)` may return false to say nothing changed. */
  edit(label, fn) {
    const before = JSON.stringify(this.scene);
    const out = fn(this.scene);
    if (out === false || JSON.stringify(this.scene) === before) return out;
    this.push(before, label);
    this.changed('scene');
    return out;
  }

  /** Starts a gesture (a drag): its updates become one undo step at `end`. */
  begin(label) {
    this.gesture = { label, before: JSON.stringify(this.scene) };
  }
  update(fn) {
    fn(this.scene);
    this.changed('scene');
  }
  end() {
    if (!this.gesture) return;
    const { label, before } = this.gesture;
    this.gesture = null;
    if (JSON.stringify(this.scene) !== before) {
      this.push(before, label);
      this.changed('scene');
    }
  }

  /** Replaces the whole scene (open, example, new), undoably. */
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
   */
  editResult(label, before) {
    this.undoStack.push({
      scene: JSON.stringify(this.scene), label, ui: this.uiSnapshot(), result: resultState(before), undone: resultState(this.result),
    });
    if (this.undoStack.length > HISTORY) this.undoStack.shift();
    this.redoStack = [];
    this.changed('result');
  }

  push(before, label) {
    this.undoStack.push({ scene: before, label, ui: this.uiSnapshot() });
    if (this.undoStack.length > HISTORY) this.undoStack.shift();
    this.redoStack = [];
  }

  uiSnapshot() {
    return { selection: this.ui.selection, pose: this.ui.pose };
  }

  canUndo() { return this.undoStack.length > 0; }
  canRedo() { return this.redoStack.length > 0; }

  undo() {
    const step = this.undoStack.pop();
    if (!step) return null;
    this.redoStack.push(this.opposite(step));
    this.restore(step);
    return step.label;
  }

  redo() {
    const step = this.redoStack.pop();
    if (!step) return null;
    this.undoStack.push(this.opposite(step));
    this.restore(step);
    return step.label;
  }

  /** The step that takes back `step`: the scene now, and for a change of the design shown, the
   * design `step` took back (not whatever is shown now: a design made or picked since is not the
   * step's). */
  opposite(step) {
    const back = { scene: JSON.stringify(this.scene), label: step.label, ui: this.uiSnapshot() };
    if ('result' in step) Object.assign(back, { result: step.undone, undone: step.result });
    return back;
  }

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

  /** The engine's mechanism families, loaded. */
  setFamilies(families) {
    this.families = families;
    this.changed('families');
  }

  /** The engine's limits on a scene, loaded. */
  setLimits(limits) {
    this.limits = limits;
    this.changed('ui');
  }

  /**
   * Puts up `result` (see `newResult`; null: none) as the design shown. The listeners are told by the
   * caller once it can be drawn: a new result's motion comes with its analysis (`answerResult`), and
   * until then the drawing keeps the one shown before rather than blinking.
   */
  setResult(result) {
    this.result = result;
  }

  /**
   * Shows mechanism `which` of the result (null: the design itself, k: its alternative k): its
   * mechanism, metrics and motion. Its analysis and springs were of the mechanism shown before, so
   * they go, and so does the check when another mechanism is picked. Told as `setResult` is.
   */
  showMechanism(which) {
    const r = this.result;
    if (!r) return;
    const d = r.design;
    const shown = which === null ? d : d.alternatives[which];
    if (r.which !== which) r.verified = null;
    Object.assign(r, { which, mechanism: shown?.mechanism, metrics: shown?.metrics, motion: shown?.motion, analysis: null, balance: null });
  }

  /** True while `result` is the one shown, with mechanism `which`: an answer asked for it still
   * belongs to what is on screen. */
  isShown(result, which) {
    return this.result === result && result.which === which;
  }

  /**
   * What the server answered for `result`'s mechanism `which` (its `analysis`, the `verified` check,
   * the `balance` springs), kept when they are still shown; false (and dropped) when another design or
   * mechanism is shown by now.
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
   */
  setBodyMass(result, index, massKg) {
    const set = (body) => {
      if (massKg === null) delete body.mass_kg;
      else body.mass_kg = massKg;
    };
    this.edit(`mass of ${result.scene.moving_bodies[index].name}`, (s) => { set(s.moving_bodies[index]); });
    set(result.scene.moving_bodies[index]);
  }

  setUi(patch) {
    Object.assign(this.ui, patch);
    this.changed('ui');
  }

  hint(text) {
    this.ui.hint = text;
    this.changed('hint');
  }
}
