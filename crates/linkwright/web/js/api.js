// @ts-check
// The server's API (docs/api.md). Errors come back as ApiError with the server's message and issues.
// The shapes of the documents and answers are written once here, as the docs describe them; what the
// server sends is taken as these (it is the app's own server, and the documents are validated there).

/**
 * @typedef {import('./geom.js').Point} Point
 * @typedef {import('./geom.js').Pose} Pose
 * @typedef {import('./scene.js').Scene} Scene
 */

/**
 * One finding about a request's documents, its field named as a path (`moving_bodies[0].poses`).
 * @typedef {{field: string, message: string, severity?: 'error' | 'warning'}} Issue
 */

/**
 * A design/1 file (docs/formats.md): a linkage found (`ok`), or the reason none was.
 * @typedef {DesignFound | DesignNotFound} Design
 * @typedef {object} DesignCommon
 * @property {'design/1'} linkwright
 * @property {string} scene  the scene's name
 * @property {Alternative[]} alternatives
 * @property {Stats} stats
 * @property {BuildRecord} [build]  the build it was checked for (absent in older files)
 * @typedef {DesignCommon & Alternative & {status: 'ok'}} DesignFound
 * @typedef {DesignCommon & {status: 'no_solution', reason: string, mechanism?: undefined, motion?: undefined,
 *   metrics?: undefined}} DesignNotFound
 *
 * A mechanism with its motion and metrics: the design's own, or one of its alternatives.
 * @typedef {{mechanism: Mechanism, motion: Motion, metrics: Metrics}} Alternative
 *
 * @typedef {object} Mechanism
 * @property {string} type  its family's id
 * @property {string} [label]  what a person calls it ("four-bar linkage")
 * @property {Record<string, Point>} joints  every joint at the first pose, by name
 * @property {MechanismPart[]} parts
 * @property {{pivot: string, tip: string}} driver  the crank: its ground pivot and its moving joint
 * @property {Slider | null} [slider]
 *
 * @typedef {{name: string, kind: 'fixed' | 'body' | 'link', joints: string[], body?: number}} MechanismPart
 *   A rigid part and the joints it carries; a `body` part is moving body number `body`.
 * @typedef {{joint: string, point: Point, direction: Point, stroke: [number, number]}} Slider
 *   A slider-crank's guide: its joint moves on the line through `point` along `direction`.
 * @typedef {{crank_start_deg: number, crank_end_deg: number, pose_crank_deg: number[]}} Motion
 *
 * @typedef {object} Metrics
 * @property {number} accuracy
 * @property {number} smoothness
 * @property {number} location
 * @property {number} size
 * @property {number} [transmission]
 * @property {number} cost
 * @property {number} min_transmission_deg
 * @property {number} [min_transmission_crank_deg]
 * @property {PoseError[][]} [pose_errors]  per pose, per moving body (absent in older files)
 * @property {PoseError} [worst_pose_error]
 * @property {PoseError & {pose: number, body: string}} [far_from_pose]  only when the design is far from a pose
 * @property {PathError} [path_error]  a path design's: how far its traced curve is from the drawn one
 *
 * @typedef {object} PathError
 * @property {number} max  the largest distance between a point of either curve and the other
 * @property {number} max_rel  it as a share of the drawn curve's size (its box's diagonal)
 * @property {number} mean
 * @property {number} mean_rel
 * @property {Point} at  the drawn curve's point nearest where they are farthest apart
 * @property {{point: number, distance: number, distance_rel: number}} [exact]  of the points to pass
 *   exactly, the one the traced curve passes farthest from
 *
 * @typedef {{position: number, position_rel_d: number, angle_deg: number}} PoseError
 * @typedef {{samples: number, candidates: number, valid: number, seed: number, seconds: {total: number}}} Stats
 * @typedef {object} BuildRecord
 * @property {string} asked  the scene's build
 * @property {string} checked  it with an `auto` scale decided
 * @property {boolean} buildable
 * @property {string} [reason]  why it cannot be built so, and what would help
 * @property {number[]} [model_mm]  a model's width and height
 */

