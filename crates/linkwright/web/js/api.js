// The server's API (docs/api.md). Errors come back as ApiError with the server's message and issues.

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

export class ApiError extends Error {
  constructor(status, error, issues = []) {
    super(error);
    this.status = status;
    this.issues = issues;
  }
}

async function failure(response) {
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
    if (e.name === 'AbortError') throw e;
    throw new ApiError(0, UNREACHABLE);
  }
  if (!response.ok) throw await failure(response);
  return response;
}

/** The answer to a request, read as JSON (or a blob, or text). */
async function request(method, path, body, { as = 'json', signal } = {}) {
  const response = await send(method, path, body, signal);
  return as === 'json' ? response.json() : as === 'blob' ? response.blob() : response.text();
}

export const examples = () => request('GET', '/api/examples');
export const families = () => request('GET', '/api/families');
/** The server's jobs and limits (of scenes too: `limits.poses_per_body`, `limits.moving_bodies`). */
export const status = () => request('GET', '/api/status');
export const example = (name) => request('GET', `/api/examples/${encodeURIComponent(name)}`);
export const check = (scene, design) => request('POST', '/api/check', { scene, design });
/** The torque along the motion, the counterbalance springs and the torque with them, at the rows of
 * `simulate`'s frames for the same steps. */
export const balance = (scene, design, alternative = null, steps = 240) =>
  request('POST', '/api/balance', { scene, design, alternative, steps });
export const simulate = (scene, design, alternative = null, steps = 240) =>
  request('POST', '/api/simulate', { scene, design, alternative, steps });
/** The design with joints moved (first-pose places by name): the moved linkage's design, its
 * violations and its motion, or which check it fails. */
export const edit = (scene, design, alternative, joints) =>
  request('POST', '/api/edit', { scene, design, alternative, joints });
export const render = (scene, design, kind, alternative = null) =>
  request('POST', '/api/render', { scene, design, kind, alternative }, { as: 'blob' });
/** Printable parts of a design: the report, the files to download and the 3D preview. */
export const fabricate = (scene, design, settings, alternative = null, signal = undefined, springs = false) =>
  request('POST', '/api/fabricate', { scene, design, settings, alternative, springs }, { signal });
export const printDefaults = () => request('GET', '/api/fabricate/settings');

/**
 * Runs a design with live progress: `body` is the request (`{scene, print_settings, ...}`, as
 * docs/api.md has it), `on(event, data)` is called for every server-sent event (accepted, queued,
 * started, progress, analysis, design, cancelled, error). Resolves with the design, or null when
 * cancelled. Aborting `signal` closes the connection, which cancels the job on the server.
 */
export async function designStream(body, on, signal) {
  try {
    const response = await send('POST', '/api/design/stream', body, signal);
    return await readEvents(response, on);
  } catch (e) {
    if (e.name === 'AbortError') return null;
    throw e;
  }
}

/** Reads a design stream's events to its end, calling `on` for each: the design it ends with, or null. */
async function readEvents(response, on) {
  const reader = response.body.pipeThrough(new TextDecoderStream()).getReader();
  let buffer = '';
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
      on(event.name, event.data);
      if (event.name === 'design') design = event.data;
      if (event.name === 'error') throw new ApiError(500, event.data?.error || 'the design failed');
    }
  }
  return design;
}

/** One server-sent event block: `event:` and `data:` lines (comments and keep-alives ignored). */
function parseEvent(block) {
  let name = 'message';
  const data = [];
  for (const line of block.split(/\r?\n/)) {
    if (line.startsWith('event:')) name = line.slice(6).trim();
    else if (line.startsWith('data:')) data.push(line.slice(5).replace(/^ /, ''));
  }
  if (data.length === 0) return null;
  try {
    return { name, data: JSON.parse(data.join('\n')) };
  } catch {
    return { name, data: data.join('\n') };
  }
}
