// @ts-check
// The app: wires the store, the canvas, the tools, the panels, the results and the files together.

import * as api from './api.js';
import { Canvas } from './canvas.js';
import { Fabricator } from './fabricate.js';
import * as F from './files.js';
import { renderObjectTab, renderSettingsTab } from './panels.js';
import { Results } from './result.js';
import * as S from './scene.js';
import { newResult, Store } from './store.js';
import { toolHint, Tools } from './tools.js';
import { Viewport } from './viewport.js';

/**
 * @typedef {import('./geom.js').Point} Point
 * @typedef {import('./store.js').Tool} Tool
 * @typedef {import('./store.js').Tab} Tab
 * @typedef {import('./store.js').Change} Change
 * @typedef {import('./scene.js').ShapeKind} ShapeKind
 * @typedef {import('./files.js').Project} Project
 */

/**
 * The element with id `id`, of the kind the app uses it as (the page has each).
 * @template {Element} E
 * @param {string} id
 * @param {new (...args: any[]) => E} kind
 * @returns {E}
 */
function element(id, kind) {
  const e = document.getElementById(id);
  if (!(e instanceof kind)) throw new Error(`the page has no ${kind.name} #${id}`);
  return e;
}

/** The HTML element with id `id`. @type {(id: string) => HTMLElement} */
const $ = (id) => element(id, HTMLElement);

const WELCOME_HINT = 'Start by drawing the part of your object that never moves: “Fixed body” is chosen, so drag a rectangle on the grid. Or open one of the Examples.';

const saved = F.restore();

/** @type {Point | null} where the pointer was last over the drawing, in the scene's units (again when they change) */
let pointerAt = null;
function showPointer() {
  if (pointerAt) $('coords').textContent = `x ${pointerAt[0].toFixed(1)}  y ${pointerAt[1].toFixed(1)} ${store.scene.units || 'mm'}`;
}

const store = new Store(saved?.scene ?? S.newScene());
const view = new Viewport();
const root = element('canvas', SVGSVGElement);
const canvas = new Canvas(root, store, view);

const results = new Results(store, canvas, {
  job: $('job'), jobFill: $('job-fill'), jobText: $('job-text'), design: element('btn-design', HTMLButtonElement), cancel: $('btn-cancel'),
  player: $('player'), play: $('btn-play'), scrub: element('scrub', HTMLInputElement), readout: $('crank-readout'),
  speed: element('speed', HTMLSelectElement), paths: element('opt-paths', HTMLInputElement), dims: element('opt-dims', HTMLInputElement),
  edit: $('btn-edit'), show: $('btn-show'), live: element('opt-live', HTMLInputElement),
}, F.saveBlob);
const fab = new Fabricator(store, results, {
  view: $('view3d'), canvas: element('view3d-canvas', HTMLCanvasElement), legend: $('view3d-legend'), toggle: $('btn-3d'),
});
results.fab = fab;

const tools = new Tools(root, store, canvas, view, {
  redraw: () => canvas.render(),
  leaveResult: () => results.player.leave(),
  liveResult: () => !!store.ui.live && canvas.showingResult(),
  poseEdited: () => results.live.poseEdited(),
  poseReleased: () => results.live.poseReleased(),
  beginJointDrag: (name) => results.joints.beginJointDrag(name),
  moveJoint: (w) => results.joints.moveJoint(w),
  endJointDrag: () => results.joints.endJointDrag(),
  deleteSelection,
  pointer: (w) => { pointerAt = w; showPointer(); },
});

function deleteSelection() {
  const sel = store.ui.selection;
  if (!sel) return;
  const vertex = sel.vertex;
  if (vertex !== undefined) {
    const done = store.edit('delete a corner', (s) => S.deleteVertex(s, sel, vertex));
    if (done !== false) {
      store.setUi({ selection: { kind: sel.kind, index: sel.index } });
      return;
    }
    store.hint('A shape needs at least three corners; press Delete again to delete the whole shape.');
    store.setUi({ selection: { kind: sel.kind, index: sel.index } });
    return;
  }
  store.edit('delete', (s) => S.deleteShape(s, sel));
  store.setUi({ selection: null });
}