/**
 * The motion of a mechanism (`POST /api/simulate`), for the animation and the plots.
 * @typedef {object} Analysis
 * @property {string[]} joint_names
 * @property {string[]} fixed_joints
 * @property {{joint: string, from: string[], kind: string}[]} dyads
 * @property {Frame[]} frames
 * @property {AnalysisPose[]} poses
 * @property {Loop[]} loops
 * @property {number} min_transmission_deg
 * @property {number} min_transmission_bound_deg
 * @property {number} [comfortable_transmission_deg]  absent in files analysed before it existed
 * @property {Torque} [torque]  when the units are a length and the travel passes no dead point
 *
 * @typedef {{crank_deg: number, joints: Point[], bodies: Pose[], transmission_deg: number[]}} Frame
 *   One step of the motion: the joints (as `joint_names`), the moving bodies' poses, each dyad's
 *   transmission angle.
 * @typedef {{pose: number, crank_deg: number, frame: number, joint_rms: number,
 *   bodies: {max_vertex: number, angle_deg: number}[]}} AnalysisPose
 *   Where the mechanism is nearest input pose `pose`, and how far each body is from it.
 * @typedef {{name: string, kind: string, grashof: boolean, description: string,
 *   links: {role: string, joints: string[], length: number}[]}} Loop
 */

/**
 * The torque to drive the crank (docs/torque-format.md), and with `springs` the counterbalance
 * springs (`POST /api/balance`).
 * @typedef {object} Torque
 * @property {number[]} crank_deg
 * @property {number[]} torque_nm
 * @property {{name: string, mass_kg: number, com: Point, torque_nm: number[]}[]} parts
 * @property {number} peak_nm
 * @property {number} peak_crank_deg
 *
 * @typedef {Torque & {springs: Spring[], torque_with_springs_nm: number[], peak_with_springs_nm: number,
 *   peak_with_springs_crank_deg: number, need: string}} Balance
 * @typedef {ExtensionSpring | TorsionSpring} Spring
 * @typedef {object} ExtensionSpring
 * @property {'extension'} kind
 * @property {{part: string, point: Point}[]} anchors  the ground end, then the moving end
 * @property {number} stiffness_n_per_m
 * @property {number} free_length
 * @property {[number, number]} length_range
 * @property {[number, number]} force_range_n
 * @property {[Point, Point][]} ends  both ends at every step
 * @typedef {object} TorsionSpring
 * @property {'torsion'} kind
 * @property {string} part
 * @property {Point} pivot
 * @property {number} stiffness_nm_per_rad
 * @property {number} free_angle_deg
 * @property {[number, number]} twist_range_deg
 * @property {[number, number]} torque_range_nm
 * @property {[Point, Point][]} ends  the pivot and the part's other joint at every step
 */

/**
 * @typedef {{constraint: string, message: string}} Violation
 * @typedef {{ok: boolean, violations: Violation[]}} CheckAnswer  The server's independent check of a design.
 * @typedef {object} EditAnswer  A design with joints moved: the moved linkage, or which check it fails.
 * @property {DesignFound | null} design
 * @property {Violation[]} violations
 * @property {Analysis | null} analysis
 * @property {{check: string, message: string} | null} rejected
 *
 * @typedef {{id: string, label: string, description: string, max_bodies: number | null}} Family
 * @typedef {{symbol: string, words: string[], millimetres: number}} LengthUnit  A unit a scene may be
 *   drawn in: the scene's word is the unit when, trimmed and with its ASCII letters lowered, it is one
 *   of `words`.
 * @typedef {{name: string, title: string, bodies: number, fixed_bodies: number, poses: number}} ExampleSummary
 * @typedef {{poses_per_body: number, moving_bodies: number} & Record<string, number>} Limits
 * @typedef {{version: string, limits: Limits}} Status
 */

