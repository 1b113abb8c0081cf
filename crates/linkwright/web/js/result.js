// Running a design (with live progress and cancel), showing the result: the animation player, the
// metrics, alternatives as thumbnails, the analysis plots and the downloads.

import { fmt, poseErrors, poseTable, reachBadge, reachText } from './accuracy.js';
import { DEFAULT_BUILD, describe, describeRecord, parseBuild, suggestedScale } from './build.js';
import { captureFrames, encodeGif, recordWebm } from './record.js';
import * as api from './api.js';
import { bodyColour } from './canvas.js';
import { savedPrintSettings } from './fabricate.js';
import { bounds, placed } from './geom.js';
import { errorPlot, loopList, torquePlot, transmissionPlot } from './plots.js';
import { NO_SPRING, springCut, springList } from './springs.js';
import { ENGINE_SETTINGS, toFile } from './scene.js';
import { screenField, screenWords } from './fields.js';
import { newResult } from './store.js';
import { clear, html, points, svg } from './svg.js';

const STAGES = { sampling: 'Sampling linkages', collision: 'Checking collisions', refining: 'Refining the best' };
/** A family's label from the engine's list (its file word until the list is loaded). */
function familyLabel(store, id) {
  const family = store.families.find((f) => f.id === id);
  return family ? family.label : id;
}

/** Seconds one way through the motion at speed 1. */
const TRAVEL_SECONDS = 3;
/** Frames of an exported motion (20 a second over one travel). */
const EXPORT_FRAMES = 60;

/** `text` with its first letter in lower case, to go on after a colon. */
const lowerFirst = (text) => text.charAt(0).toLowerCase() + text.slice(1);

/** What a design depends on in the drawing (settings may change without hiding it). */
export function geometryKey(scene) {
  return JSON.stringify([
    // A body's mass (or its material and thickness) changes the torque, not the design.
    // Nor does a body's name.
    scene.fixed_bodies.map(({ name, ...body }) => body),
    scene.moving_bodies.map(({ mass_kg, material, thickness, name, ...body }) => body), scene.linkage_region || null,
    scene.avoid_regions || [], scene.must_hit_poses || [],
  ]);
}

/** What a person calls a design's linkage: the engine writes it (older files name the family only). */
export function mechanismName(m) {
  if (!m) return '';
  return m.label || m.type.replace('_', '-');
}