// ---- Toolbar -----------------------------------------------------------------------------------

/**
 * The buttons on the page with the data attribute `attribute` (as a selector: `[data-tool]`).
 * @param {string} attribute
 * @returns {HTMLElement[]}
 */
const buttons = (attribute) => [...document.querySelectorAll(attribute)].filter((b) => b instanceof HTMLElement);

for (const b of buttons('[data-tool]')) {
  b.addEventListener('click', () => tools.setTool(/** @type {Tool} */ (b.dataset.tool)));
}
for (const b of buttons('[data-kind-choice]')) {
  b.addEventListener('click', () => {
    store.setUi({ kind: /** @type {ShapeKind} */ (b.dataset.kindChoice) });
    // Choosing what to draw also picks a drawing tool, so the next drag draws it.
    if (store.ui.tool === 'select' || store.ui.tool === 'pan') tools.setTool('rect');
    else store.hint(toolHint(store.ui));
  });
}
const gridOption = element('opt-grid', HTMLInputElement), snapOption = element('opt-snap', HTMLInputElement);
gridOption.addEventListener('change', () => store.setUi({ grid: gridOption.checked }));
snapOption.addEventListener('change', () => store.setUi({ snap: snapOption.checked }));
$('btn-fit').addEventListener('click', fit);
$('btn-undo').addEventListener('click', undo);
$('btn-redo').addEventListener('click', redo);
const sceneName = element('scene-name', HTMLInputElement);
sceneName.addEventListener('change', () => {
  const name = sceneName.value || 'untitled';
  store.edit('rename the scene', (s) => { s.name = name; });
});

/** Frames everything (the whole motion while a design is shown), clear of the player at the bottom
 * and with room above for a selected shape's rotation handle. */
function fit() {
  const player = $('player');
  const bottom = player.hidden ? 40 : player.offsetHeight + 28;
  view.fit([...S.allPoints(store.scene), ...results.player.motionPoints()], 40, { top: 64, bottom });
  canvas.render();
}
results.fitView = fit;

function undo() {
  const label = store.undo();
  results.player.drawFrame();
  store.hint(label ? `Undid: ${label}. (Redo: Ctrl+Shift+Z)` : 'Nothing to undo.');
}

function redo() {
  const label = store.redo();
  results.player.drawFrame();
  store.hint(label ? `Redid: ${label}.` : 'Nothing to redo.');
}

// ---- Poses -------------------------------------------------------------------------------------

$('btn-pose-insert').addEventListener('click', () => {
  const at = store.ui.pose;
  results.player.leave();
  store.edit('insert a pose', (s) => S.insertPose(s, at));
  store.setUi({ pose: at + 1 });
  store.hint(store.scene.moving_bodies.some((b) => b.path)
    ? `Pose ${at + 2} inserted on the path: drag it along the path, turn it with its round handle.`
    : `Pose ${at + 2} inserted halfway between its neighbours: drag it into place.`);
});
$('btn-pose-delete').addEventListener('click', () => {
  const at = store.ui.pose;
  if (store.edit(`delete pose ${at + 1}`, (s) => S.deletePose(s, at)) === false) {
    store.hint('Every moving body needs at least two poses (a start and an end).');
    return;
  }
  store.clampSelection();
  store.changed('ui');
});
$('btn-pose-earlier').addEventListener('click', () => movePose(-1));
$('btn-pose-later').addEventListener('click', () => movePose(1));

/**
 * Moves the current pose `step` places earlier (−1) or later (1).
 * @param {number} step
 */
function movePose(step) {
  const at = store.ui.pose, to = at + step;
  if (to < 0 || to >= S.poseCount(store.scene)) return;
  store.edit(`move pose ${at + 1}`, (s) => S.swapPoses(s, at, to));
  store.setUi({ pose: to });
}

/**
 * Pose `i`: where the design shown reaches it, or else the pose to edit.
 * @param {number} i
 */