/**
 * Printing and making parts (docs/api-fabricate.md).
 * @typedef {Record<string, unknown>} PrintSettings  print settings by field (`bed` nested), millimetres;
 *   a field left out keeps its default
 * @typedef {object} Fabrication  The answer of `POST /api/fabricate`.
 * @property {string} id
 * @property {number} used  the design made: 0 itself, k its alternative k − 1
 * @property {boolean} checks_ok
 * @property {PrintReport | WorkshopReport} report
 * @property {FabricationFile[]} files
 * @property {FabricationFile | null} [zip]
 * @property {Preview} [preview]  printed parts only
 * @property {Balance} [balance]  when springs were asked for
 *
 * @typedef {{name: string, media_type?: string, bytes: number, url: string}} FabricationFile
 *
 * @typedef {object} PrintReport  fabrication.json: a printed model's parts
 * @property {'fabrication/1'} linkwright
 * @property {string} [scale]
 * @property {number[]} [model_mm]
 * @property {PrintedPart[]} [parts]
 * @property {unknown[]} [plates]
 * @property {{front: number, back: number, count: number}} [layers]
 * @property {{parts: number, volume_mm3?: number, mass_g?: number}} [totals]
 * @property {{name: string, footprint_mm: number[], square_bed_mm: number, max_scale: number}[]} [oversized]
 * @property {Record<string, unknown>} [checks]
 * @property {{bed: {width: number, depth: number}, fill_fraction: number}} [settings]
 * @property {string[]} [assembly]
 * @property {{hooks?: {on: string, part: string, point: Point}[]}[]} [springs]  each spring's hooks, as `balance.springs`
 *
 * @typedef {{name: string, role: string, file?: string, size_mm: number[], mass_g: number, body?: number}} PrintedPart
 *
 * @typedef {object} WorkshopReport  workshop.json: a full-size build's parts
 * @property {'workshop/1'} linkwright
 * @property {string[]} [notes]
 * @property {{thickness_mm: number, mass_kg: number}[]} [links]
 * @property {{count: number}[]} [bolts]
 * @property {{size: string}} [bolt]
 * @property {string} material
 * @property {unknown[]} [layers]
 * @property {number} peak_torque_nm
 * @property {string[]} [steps]
 *
 * @typedef {object} Preview  What the 3D view needs: every part's mesh and every carrier's pose along the motion.
 * @property {PreviewPart[]} parts
 * @property {number[][]} poses  per row, `x, y, angle_deg` of each carrier in turn
 * @property {{hooks: [number, number, number][], z: number, radius: number}[]} [springs]
 * @typedef {{name: string, role: string, carrier: number, body?: number, positions: number[], indices: number[]}} PreviewPart
 */

/**
 * An event of a design stream (docs/api.md, `POST /api/design/stream`).
 * @typedef {{name: 'accepted', data: {warnings: Issue[]}}
 *   | {name: 'queued', data: {message: string}}
 *   | {name: 'started', data: {}}
 *   | {name: 'progress', data: Progress}
 *   | {name: 'analysis', data: Analysis}
 *   | {name: 'design', data: Design}
 *   | {name: 'cancelled', data: {reason: string}}
 *   | {name: 'error', data: {error?: string}}} StreamEvent
 * @typedef {{stage: string, mechanism: string, fraction: number, best_cost: number | null}} Progress
 */

/** One id per browser tab: the server runs at most one design per client. */
const CLIENT = (() => {
  try {
    let id = sessionStorage.getItem('linkwright.client');
    if (!id) {
      id = Array.from(crypto.getRandomValues(new Uint8Array(12)), (b) => b.toString(16).padStart(2, '0')).join('');
      sessionStorage.setItem('linkwright.client', id);
    }
    return id;
  } catch {
    return 'tab';
  }
})();

/** A request the server refused (or could not be sent): its status (0: no answer), message and issues. */
export class ApiError extends Error {
  /**
   * @param {number} status
   * @param {string} error
   * @param {Issue[]} [issues]
   */
  constructor(status, error, issues = []) {
    super(error);
    this.status = status;
    this.issues = issues;
  }
}