export class Results {
  constructor(store, canvas, els, save) {
    this.store = store;
    this.canvas = canvas;
    this.els = els; // {job, jobFill, jobText, design, cancel, player, play, scrub, readout, speed, paths, dims, edit, tab}
    this.save = save; // (blob, filename) => void
    this.fitView = () => {}; // frames the view (set by the app)
    this.controller = null;
    this.epoch = 0; // counts the scenes opened: an answer for an earlier one is dropped
    this.error = null; // {message, issues, scene}: why the last design failed, and for which scene
    this.pos = 0;
    this.dir = 1;
    this.playing = false;
    this.heldPose = null; // the pose a live drag holds the animation at
    this.speed = 1;
    this.last = null;
    this.plot = null;
    this.torque = null;
    this.fab = null; // the Fabricator, which adds its part to the Result tab and follows the animation
    els.design.addEventListener('click', () => this.run());
    this.designTitle = els.design.title;
    els.cancel.addEventListener('click', () => this.cancel());
    els.play.addEventListener('click', () => this.setPlaying(!this.playing));
    els.scrub.addEventListener('input', () => {
      this.setPlaying(false);
      this.pos = (Number(els.scrub.value) / 1000) * (this.frameCount() - 1);
      this.drawFrame();
    });
    els.speed.addEventListener('change', () => { this.speed = Number(els.speed.value) || 1; });
    els.paths.addEventListener('change', () => this.store.setUi({ paths: els.paths.checked }));
    els.dims.addEventListener('change', () => this.store.setUi({ dimensions: els.dims.checked }));
    els.edit.addEventListener('click', () => this.leave());
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

  frameCount() {
    return this.result?.analysis?.frames.length || 0;
  }

  /** Shows the animation (when there is a fresh design). */
  enter() {
    if (!this.fresh() || !this.result.analysis) return;
    this.store.setUi({ showResult: true, selection: null });
    this.setPlaying(true);
  }

  /** While the result is shown, moves its animation to input pose `i` and pauses there; false when
   * no result is shown (the pose bar then selects the pose for editing). */
  showPose(i) {
    if (!this.store.ui.showResult || !this.pauseAt(i)) return false;
    this.store.setUi({ pose: i });
    this.store.hint(`Pose ${i + 1}, as the design reaches it. Press Play to move on, or Edit drawing to change the poses.`);
    return true;
  }

  /** Pauses the animation where the design shown reaches input pose `i`; false when it has no such pose. */
  pauseAt(i) {
    const pose = this.result?.analysis?.poses?.[i];
    if (!pose) return false;
    this.setPlaying(false);
    this.pos = pose.frame;
    this.drawFrame();
    return true;
  }

  /** Every point the motion shown passes (its bodies and joints at each frame), to frame the view by;
   * none when no design is shown. */
  motionPoints() {
    const r = this.result;
    if (!this.store.ui.showResult || !r?.analysis) return [];
    const bodies = r.scene.moving_bodies;
    return r.analysis.frames.flatMap((f) => [...f.joints, ...f.bodies.flatMap((pose, k) => placed(bodies[k].polygon, pose))]);
  }

  /** Back to editing: the animation stops and the poses are editable again. */
  leave() {
    if (!this.store.ui.showResult) return;
    this.setPlaying(false);
    this.store.setUi({ showResult: false });
  }

  /** Keeps the canvas and the player in step with the state (called on every change). */
  sync() {
    // In live mode the last design stays up while the next one is computed for the edited poses.
    const current = this.fresh() || (this.store.ui.live && this.liveBusy);
    const show = !!this.store.ui.showResult && current && !!this.result?.analysis;
    this.canvas.resultShown = show;
    this.els.player.hidden = !show;
    this.els.show.hidden = show || !this.fresh() || !this.result?.analysis;
    if (!show) this.setPlaying(false);
    this.fab?.sync(show);
    // While a design runs, its progress bar and Cancel take the Design button's place.
    this.els.design.hidden = !!this.controller;
    const nothingMoves = this.store.scene.moving_bodies.length === 0;
    this.els.design.disabled = nothingMoves;
    this.els.design.title = nothingMoves ? 'Draw a moving body first: a linkage needs something to move' : this.designTitle;
  }

  /** Plays or pauses the design shown (nothing when none is). */
  togglePlaying() {
    if (this.store.ui.showResult && this.result?.analysis) this.setPlaying(!this.playing);
  }

  setPlaying(on) {
    if (on && this.frameCount() < 2) on = false;
    this.playing = on;
    this.els.play.textContent = on ? '❚❚ Pause' : '▶ Play';
    this.els.play.setAttribute('aria-pressed', String(on));
    if (on && !this.raf) {
      this.last = null;
      this.raf = requestAnimationFrame((t) => this.tick(t));
    }
  }

  tick(t) {
    this.raf = null;
    if (!this.playing) return;
    const n = this.frameCount();
    if (this.last !== null && n > 1) {
      const dt = Math.min((t - this.last) / 1000, 0.1);
      this.pos += (this.dir * dt * this.speed * (n - 1)) / TRAVEL_SECONDS;
      if (this.pos >= n - 1) { this.pos = n - 1; this.dir = -1; }
      if (this.pos <= 0) { this.pos = 0; this.dir = 1; }
      this.drawFrame();
    }
    this.last = t;
    this.raf = requestAnimationFrame((u) => this.tick(u));
  }

  /** The configuration at fractional frame `pos`, interpolated between neighbouring frames. */
  frameAt(pos) {
    const frames = this.result.analysis.frames;
    const i = Math.max(0, Math.min(frames.length - 1, Math.floor(pos)));
    const j = Math.min(frames.length - 1, i + 1);
    const t = Math.max(0, Math.min(1, pos - i));
    const a = frames[i], b = frames[j];
    const mix = (x, y) => x + (y - x) * t;
    const springs = (this.result.balance?.springs || []).filter((s) => s.ends[j]).map((s) => ({
      kind: s.kind,
      ends: [0, 1].map((e) => [mix(s.ends[i][e][0], s.ends[j][e][0]), mix(s.ends[i][e][1], s.ends[j][e][1])]),
    }));
    return {
      springs,
      crank_deg: mix(a.crank_deg, b.crank_deg),
      joints: a.joints.map((p, k) => [mix(p[0], b.joints[k][0]), mix(p[1], b.joints[k][1])]),
      bodies: a.bodies.map((p, k) => [mix(p[0], b.bodies[k][0]), mix(p[1], b.bodies[k][1]), mix(p[2], b.bodies[k][2])]),
    };
  }

  drawFrame() {
    if (!this.result?.analysis) return;
    const frame = this.frameAt(this.pos);
    this.canvas.renderResultFrame(frame);
    const n = this.frameCount();
    this.els.scrub.value = String(n > 1 ? Math.round((this.pos / (n - 1)) * 1000) : 0);
    this.els.readout.textContent = `crank ${frame.crank_deg.toFixed(1)}°`;
    this.canvas.root.dataset.crank = frame.crank_deg.toFixed(3);
    this.plot?.moveCursor(frame.crank_deg);
    this.torque?.moveCursor(frame.crank_deg);
    const frames = this.result.analysis.frames, first = frames[0].crank_deg, last = frames[n - 1].crank_deg;
    this.fab?.frame(last === first ? 0 : (frame.crank_deg - first) / (last - first));
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
            ? `Designed, but it cannot be printed at ${checked?.scale ?? design.build.checked}: the Result tab says why and what to do.`
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
      this.error = { message: e.message, issues: e.issues || [], scene: JSON.stringify(scene) };
      this.store.setUi({ tab: 'result' });
      this.store.hint(e.issues?.length ? 'Cannot design this yet: the Result tab lists what to change.' : `Cannot design: ${e.message}`);
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

  /** Starts moving joint `name` of the design shown, if one is shown: the animation goes to the
   * first pose (where a design gives its joints) and waits there. */
  beginJointDrag(name) {
    const r = this.result;
    if (!this.canvas.showingResult() || !r?.analysis || !r.mechanism?.joints?.[name]) return false;
    this.setPlaying(false);
    this.pos = 0;
    this.drawFrame();
    this.jointDrag = { name, before: r, target: null, moved: false, ended: false };
    this.store.hint(`Joint ${name}: drag it; the linkage is simulated and checked again as it moves (Ctrl+Z undoes).`);
    return true;
  }

  /** The joint being moved goes to world point `w` (at the first pose). */
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

  /** Moves joints of the design shown (`{name: [x, y]}`), as one undoable step. */
  async placeJoints(joints) {
    const r = this.result;
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
   */
  async runEdit(drag) {
    this.editBusy = true;
    const base = drag.before;
    while (drag.target) {
      const w = drag.target;
      drag.target = null;
      try {
        const answer = await api.edit(base.scene, base.design, base.which, { [drag.name]: w });
        if (answer.design) {
          const r = newResult({ design: answer.design, scene: base.scene, key: base.key, warnings: base.warnings });
          Object.assign(r, { mechanism: answer.design.mechanism, motion: answer.design.motion, metrics: answer.design.metrics, analysis: answer.analysis });
          r.verified = { ok: answer.violations.length === 0, violations: answer.violations };
          this.store.setResult(r);
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
          this.canvas.rejectedJoint = { name: drag.name, at: w, message: answer.rejected.message };
          this.store.hint(`Joint ${drag.name} cannot go to (${w[0].toFixed(1)}, ${w[1].toFixed(1)}): ${answer.rejected.message}.`);
        }
      } catch (e) {
        this.store.hint(`Cannot move joint ${drag.name}: ${e.message}`);
      }
      this.pos = 0;
      this.drawFrame();
      this.store.changed('result');
    }
    this.editBusy = false;
    if (drag.ended) this.finishJointDrag();
  }

  finishJointDrag() {
    const drag = this.jointDrag;
    this.jointDrag = null;
    this.canvas.rejectedJoint = null;
    if (drag?.moved) this.store.editResult(`move joint ${drag.name}`, drag.before);
    this.drawFrame();
  }

  /** Forgets the design and any error (a new scene was opened); a design, a live redesign or parts
   * still being made for the scene before are stopped, and what they answer is dropped. */
  clear() {
    this.epoch += 1;
    this.controller?.abort();
    this.controller = null;
    this.progress(null);
    this.livePending = false;
    this.fab?.forget();
    this.store.setResult(null);
    this.error = null;
    this.good = null;
    this.setPlaying(false);
    this.store.changed('result');
  }

  /**
   * Live mode: after a pose was moved, designs again from the last good design (a warm start, fast),
   * at most one request at a time; edits made meanwhile are picked up by one more run.
   */
  poseEdited() {
    if (!this.store.ui.live || this.controller || !this.lastGood()) return;
    // While a pose is dragged the design shown waits where it reaches that pose, so the person sees
    // the two meet as they move it (and the page leaves the cores to the redesign); it plays again
    // when the pose is let go.
    this.heldPose = this.store.ui.pose;
    this.pauseAt(this.heldPose);
    if (this.liveBusy) {
      this.livePending = true;
      return;
    }
    this.runLive();
  }

  /** A pose dragged in live mode was let go: the design shown plays again. */
  poseReleased() {
    if (this.heldPose == null) return;
    this.heldPose = null;
    if (this.canvas.showingResult()) this.setPlaying(true);
  }

  lastGood() {
    const r = this.result;
    if (r?.design?.status === 'ok') this.good = r.design;
    return this.good;
  }

  async runLive() {
    this.liveBusy = true;
    this.livePending = false;
    const scene = toFile(this.store.scene);
    const key = geometryKey(this.store.scene);
    const epoch = this.epoch;
    try {
      // The motion analysis comes with the design: one round trip less per step of the drag.
      let analysis = null;
      // The design that follows the one shown, not the cheapest: a small drag moves the linkage a little.
      const request = { scene, from: this.lastGood(), print_settings: savedPrintSettings(), analysis: true, follow: true };
      const design = await api.designStream(request, (event) => { if (event.name === 'analysis') analysis = event.data; });
      if (epoch !== this.epoch) {
        // Another scene was opened: this answer is not for it.
      } else if (design?.status === 'ok') {
        this.store.setResult(newResult({ design, scene, key }));
        await this.select(null, { keep: true, analysis });
        this.verify();
        this.store.hint(`Live: redesigned for the moved pose (cost ${design.metrics.cost.toFixed(2)}).`);
      } else if (design) {
        this.store.hint('Live: no linkage reaches the poses as they are now; move the pose back a little, or press Design linkage.');
      }
    } catch (e) {
      if (epoch === this.epoch) this.store.hint(`Live: ${e.message}`);
    }
    // The scene the last live request answered (a design or not), for whoever waits on it.
    this.liveAnswered = scene;
    this.liveBusy = false;
    if (this.livePending) this.runLive();
    else {
      this.sync();
      this.store.changed('result');
    }
  }

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

  progress(p) {
    const { job, jobFill, jobText } = this.els;
    job.hidden = !p;
    if (!p) return;
    jobFill.style.width = `${Math.round(p.fraction * 100)}%`;
    jobText.textContent = p.text;
  }

  /** Shows mechanism `which` (null: the design itself) of the current result; `analysis`, its motion
   * analysis when it came with the design. */
  async select(which, { keep = false, analysis = null } = {}) {
    const r = this.result;
    if (!r) return;
    this.store.showMechanism(which);
    const d = r.design;
    this.plot = null;
    this.torque = null;
    if (d.status !== 'ok' || !r.mechanism) {
      this.store.changed('result');
      return;
    }
    try {
      const before = this.frameCount();
      const got = analysis || await api.simulate(r.scene, d, which);
      // Another design (or mechanism) shown meanwhile: this analysis is not for it.
      if (!this.store.answerResult(r, which, { analysis: got })) return;
      const held = keep && this.heldPose != null ? r.analysis.poses?.[this.heldPose] : null;
      if (held) {
        this.pos = held.frame;
      } else if (keep && before > 1) {
        // The same place along the motion, in the new design's frames.
        this.pos = Math.min((this.pos / (before - 1)) * (r.analysis.frames.length - 1), r.analysis.frames.length - 1);
      } else {
        this.pos = 0;
        this.dir = 1;
      }
      // A live result arrives while a pose is being dragged: that drag keeps its pose.
      this.store.setUi(keep ? { showResult: true } : { showResult: true, selection: null });
      this.sync();
      this.drawFrame();
      this.setPlaying(!held);
    } catch (e) {
      if (!this.store.isShown(r, which)) return;
      this.error = { message: e.message, issues: e.issues || [] };
    }
    this.store.changed('result');
  }

  /**
   * Each moving body's mass, as the torque weighs it. A printed model's bodies weigh what their print
   * does at the model's scale (the real object's mass does not count); a full-size build's weigh the
   * scene's `mass_kg`, editable here (empty: its material's weight), and the torque is computed again
   * at once.
   */
  massTable(r) {
    const parts = r.analysis.torque?.parts || [];
    const build = parseBuild(r.scene.build ?? DEFAULT_BUILD);
    const full = build?.kind === 'full';
    const weighed = (i) => {
      const part = r.mechanism.parts.find((p) => p.kind === 'body' && p.body === i);
      return parts.find((p) => p.name === part?.name);
    };
    const rows = r.scene.moving_bodies.map((body, i) => {
      const mass = weighed(i)?.mass_kg;
      if (!full) {
        return html('tr', {}, [html('th', { text: body.name }), html('td', { 'data-printed-mass': i, text: mass === undefined ? '–' : `${kilograms(mass)} kg` })]);
      }
      const change = (e) => {
        const text = e.target.value.trim(), v = Number(text);
        if (text !== '' && !(Number.isFinite(v) && v > 0 && v <= 1e5)) {
          this.store.hint('A mass is a number of kilograms, more than 0 and at most 100000; leave it empty to weigh the body in its material.');
          return;
        }
        // The design stays (a mass changes no geometry): its torque is weighed again, and springs
        // found for the old masses are dropped (the status line says so).
        this.store.setBodyMass(r, i, text === '' ? null : v);
        const hadSprings = !!r.balance;
        this.select(r.which, { keep: true }).then(() => this.store.hint(`${body.name} weighs ${text === '' ? 'what its material does' : `${v} kg`} now: the torque is weighed again${hadSprings ? '; the springs were for the old masses, so press Suggest springs again' : ''}.`));
      };
      return html('tr', {}, [
        html('th', { text: body.name }),
        // Empty, the field shows what the body weighs in its material: the number alone, so that it
        // fits (the note below names the material).
        html('td', {}, [html('input', {
          type: 'number', min: '0', step: 'any', 'data-mass': i, 'aria-label': `mass of ${body.name}, kg`,
          value: body.mass_kg ?? '', placeholder: mass === undefined ? '' : kilograms(mass),
          title: `Empty: ${body.name} weighs ${mass === undefined ? 'what it does' : `${kilograms(mass)} kg`} in ${build.material}`,
          onchange: change,
        }), ' kg']),
      ]);
    });
    // The scale the model is weighed at: the one the design was checked at (an auto scale decided).
    const checked = parseBuild(r.design.build?.checked)?.scale ?? build?.scale;
    const note = full
      ? `The real masses: type a body’s, or leave it empty to weigh it in ${build.material} (the grey number).`
      : `As printed${checked && checked !== 'auto' ? ` at ${checked}` : ''}: a printed model weighs what its parts do. A body’s real mass counts when it is built full size (Settings › Build).`;
    return html('div', {}, [
      html('table', { class: 'masses' }, [html('tr', {}, [html('th', { text: 'Body' }), html('th', { text: 'Mass' })]), ...rows]),
      html('p', { class: 'note', 'data-masses': full ? 'real' : 'printed', text: note }),
    ]);
  }

  /** Asks for the springs that balance the mechanism shown; they are drawn and listed when they come. */
  async suggestSprings() {
    const r = this.result;
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
      this.store.hint(`Cannot suggest springs: ${e.message}`);
    } finally {
      this.balancing = false;
      this.drawFrame();
      this.store.changed('result');
    }
  }

  /**
   * Checks the mechanism shown independently (the server's verifier). The verifier reads a design's own
   * mechanism only, so an alternative is checked as the design of a file of its own.
   */
  async verify() {
    const r = this.result;
    const which = r.which;
    let answer;
    try {
      answer = await api.check(r.scene, designShown(r.design, which));
    } catch (e) {
      answer = { ok: false, violations: [{ constraint: 'check', message: e.message }] };
    }
    // Dropped when another design or mechanism is shown by now.
    this.store.answerResult(r, which, { verified: answer });
  }

  async download(kind) {
    const r = this.result;
    if (!r) return;
    // Named as the scene is now (it may have been renamed since it was designed).
    const base = (this.store.scene.name || 'design').replace(/[^\w.-]+/g, '_');
    if (kind === 'json') {
      const file = JSON.stringify(designShown(r.design, r.which), null, 2);
      this.save(new Blob([file], { type: 'application/json' }), `${base}.design.json`);
      return;
    }
    try {
      const blob = await api.render(r.scene, r.design, kind, r.which);
      this.save(blob, `${base}.${kind}.svg`);
    } catch (e) {
      this.store.hint(`Cannot make the picture: ${e.message}`);
    }
  }

  /** The motion as shown on the canvas, one travel from the first pose to the last, as an animated GIF
   * or a WebM video of TRAVEL_SECONDS. */
  async exportMotion(kind) {
    const r = this.result;
    const frames = r?.analysis?.frames;
    if (!frames?.length || !this.canvas.showingResult() || this.exporting) {
      this.store.hint('Show the design first (▶ Show the design), then export its motion.');
      return;
    }
    this.exporting = true;
    const base = (this.store.scene.name || 'design').replace(/[^\w.-]+/g, '_');
    const count = Math.min(EXPORT_FRAMES, frames.length);
    const frameAt = (i) => frames[Math.round((i * (frames.length - 1)) / Math.max(count - 1, 1))];
    const wasPlaying = this.playing;
    this.setPlaying(false);
    const show = (i) => this.canvas.renderResultFrame(frameAt(i));
    this.store.hint(`Recording the motion (${count} frames)…`);
    try {
      if (kind === 'gif') {
        const { frames: images } = await captureFrames(this.canvas.root, count, show);
        const delay = Math.max(2, Math.round((100 * TRAVEL_SECONDS) / count));
        this.save(new Blob([encodeGif(images, delay)], { type: 'image/gif' }), `${base}.motion.gif`);
      } else {
        const video = await recordWebm(this.canvas.root, count, count / TRAVEL_SECONDS, show);
        if (!video) throw new Error('this browser cannot record WebM video; the GIF works everywhere');
        this.save(video, `${base}.motion.webm`);
      }
      this.store.hint(`Saved the motion as ${kind === 'gif' ? 'an animated GIF' : 'a WebM video'}.`);
    } catch (e) {
      this.store.hint(`Cannot record the motion: ${e.message}`);
    } finally {
      this.exporting = false;
      this.drawFrame();
      if (wasPlaying) this.setPlaying(true);
    }
  }

  /** The Result tab. */
  renderTab(host) {
    clear(host);
    const r = this.result;
    // An error speaks of the scene it came from: after an edit or an undo it may not hold.
    const error = this.error && (!this.error.scene || this.error.scene === JSON.stringify(toFile(this.store.scene))) ? this.error : null;
    if (error) {
      // Each problem once, where it is on screen; clicking one that names a shape selects it.
      const item = (i) => {
        const at = screenField(i.field, this.store.scene);
        const select = at.selection ? () => this.store.setUi({ selection: at.selection, pose: at.pose ?? this.store.ui.pose, tab: 'object' }) : null;
        return html('li', { class: i.severity }, [
          select ? html('a', { href: '#', text: at.text, onclick: (e) => { e.preventDefault(); select(); } }) : html('b', { text: at.text }),
          `: ${screenWords(i.message, this.store.scene, this.store.families)}`,
        ]);
      };
      host.append(html('div', { class: 'callout error' }, [
        html('b', { text: 'Cannot design this yet' }),
        error.issues.length ? html('ul', {}, error.issues.map(item)) : html('p', { text: error.message }),
      ]));
    }
    if (!r) {
      if (!error) host.append(html('p', { class: 'empty', text: 'No design yet. Draw a fixed body, a moving body and its poses, then press “Design linkage”.' }));
      return;
    }
    const d = r.design;
    // While a live redesign follows a dragged pose, the next design is on its way: no warning.
    const following = this.store.ui.live && (this.liveBusy || this.heldPose != null);
    if (!this.fresh() && !following) {
      host.append(html('div', { class: 'callout warn', 'data-stale': '', text: 'The drawing changed since this design. Press “Design linkage” to update it.' }));
    }
    if (d.status !== 'ok') {
      host.append(html('div', { class: 'callout warn' }, [
        html('b', { text: 'No linkage found' }),
        html('p', { class: 'reason', text: screenWords(d.reason || '', this.store.scene, this.store.families) }),
        // When the drawing's size does not suit the build, the reason says so first.
        /does not suit the build/.test(d.reason || '') ? this.buildActions(d.build, d.reason) : null,
      ]));
      host.append(...this.buildLines(d));
      host.append(statsLine(d));
      return;
    }
    const m = r.metrics || d.metrics;
    host.append(html('h3', { text: r.which === null ? `Best design: ${mechanismName(d.mechanism)}` : `Alternative ${r.which + 1}: ${mechanismName(r.mechanism)}` }));
    host.append(...this.buildLines(d));
    // The check says whether the linkage is sound; the pose errors say how closely it does the job.
    const errors = poseErrors(m, r.analysis, r.scene);
    if (r.verified && !r.verified.ok) {
      host.append(html('div', { class: 'callout error' }, r.verified.violations.map((v) => html('p', { text: `${v.constraint}: ${v.message}` }))));
    } else if (r.verified) {
      host.append(errors
        ? reachBadge(errors, r.scene)
        : html('p', { class: 'badge verified', text: 'Re-simulated independently: no hard constraint is violated (the poses are not measured yet)' }));
    }
    if (errors) host.append(poseTable(errors, r.scene));
    host.append(html('table', { class: 'metrics' }, [
      ['Cost (lower is better)', m.cost.toFixed(3)],
      ['Accuracy (mean squared error)', m.accuracy.toPrecision(3)],
      ['Smoothness (path/chord)', m.smoothness.toFixed(3)],
      ['Distance from region', m.location.toFixed(2)],
      ['Mean link length', m.size.toFixed(1)],
      ['Worst transmission angle', transmissionWords(m, r.motion || d.motion, r.scene)],
    ].map(([k, v]) => html('tr', {}, [html('th', { text: k }), html('td', { text: v })]))));
    host.append(statsLine(d));
    for (const w of r.warnings || []) host.append(html('p', { class: 'note', text: `Note: ${w.field}: ${w.message}` }));
    host.append(html('h3', { text: 'Joints' }), this.jointTable(r));

    const options = [null, ...d.alternatives.map((_, i) => i)];
    if (options.length > 1) {
      host.append(html('h3', { text: 'Alternatives' }));
      host.append(html('div', { class: 'thumbs' }, options.map((w) => this.thumbnail(w))));
    }
    host.append(html('h3', { text: 'Downloads' }));
    host.append(html('div', { class: 'inline' }, [
      html('button', { text: 'Design JSON', title: 'the design/1 file', onclick: () => this.download('json') }),
      html('button', { text: 'Animation SVG', title: 'open it in a browser to watch the motion', onclick: () => this.download('animation') }),
      html('button', { text: 'Design sheet SVG', onclick: () => this.download('design') }),
      html('button', { text: 'Motion GIF', 'data-export': 'gif', title: 'the motion as shown, an animated picture', onclick: () => this.exportMotion('gif') }),
      html('button', { text: 'Motion video', 'data-export': 'webm', title: 'the motion as shown, a WebM video', onclick: () => this.exportMotion('webm') }),
    ]));
    this.fab?.render(host);
    if (r.analysis) {
      const a = r.analysis;
      this.plot = transmissionPlot(a);
      host.append(html('h3', { text: 'Transmission angles over the motion' }), this.plot.element);
      this.torque = a.torque ? torquePlot(a, r.balance) : null;
      if (this.torque) {
        host.append(html('h3', { text: 'Torque to drive the crank' }), this.torque.element, this.massTable(r));
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
      host.append(html('h3', { text: 'Error at each pose' }), errorPlot(a, r.scene));
      host.append(html('h3', { text: 'Loops' }), loopList(a));
      this.drawFrame();
    }
  }

  /**
   * How the design is built, from its file's `build` record: “Printed model at 1:10 (auto), 214 × 180
   * mm” or “Full size, plywood”; when it cannot be built so, a warning with the engine's reason and
   * buttons that change the build and design again; when the scene now asks for another build, a note.
   */
  buildLines(d) {
    const record = d.build;
    const text = describeRecord(record);
    if (!text) return [];
    const out = [html('p', { class: 'build-line', 'data-build': record.checked, text })];
    if (d.status === 'ok' && record.buildable === false) {
      const model = parseBuild(record.checked);
      const scale = model?.kind === 'model' ? model.scale : record.checked;
      const reason = (record.reason || '').replace(/^./, (c) => c.toUpperCase());
      out.push(html('div', { class: 'callout warn', 'data-unbuildable': 'true', role: 'status' }, [
        html('b', { text: `This linkage cannot be printed at ${scale}` }),
        reason ? html('p', { text: /[.!?]$/.test(reason) ? reason : `${reason}.` }) : null,
        this.buildActions(record, record.reason),
      ]));
    }
    const now = parseBuild(this.store.scene.build ?? DEFAULT_BUILD);
    const asked = parseBuild(record.asked);
    if (now && asked && JSON.stringify(now) !== JSON.stringify(asked)) {
      out.push(html('p', { class: 'note', 'data-build-changed': 'true',
        text: `Settings › Build is now “${describe(this.store.scene.build ?? DEFAULT_BUILD)}”: press “Design linkage” to design for it.` }));
    }
    return out;
  }

  /** Buttons that set the build and design again: the scale the engine's reason suggests (when it
   * names one), the automatic scale (when another was asked for) and full size. */
  buildActions(record, reason) {
    const asked = parseBuild(record?.asked ?? DEFAULT_BUILD);
    const checked = parseBuild(record?.checked ?? '');
    const suggested = suggestedScale(reason);
    const choices = [];
    if (suggested && suggested !== checked?.scale) choices.push(['scale', `model:${suggested}`, `Print at ${suggested} and redesign`]);
    if (asked?.kind === 'model' && asked.scale !== 'auto') choices.push(['auto', 'model:auto', 'Auto scale and redesign']);
    if (asked?.kind !== 'full') choices.push(['full', 'full:plywood', 'Build it full size and redesign']);
    return html('div', { class: 'inline actions' }, choices.map(([action, word, text]) => html('button', {
      text, 'data-build-action': action, title: `Settings › Build: ${describe(word)}; then design again`,
      onclick: () => this.rebuildAs(word),
    })));
  }

  /** Sets the scene's build (one undo step, as in Settings) and designs again. */
  rebuildAs(word) {
    if (this.controller) return;
    this.store.edit(`build ${word}`, (s) => { s.build = word; });
    this.store.hint(`Build: ${describe(word)}. Designing again…`);
    this.run();
  }

  /** The joints of the mechanism shown at the first pose: type a place to move one (as a drag does),
   * tick Pin to keep it there in the next design. */
  jointTable(r) {
    const units = this.store.scene.units || 'mm';
    const pinned = this.store.scene.pinned_joints || {};
    const row = (name) => {
      const [x, y] = r.mechanism.joints[name];
      const place = (axis) => (e) => {
        const v = Number(e.target.value);
        if (e.target.value.trim() === '' || !Number.isFinite(v)) return;
        const p = [...r.mechanism.joints[name]];
        p[axis] = v;
        this.placeJoints({ [name]: p });
      };
      const pin = (e) => {
        const on = e.target.checked;
        this.store.edit(`${on ? 'pin' : 'unpin'} joint ${name}`, (s) => {
          const pins = { ...(s.pinned_joints || {}) };
          if (on) pins[name] = [...r.mechanism.joints[name]]; else delete pins[name];
          if (Object.keys(pins).length) s.pinned_joints = pins; else delete s.pinned_joints;
        });
        this.store.hint(on
          ? `Joint ${name} is pinned where it is: the next design keeps it there.`
          : `Joint ${name} is free again.`);
      };
      return html('tr', {}, [
        html('th', { text: name }),
        html('td', {}, [html('input', { type: 'number', step: 'any', value: fmt(x), 'data-joint-x': name, 'aria-label': `${name} x (${units})`, onchange: place(0) })]),
        html('td', {}, [html('input', { type: 'number', step: 'any', value: fmt(y), 'data-joint-y': name, 'aria-label': `${name} y (${units})`, onchange: place(1) })]),
        html('td', {}, [html('label', {}, [html('input', { type: 'checkbox', checked: name in pinned, 'data-pin': name, onchange: pin }), ' pin'])]),
      ]);
    };
    return html('table', { class: 'joint-table', title: `Joint places at the first pose, ${units}. Drag a joint on the canvas, or type here.` }, [
      html('tr', {}, [html('th', { text: 'joint' }), html('th', { text: `x (${units})` }), html('th', { text: `y (${units})` }), html('th', { text: '' })]),
      ...Object.keys(r.mechanism.joints).sort().map(row),
    ]);
  }

  /** A small picture of one design at its first pose, to pick it. */
  thumbnail(which) {
    const r = this.result;
    const d = r.design;
    const m = which === null ? d.mechanism : d.alternatives[which].mechanism;
    const metrics = which === null ? d.metrics : d.alternatives[which].metrics;
    const scene = r.scene;
    const bodies = scene.moving_bodies.map((b) => placed(b.polygon, b.poses[0]));
    const joints = m.joints;
    // Framed on the linkage, with a quarter of its extent around it: next to a large body a small
    // linkage would be a few pixels, and the alternatives would all look alike. The bodies are cut.
    const jb = bounds(Object.values(joints));
    const margin = 0.25 * Math.max(jb.maxX - jb.minX, jb.maxY - jb.minY, 1e-9);
    const bb = { minX: jb.minX - margin, maxX: jb.maxX + margin, minY: jb.minY - margin, maxY: jb.maxY + margin };
    const w = 84, h = 54;
    const k = Math.min(w / (bb.maxX - bb.minX), h / (bb.maxY - bb.minY));
    // Centred both ways.
    const [cx, cy] = [(bb.minX + bb.maxX) / 2, (bb.minY + bb.maxY) / 2];
    const s = (p) => [w / 2 + (p[0] - cx) * k, h / 2 - (p[1] - cy) * k];
    const pic = svg('svg', { viewBox: `0 0 ${w} ${h}`, width: w, height: h });
    for (const b of scene.fixed_bodies) pic.append(svg('polygon', { class: 'fixed', points: points(b.polygon.map(s)) }));
    bodies.forEach((b, i) => pic.append(svg('polygon', { class: 'moving', style: `--c:${bodyColour(i)}`, points: points(b.map(s)) })));
    for (const part of m.parts.filter((p) => p.kind === 'link')) {
      const pts = part.joints.filter((n) => joints[n]).map((n) => s(joints[n]));
      pic.append(svg(pts.length > 2 ? 'polygon' : 'polyline', { class: 'link thin', points: points(pts) }));
    }
    for (const p of Object.values(joints)) {
      const q = s(p);
      pic.append(svg('circle', { class: 'joint', cx: q[0], cy: q[1], r: 2 }));
    }
    const label = which === null ? 'Best' : `#${which + 1}`;
    return html('button', {
      class: r.which === which ? 'thumb selected' : 'thumb',
      title: `${label}: ${mechanismName(m)}, cost ${metrics.cost.toFixed(3)}${worstMiss(metrics, r.scene)}`,
      'data-which': which === null ? 'best' : String(which),
      onclick: async () => {
        await this.select(which);
        if (this.result?.design !== d || this.result.which !== which) return;
        this.verify();
        const m = which === null ? d.mechanism : d.alternatives[which].mechanism;
        this.store.hint(`${which === null ? 'Best design' : `Alternative ${which + 1}`}: ${mechanismName(m)}, cost ${metrics.cost.toFixed(2)}.`);
      },
    }, [pic, html('span', { text: `${label} · ${metrics.cost.toFixed(2)}` })]);
  }
}

/** The design file with the mechanism shown (`which`: null for the best) as its design, the others
 * after it as alternatives, the former best first: what a person viewing an alternative downloads. */
function designShown(d, which) {
  const shown = which === null ? null : d.alternatives?.[which];
  if (!shown) return d;
  const best = { mechanism: d.mechanism, motion: d.motion, metrics: d.metrics };
  return { ...d, ...shown, alternatives: [best, ...d.alternatives.filter((_, i) => i !== which)] };
}

/** A mass in kilograms to three figures (a printed part weighs grams, a bed tens of kilograms). */
const kilograms = (kg) => String(Number(kg.toPrecision(3)));

/** The largest pose miss a design file states for a mechanism (files before it was added do not). */
function worstMiss(metrics, scene) {
  const w = metrics.worst_pose_error;
  if (!w || !Number.isFinite(w.position) || !Number.isFinite(w.angle_deg)) return '';
  return `, poses missed by at most ${fmt(w.position)} ${scene.units || 'mm'} and ${fmt(Math.abs(w.angle_deg))}°`;
}

/** The worst transmission angle, where along the motion it is, and whether it leaves the comfortable band. */
function transmissionWords(m, motion, scene) {
  let text = `${m.min_transmission_deg.toFixed(1)}°`;
  const at = m.min_transmission_crank_deg;
  const span = motion ? motion.crank_end_deg - motion.crank_start_deg : 0;
  if (Number.isFinite(at) && span !== 0) {
    const share = Math.min(1, Math.max(0, (at - motion.crank_start_deg) / span));
    text += ` at ${Math.round(100 * share)}% of the motion`;
  }
  const comfortable = scene.settings?.comfortable_transmission_deg ?? ENGINE_SETTINGS.comfortable_transmission_deg;
  if (m.min_transmission_deg < comfortable) text += `, under the comfortable ${comfortable}°`;
  return text;
}

function statsLine(d) {
  const s = d.stats;
  return html('p', { class: 'note', text: `${s.valid} valid of ${s.samples} samples in ${s.seconds.total.toFixed(1)} s, seed ${s.seed}.` });
}