function goToPose(i) {
  if (!results.player.showPose(i)) store.setUi({ pose: i });
}

function renderPoseBar() {
  const n = S.poseCount(store.scene);
  $('posebar').hidden = n === 0;
  const host = $('pose-buttons');
  // The buttons are kept while the number of poses is, so the one with the keyboard's focus keeps it.
  if (host.children.length !== n) {
    host.replaceChildren(...Array.from({ length: n }, (_, i) => {
      const b = document.createElement('button');
      b.addEventListener('click', () => goToPose(i));
      return b;
    }));
  }
  [...host.children].forEach((b, i) => {
    if (!(b instanceof HTMLElement)) return;
    const marked = i > 0 && i < n - 1 && S.isMustHit(store.scene, i);
    b.textContent = marked ? `Pose ${i + 1} ◆` : `Pose ${i + 1}`;
    if (marked) b.title = 'The linkage must hit this pose';
    else b.removeAttribute('title');
    b.className = i === store.ui.pose ? 'on' : '';
    b.setAttribute('aria-pressed', String(i === store.ui.pose));
  });
  // A body that follows a path needs only where it starts; other motions a start and an end.
  element('btn-pose-delete', HTMLButtonElement).disabled = n <= (store.scene.moving_bodies.some((b) => b.path) ? 1 : 2);
  const most = store.limits?.poses_per_body;
  const insert = element('btn-pose-insert', HTMLButtonElement);
  insert.disabled = typeof most === 'number' && Number.isFinite(most) && n >= most;
  insert.title = insert.disabled
    ? `A body has at most ${most} poses: delete one to insert another`
    : store.scene.moving_bodies.some((b) => b.path)
    ? 'Insert a pose the body must also pass, after the current one along its path'
    : 'Insert a pose after the current one, halfway to the next';
  element('btn-pose-earlier', HTMLButtonElement).disabled = store.ui.pose === 0;
  element('btn-pose-later', HTMLButtonElement).disabled = store.ui.pose >= n - 1;
}

// ---- Tabs --------------------------------------------------------------------------------------

for (const b of buttons('[data-tab]')) {
  b.addEventListener('click', () => store.setUi({ tab: /** @type {Tab} */ (b.dataset.tab) }));
}

/** @type {Tab | null} */
let shownTab = null;
/**
 * Shows the tab chosen, drawn again when `what` changed concerns it.
 * @param {Set<Change>} what
 */
function renderTabs(what) {
  const tab = store.ui.tab;
  for (const b of buttons('[data-tab]')) {
    b.classList.toggle('on', b.dataset.tab === tab);
    $(`tab-${b.dataset.tab}`).hidden = b.dataset.tab !== tab;
  }
  const switched = tab !== shownTab;
  shownTab = tab;
  if (tab === 'object') renderObjectTab($('tab-object'), store);
  if (tab === 'settings' && (switched || what.has('scene') || what.has('families') || what.has('lengthUnits'))) renderSettingsTab($('tab-settings'), store);
  if (tab === 'result' && (switched || what.has('result') || what.has('scene'))) {
    // Drawn again on every change: where the person had scrolled to stays (unless the tab was just opened).
    const host = $('tab-result'), top = host.scrollTop;
    results.tab.render(host);
    if (!switched) host.scrollTop = top;
  }
}

// ---- Files -------------------------------------------------------------------------------------

/**
 * Opens a file chosen or dropped: a scene (with its project's design), or a design for the scene shown.
 * @param {File} file
 */
async function openFile(file) {
  try {
    const got = await F.readFile(file);
    if (got.scene) {
      results.player.leave();
      store.replace(got.scene, `open ${file.name}`);
      markSaved();
      results.clear();
      if (got.project) await openProject(got.project);
      fit();
      store.hint(got.project
        ? `Opened ${file.name} with its design, as it was saved. (Undo brings the previous scene back.)`
        : `Opened ${file.name}. (Undo brings the previous scene back.)`);
    } else {
      store.setResult(newResult({ design: got.design, scene: S.toFile(store.scene), key: S.geometryKey(store.scene) }));
      await results.select(null);
      store.setUi({ tab: 'result' });
      store.hint(`Opened the design ${file.name} for this scene.`);
    }
  } catch (e) {
    store.hint(`Cannot open ${file.name}: ${e instanceof Error ? e.message : e}`);
  }
}