/**
 * The error a refused request answered with.
 * @param {Response} response
 */
async function failure(response) {
  /** @type {{error?: string, issues?: Issue[]} | null} */
  let body = null;
  try {
    body = await response.json();
  } catch {
    // not JSON: use the status text
  }
  return new ApiError(response.status, body?.error || `${response.status} ${response.statusText}`, body?.issues || []);
}

const UNREACHABLE = 'the Linkwright server does not answer: is `linkwright serve` still running?';

/**
 * Sends a request and returns the server's response once it says it succeeded. Every request of the
 * app goes through here, so its errors are handled in one place: a refusal becomes an ApiError with
 * the server's message and issues, a server that cannot be reached one with status 0; an abort
 * (`signal`) is thrown as the AbortError it is.
 * @param {'GET' | 'POST'} method
 * @param {string} path
 * @param {unknown} body  sent as JSON (undefined: no body)
 * @param {AbortSignal} [signal]
 * @returns {Promise<Response>}
 */
async function send(method, path, body, signal) {
  let response;
  try {
    response = await fetch(path, {
      method,
      headers: { 'content-type': 'application/json', 'x-linkwright-client': CLIENT },
      body: body === undefined ? undefined : JSON.stringify(body),
      signal,
    });
  } catch (e) {
    if (isAbort(e)) throw e;
    throw new ApiError(0, UNREACHABLE);
  }
  if (!response.ok) throw await failure(response);
  return response;
}

/**
 * What a caught error says: its message and, for a refusal of the server, the issues it named.
 * @param {unknown} e
 * @returns {{message: string, issues: Issue[]}}
 */
export function errorOf(e) {
  if (e instanceof ApiError) return { message: e.message, issues: e.issues };
  return { message: e instanceof Error ? e.message : String(e), issues: [] };
}

/** True when `e` is the error an aborted request throws. @type {(e: unknown) => boolean} */
export const isAbort = (e) => e instanceof Error && e.name === 'AbortError';

/**
 * The answer to a request, read as JSON: taken as the shape the caller's type says (docs/api.md).
 * @param {'GET' | 'POST'} method
 * @param {string} path
 * @param {unknown} [body]
 * @param {AbortSignal} [signal]
 * @returns {Promise<any>}
 */
async function request(method, path, body, signal) {
  return (await send(method, path, body, signal)).json();
}

/** The example gallery. @type {() => Promise<ExampleSummary[]>} */
export const examples = () => request('GET', '/api/examples');
/** @type {() => Promise<Family[]>} */
export const families = () => request('GET', '/api/families');
/** The length units a scene may be drawn in, as the engine reads them. @type {() => Promise<LengthUnit[]>} */
export const units = () => request('GET', '/api/units');
/** The server's jobs and limits (of scenes too: `limits.poses_per_body`, `limits.moving_bodies`). @type {() => Promise<Status>} */
export const status = () => request('GET', '/api/status');
/** An example's scene/1 file, as JSON. @type {(name: string) => Promise<unknown>} */
export const example = (name) => request('GET', `/api/examples/${encodeURIComponent(name)}`);
/** @type {(scene: Scene, design: Design) => Promise<CheckAnswer>} */
export const check = (scene, design) => request('POST', '/api/check', { scene, design });
/**
 * The torque along the motion, the counterbalance springs and the torque with them, at the rows of
 * `simulate`'s frames for the same steps.
 * @type {(scene: Scene, design: Design, alternative?: number | null, steps?: number) => Promise<Balance>}
 */
export const balance = (scene, design, alternative = null, steps = 240) =>
  request('POST', '/api/balance', { scene, design, alternative, steps });
/** @type {(scene: Scene, design: Design, alternative?: number | null, steps?: number) => Promise<Analysis>} */
export const simulate = (scene, design, alternative = null, steps = 240) =>
  request('POST', '/api/simulate', { scene, design, alternative, steps });
