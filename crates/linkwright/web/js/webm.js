// @ts-check
// The WebM container (Matroska's EBML elements, the subset WebM players read) around VP8 frames the
// browser's VideoEncoder made: one video track, a cluster from each key frame, every frame a
// SimpleBlock at its own time. Times are in milliseconds (TimecodeScale 1,000,000 ns).

/** Element IDs, with their length marker bits, as the Matroska specification numbers them. */
const ID = {
  EBML: 0x1a45dfa3, EBMLVersion: 0x4286, EBMLReadVersion: 0x42f7, EBMLMaxIDLength: 0x42f2, EBMLMaxSizeLength: 0x42f3,
  DocType: 0x4282, DocTypeVersion: 0x4287, DocTypeReadVersion: 0x4285,
  Segment: 0x18538067, Info: 0x1549a966, TimecodeScale: 0x2ad7b1, Duration: 0x4489, MuxingApp: 0x4d80, WritingApp: 0x5741,
  Tracks: 0x1654ae6b, TrackEntry: 0xae, TrackNumber: 0xd7, TrackUID: 0x73c5, TrackType: 0x83, FlagLacing: 0x9c,
  CodecID: 0x86, DefaultDuration: 0x23e383, Video: 0xe0, PixelWidth: 0xb0, PixelHeight: 0xba,
  Cluster: 0x1f43b675, Timecode: 0xe7, SimpleBlock: 0xa3,
};

/**
 * The bytes of a non-negative integer, big-endian, at least `min` of them.
 * @param {number} value
 * @returns {number[]}
 */
function uintBytes(value, min = 1) {
  /** @type {number[]} */
  const out = [];
  for (let v = value; v > 0 || out.length < min; v = Math.floor(v / 256)) out.unshift(v % 256);
  return out;
}

/**
 * An element size as an EBML variable-length integer (the shortest that holds it).
 * @param {number} n
 */
function sizeBytes(n) {
  for (let len = 1; len <= 8; len++) {
    if (n < 2 ** (7 * len) - 1) {
      const bytes = uintBytes(n, len);
      bytes[0] |= 0x80 >> (len - 1);
      return bytes;
    }
  }
  throw new Error('an element too large for WebM');
}

/**
 * One element: its ID, its size, its content (bytes, or child elements).
 * @param {number} id
 * @param {Uint8Array | Uint8Array[]} content
 * @returns {Uint8Array<ArrayBuffer>}
 */
function element(id, content) {
  const body = Array.isArray(content) ? concat(content) : content;
  return concat([Uint8Array.from(uintBytes(id)), Uint8Array.from(sizeBytes(body.length)), body]);
}

/** @type {(id: number, value: number) => Uint8Array} */
const uint = (id, value) => element(id, Uint8Array.from(uintBytes(value)));
/** @type {(id: number, value: string) => Uint8Array} */
const text = (id, value) => element(id, new TextEncoder().encode(value));
/**
 * @param {number} id
 * @param {number} value
 */
function float(id, value) {
  const bytes = new Uint8Array(8);
  new DataView(bytes.buffer).setFloat64(0, value);
  return element(id, bytes);
}

/**
 * @param {Uint8Array[]} parts
 * @returns {Uint8Array<ArrayBuffer>}
 */
function concat(parts) {
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) {
    out.set(p, at);
    at += p.length;
  }
  return out;
}

/**
 * @typedef {{data: Uint8Array, ms: number, key: boolean}} VideoChunk  An encoded frame: its bytes, its
 *   time in milliseconds, and whether it is a key frame.
 */

/**
 * A WebM file of VP8 `frames`, in order, the first a key frame, of `width` × `height` pixels at `fps`
 * frames a second.
 * @param {{width: number, height: number, fps: number, frames: VideoChunk[]}} video
 * @returns {Uint8Array<ArrayBuffer>}
 */
export function webmFile({ width, height, fps, frames }) {
  const header = element(ID.EBML, [
    uint(ID.EBMLVersion, 1), uint(ID.EBMLReadVersion, 1), uint(ID.EBMLMaxIDLength, 4), uint(ID.EBMLMaxSizeLength, 8),
    text(ID.DocType, 'webm'), uint(ID.DocTypeVersion, 2), uint(ID.DocTypeReadVersion, 2),
  ]);
  const info = element(ID.Info, [
    uint(ID.TimecodeScale, 1e6), float(ID.Duration, (frames.length * 1000) / fps),
    text(ID.MuxingApp, 'Linkwright'), text(ID.WritingApp, 'Linkwright'),
  ]);
  const tracks = element(ID.Tracks, [element(ID.TrackEntry, [
    uint(ID.TrackNumber, 1), uint(ID.TrackUID, 1), uint(ID.TrackType, 1), uint(ID.FlagLacing, 0),
    text(ID.CodecID, 'V_VP8'), uint(ID.DefaultDuration, Math.round(1e9 / fps)),
    element(ID.Video, [uint(ID.PixelWidth, width), uint(ID.PixelHeight, height)]),
  ])]);
  /** @type {{ms: number, children: Uint8Array[]}[]} */
  const clusters = [];
  /** @type {{ms: number, children: Uint8Array[]} | null} */
  let cluster = null;
  for (const f of frames) {
    // A cluster starts at each key frame (a player seeks to clusters) and holds 16-bit relative times.
    if (f.key || !cluster || f.ms - cluster.ms > 30000) {
      cluster = { ms: f.ms, children: [uint(ID.Timecode, f.ms)] };
      clusters.push(cluster);
    }
    const relative = f.ms - cluster.ms;
    // Track 1 (as a variable-length integer), the time relative to the cluster, the key-frame flag.
    const head = Uint8Array.from([0x81, (relative >> 8) & 0xff, relative & 0xff, f.key ? 0x80 : 0]);
    cluster.children.push(element(ID.SimpleBlock, concat([head, f.data])));
  }
  const segment = element(ID.Segment, [info, tracks, ...clusters.map((c) => element(ID.Cluster, c.children))]);
  return concat([header, segment]);
}