/**
 * Shows a project's design (as saved: no redesign), its springs and its print settings.
 * @param {Project} project
 */
async function openProject({ design, which, balance, print }) {
  if (print) fab.usePrint(print);
  const shown = newResult({ design, scene: S.toFile(store.scene), key: S.geometryKey(store.scene) });
  store.setResult(shown);
  await results.select(which);
  if (balance && shown.analysis) store.answerResult(shown, which, { balance });
  store.setUi({ tab: 'result' });
  results.verify();
}

$('btn-open').addEventListener('click', () => $('file-input').click());
const fileInput = element('file-input', HTMLInputElement);
fileInput.addEventListener('change', () => {
  const file = fileInput.files?.[0];
  fileInput.value = '';
  if (file) openFile(file);
});
$('btn-save').addEventListener('click', () => {
  // With the design shown for the drawing as it is, the file keeps it (a project); else the scene.
  const r = store.result;
  const shown = r?.design && results.fresh()
    ? { design: r.design, which: r.which, balance: r.balance || null, print: fab.print }
    : undefined;
  F.saveScene(store.scene, shown);
  markSaved();
  store.hint(shown
    ? `Saved ${store.scene.name}.json to your downloads: the scene with its design, springs and print settings.`
    : `Saved ${store.scene.name}.json to your downloads.`);
});
$('btn-new').addEventListener('click', () => {
  results.player.leave();
  store.replace(S.newScene(), 'new scene');
  markSaved();
  results.clear();
  // As "Start drawing" does: the hint below tells the person to draw the fixed part first.
  store.setUi({ kind: 'fixed' });
  tools.setTool('rect');
  fit();
  store.hint(`New scene. (Undo brings the previous one back.) ${WELCOME_HINT}`);
});
F.dropTarget($('drop'), openFile);

/** @type {string | null} the scene as it was last saved or opened (null: not known to be saved, as after a reload) */
let savedScene = null;
const unsaved = () => !S.isEmpty(store.scene) && JSON.stringify(S.toFile(store.scene)) !== savedScene;
const markSaved = () => { savedScene = JSON.stringify(S.toFile(store.scene)); };

/**
 * Asks whether to replace a drawing with unsaved changes by `what`: true to go on (after saving it,
 * when the person asks to). A drawing without unsaved changes is replaced without asking.
 * @param {string} what
 * @returns {Promise<boolean>}
 */
function askReplace(what) {
  if (!unsaved()) return Promise.resolve(true);
  const ask = element('replace', HTMLDialogElement);
  $('replace-text').textContent = `“${store.scene.name}” has changes that are not saved in a file. Opening ${what} replaces it (Undo brings it back while this page is open).`;
  return new Promise((resolve) => {
    /** @type {(go: boolean, save?: boolean) => () => void} */
    const answer = (go, save = false) => () => {
      ask.onclose = null;
      ask.close();
      if (save) $('btn-save').click();
      resolve(go);
    };
    $('btn-replace').onclick = answer(true);
    $('btn-replace-save').onclick = answer(true, true);
    $('btn-replace-keep').onclick = answer(false);
    ask.onclose = () => resolve(false);
    ask.showModal();
  });
}

const gallery = element('gallery', HTMLDialogElement);
function openGallery() {
  gallery.showModal();
  F.fillGallery($('gallery-list'), async (scene, entry) => {
    gallery.close();
    if (!(await askReplace(`the ${entry.title} example`))) return;
    results.player.leave();
    store.replace(scene, `open the ${entry.title} example`);
    markSaved();
    results.clear();
    fit();
    store.hint(`Opened the ${entry.title} example: press “Design linkage” to find its mechanism.`);
  }, (message) => store.hint(`Cannot load the examples: ${message}`));
}
$('btn-examples').addEventListener('click', openGallery);
$('btn-gallery-close').addEventListener('click', () => gallery.close());
$('welcome-examples').addEventListener('click', openGallery);
$('welcome-start').addEventListener('click', () => {
  store.setUi({ kind: 'fixed', welcomeClosed: true });
  tools.setTool('rect');
});