/**
 * The design with joints moved (first-pose places by name): the moved linkage's design, its
 * violations and its motion, or which check it fails.
 * @type {(scene: Scene, design: Design, alternative: number | null, joints: Record<string, Point>) => Promise<EditAnswer>}
 */
export const edit = (scene, design, alternative, joints) =>
  request('POST', '/api/edit', { scene, design, alternative, joints });
/**
 * A picture of the design as SVG: the design sheet or the animation.
 * @type {(scene: Scene, design: Design, kind: 'design' | 'animation', alternative?: number | null) => Promise<Blob>}
 */
export const render = async (scene, design, kind, alternative = null) =>
  (await send('POST', '/api/render', { scene, design, kind, alternative })).blob();
/**
 * Printable parts of a design: the report, the files to download and the 3D preview.
 * @type {(scene: Scene, design: Design, settings: PrintSettings, alternative?: number | null, signal?: AbortSignal,
 *   springs?: boolean) => Promise<Fabrication>}
 */
export const fabricate = (scene, design, settings, alternative = null, signal = undefined, springs = false) =>
  request('POST', '/api/fabricate', { scene, design, settings, alternative, springs }, signal);
/** The server's default print settings. @type {() => Promise<PrintSettings>} */
export const printDefaults = () => request('GET', '/api/fabricate/settings');

/**
 * Runs a design with live progress: `body` is the request (`{scene, print_settings, ...}`, as
 * docs/api.md has it), `on(event)` is called for every server-sent event (accepted, queued,
 * started, progress, analysis, design, cancelled, error). Resolves with the design, or null when
 * cancelled. Aborting `signal` closes the connection, which cancels the job on the server.
 * @param {{scene: Scene} & Record<string, unknown>} body
 * @param {(event: StreamEvent) => void} on
 * @param {AbortSignal} [signal]
 * @returns {Promise<Design | null>}
 */
export async function designStream(body, on, signal) {
  try {
    const response = await send('POST', '/api/design/stream', body, signal);
    return await readEvents(response, on);
  } catch (e) {
    if (isAbort(e)) return null;
    throw e;
  }
}

/**
 * Reads a design stream's events to its end, calling `on` for each: the design it ends with, or null.
 * @param {Response} response
 * @param {(event: StreamEvent) => void} on
 * @returns {Promise<Design | null>}
 */
async function readEvents(response, on) {
  if (!response.body) throw new ApiError(response.status, 'the design stream has no body');
  const reader = response.body.pipeThrough(new TextDecoderStream()).getReader();
  let buffer = '';
  /** @type {Design | null} */
  let design = null;
  for (;;) {
    const { value, done } = await reader.read();
    if (done) break;
    buffer += value;
    let cut;
    while ((cut = buffer.search(/\r?\n\r?\n/)) >= 0) {
      const block = buffer.slice(0, cut);
      buffer = buffer.slice(cut).replace(/^\r?\n\r?\n/, '');
      const event = parseEvent(block);
      if (!event) continue;
      on(event);
      if (event.name === 'design') design = event.data;
      if (event.name === 'error') throw new ApiError(500, event.data?.error || 'the design failed');
    }
  }
  return design;
}

/**
 * One server-sent event block: `event:` and `data:` lines (comments and keep-alives ignored). Its data
 * is taken as what the server sends for its name (or text, when it is not JSON).
 * @param {string} block
 * @returns {StreamEvent | null}
 */
function parseEvent(block) {
  let name = 'message';
  /** @type {string[]} */
  const data = [];
  for (const line of block.split(/\r?\n/)) {
    if (line.startsWith('event:')) name = line.slice(6).trim();
    else if (line.startsWith('data:')) data.push(line.slice(5).replace(/^ /, ''));
  }
  if (data.length === 0) return null;
  /** @type {any} */
  let value;
  try {
    value = JSON.parse(data.join('\n'));
  } catch {
    value = data.join('\n');
  }
  return /** @type {StreamEvent} */ ({ name, data: value });
}