// ---- Keyboard ----------------------------------------------------------------------------------

window.addEventListener('keydown', (e) => {
  // An open dialog (the examples, this list) has the keyboard to itself: Escape closes it.
  if (document.querySelector('dialog[open]')) return;
  const target = e.target instanceof Element ? e.target : null;
  const type = target instanceof HTMLInputElement ? target.type : '';
  const typing = !!target?.closest('input, select, textarea') && !['checkbox', 'range', 'radio'].includes(type);
  const mod = e.ctrlKey || e.metaKey;
  if (mod && e.key.toLowerCase() === 'z') {
    if (typing) return;
    e.preventDefault();
    if (e.shiftKey) redo(); else undo();
    return;
  }
  if (mod && e.key.toLowerCase() === 'y') { if (!typing) { e.preventDefault(); redo(); } return; }
  if (mod && e.key.toLowerCase() === 's') { e.preventDefault(); $('btn-save').click(); return; }
  if (mod && e.key.toLowerCase() === 'o') { e.preventDefault(); $('btn-open').click(); return; }
  if (typing || mod || e.altKey) return;
  // Arrow keys and Space on a radio button choose in its group (Settings › Build).
  if (type === 'radio') return;
  // Enter and Space press the focused button, link or disclosure, as everywhere else.
  const pressable = target?.closest('button, a[href], summary, [role=button], input[type=checkbox]');
  if (pressable && (e.key === 'Enter' || e.key === ' ')) return;
  if (e.key === ' ') {
    // A tap plays or pauses the design shown; held, it pans while dragging (see keyup).
    if (!e.repeat) tools.spacePanned = false;
    tools.space = true;
    e.preventDefault();
    return;
  }
  if (e.key === '?') { element('shortcuts', HTMLDialogElement).showModal(); return; }
  if (tools.key(e)) { e.preventDefault(); return; }
  /** @type {Record<string, Tool>} */
  const shortcuts = { v: 'select', h: 'pan', r: 'rect', p: 'polygon', e: 'ellipse', t: 'path' };
  const key = e.key.toLowerCase();
  if (shortcuts[key]) tools.setTool(shortcuts[key]);
  else if (key === 'f') fit();
  else if (key === '+' || key === '=' || key === '-') {
    view.zoomAt([view.width / 2, view.height / 2], key === '-' ? 1 / 1.25 : 1.25);
    canvas.render();
  }
  else if (key === 'g') { store.setUi({ grid: !store.ui.grid }); gridOption.checked = store.ui.grid; }
  else if (key === 'enter') { e.preventDefault(); results.run(); }
  else if (/^[1-9]$/.test(key) && Number(key) <= S.poseCount(store.scene)) goToPose(Number(key) - 1);
});
window.addEventListener('keyup', (e) => {
  if (e.key !== ' ' || !tools.space) return;
  tools.space = false;
  if (!tools.spacePanned) results.player.togglePlaying();
});
$('btn-shortcuts-close').addEventListener('click', () => element('shortcuts', HTMLDialogElement).close());

// ---- Rendering ---------------------------------------------------------------------------------

// Where the canvas was on the page at the last resize: when it moves (the pose bar appears above
// it, say), the view moves back by as much, so the drawing stays where it was on the page.
/** @type {{left: number, top: number} | null} */
let canvasAt = null;
function resize() {
  const r = root.getBoundingClientRect();
  if (canvasAt) view.pan(canvasAt.left - r.left, canvasAt.top - r.top);
  canvasAt = { left: r.left, top: r.top };
  view.resize(r.width, r.height);
  canvas.render();
}
new ResizeObserver(resize).observe(root);

// The Type menu and the progress labels name the engine's families.
api.families().then((families) => {
  store.setFamilies(families);
}, (e) => store.hint(`Cannot reach the engine: ${e.message}`));
// The size of a printed model (Settings › Build) reads the scene's units with the engine's table;
// without it the size is not shown, and the server still says it when it answers.
api.units().then((units) => {
  store.setLengthUnits(units);
}, () => {});
// The engine's limits on a scene: Insert pose stops at its most poses.
api.status().then((status) => {
  store.setLimits(status.limits);
}, () => {});

/** @type {ReturnType<typeof setTimeout> | undefined} */
let saveTimer;
store.subscribe((what) => {
  if (what.has('scene')) store.clampSelection();
  results.sync();
  if (document.activeElement !== sceneName) sceneName.value = store.scene.name;
  element('btn-undo', HTMLButtonElement).disabled = !store.canUndo();
  element('btn-redo', HTMLButtonElement).disabled = !store.canRedo();
  for (const b of buttons('[data-tool]')) b.classList.toggle('on', b.dataset.tool === store.ui.tool);
  // What the shape tools draw is shown chosen only while one of them is.
  const drawing = ['rect', 'polygon', 'ellipse'].includes(store.ui.tool);
  for (const b of buttons('[data-kind-choice]')) b.classList.toggle('on', drawing && b.dataset.kindChoice === store.ui.kind);
  $('welcome').hidden = !S.isEmpty(store.scene) || !!store.ui.welcomeClosed;
  $('hint').textContent = store.ui.hint;
  showPointer();
  renderPoseBar();
  renderTabs(what);
  canvas.render();
  clearTimeout(saveTimer);
  saveTimer = setTimeout(persist, 250);
});

function persist() {
  const r = store.result;
  F.autosave({
    scene: store.scene,
    pose: store.ui.pose,
    view: { ox: view.ox, oy: view.oy, k: view.k, left: canvasAt?.left, top: canvasAt?.top },
    result: r && results.fresh() ? { design: r.design, scene: r.scene, which: r.which } : null,
    live: !!store.ui.live,
  });
}
window.addEventListener('pagehide', persist);

// ---- Start -------------------------------------------------------------------------------------

resize();
if (saved) {
  store.setUi({ pose: saved.pose || 0 });
  store.clampSelection();
  if (saved.view && Number.isFinite(saved.view.k)) {
    const { ox, oy, k, left, top } = saved.view;
    Object.assign(view, { ox, oy, k });
    // Saved where the canvas was then: the next resize moves the view by where it is now.
    if (typeof left === 'number' && typeof top === 'number' && Number.isFinite(left) && Number.isFinite(top)) canvasAt = { left, top };
    resize();
  } else fit();
  store.hint('Welcome back: your last scene is restored.');
  if (saved.live) {
    store.setUi({ live: true });
    element('opt-live', HTMLInputElement).checked = true;
  }
  if (saved.result?.design) {
    store.setResult(newResult({ design: saved.result.design, scene: saved.result.scene, key: S.geometryKey(store.scene) }));
    results.select(saved.result.which ?? null).then(() => results.verify());
  }
} else {
  fit();
  store.hint(WELCOME_HINT);
}
store.changed('scene');
store.hint(store.ui.hint || toolHint(store.ui));
if (S.isEmpty(store.scene)) store.setUi({ tool: 'rect' });

// For the end-to-end tests and the curious: the state, and page positions of world points and back.
Object.assign(window, {
  linkwright: {
    store,
    results,
    /** @param {Point} p */
    screenOf(p) {
      const r = root.getBoundingClientRect();
      const s = view.toScreen(p);
      return [r.left + s[0], r.top + s[1]];
    },
    /** @param {Point} p  a page position */
    worldOf(p) {
      const r = root.getBoundingClientRect();
      return view.toWorld([p[0] - r.left, p[1] - r.top]);
    },
  },
});
document.body.dataset.ready = 'true';
