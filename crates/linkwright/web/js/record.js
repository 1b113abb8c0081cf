// @ts-check
// The motion as a file: frames of the drawing as shown (the canvas' own SVG, with the page's style
// sheet inlined), rasterised by the browser, then an animated GIF (encoded here: LZW after the GIF89a
// specification, a palette of the drawing's own colours) or a WebM video (each frame encoded by the
// browser's VideoEncoder, put in a WebM file here: webm.js).

import { webmFile } from './webm.js';

/**
 * @typedef {{width: number, height: number, k: number}} FrameSize  an exported frame's size, pixels,
 *   and its scale from the screen
 */

/** Longest side of an exported frame, pixels. */
const MAX_SIDE = 800;

/** The page's style rules as text, so a copy of the SVG draws as it does on the page. */
function styleText() {
  /** @type {string[]} */
  const rules = [];
  for (const sheet of document.styleSheets) {
    try {
      for (const rule of sheet.cssRules) rules.push(rule.cssText);
    } catch {
      // A sheet from another origin cannot be read; the app has none.
    }
  }
  return rules.join('\n');
}

/**
 * The size an export of `svg` gets: its size on screen, the longer side at most MAX_SIDE.
 * @param {SVGSVGElement} svg
 * @returns {FrameSize}
 */
export function exportSize(svg) {
  const r = svg.getBoundingClientRect();
  const k = Math.min(1, MAX_SIDE / Math.max(r.width, r.height, 1));
  return { width: Math.max(2, Math.round(r.width * k)), height: Math.max(2, Math.round(r.height * k)), k };
}

/**
 * Draws the SVG element `svg` as it is now into the 2D context `ctx` of `size`, on white, with the
 * page's style `css`.
 * @param {SVGSVGElement} svg
 * @param {CanvasRenderingContext2D} ctx
 * @param {FrameSize} size
 * @param {string} css
 */
export async function drawSvg(svg, ctx, size, css) {
  const copy = /** @type {SVGSVGElement} */ (svg.cloneNode(true));
  const r = svg.getBoundingClientRect();
  copy.setAttribute('xmlns', 'http://www.w3.org/2000/svg');
  copy.setAttribute('width', String(size.width));
  copy.setAttribute('height', String(size.height));
  copy.setAttribute('viewBox', `0 0 ${r.width} ${r.height}`);
  const style = document.createElementNS('http://www.w3.org/2000/svg', 'style');
  style.textContent = css;
  copy.prepend(style);
  const text = new XMLSerializer().serializeToString(copy);
  const image = new Image();
  image.src = `data:image/svg+xml;charset=utf-8,${encodeURIComponent(text)}`;
  await image.decode();
  ctx.fillStyle = '#fff';
  ctx.fillRect(0, 0, size.width, size.height);
  ctx.drawImage(image, 0, 0, size.width, size.height);
}

/**
 * A canvas the size of an export of `svg` (`even`: rounded down to even numbers of pixels, as a
 * video's frames are), its 2D context (with `options`), and the page's style.
 * @param {SVGSVGElement} svg
 * @param {CanvasRenderingContext2DSettings} [options]
 * @param {{even?: boolean}} [rounding]
 */
function frameCanvas(svg, options = {}, { even = false } = {}) {
  const size = exportSize(svg);
  if (even) Object.assign(size, { width: size.width - (size.width % 2), height: size.height - (size.height % 2) });
  const canvas = document.createElement('canvas');
  canvas.width = size.width;
  canvas.height = size.height;
  const ctx = canvas.getContext('2d', options);
  if (!ctx) throw new Error('this browser cannot draw into a canvas');
  return { canvas, ctx, size, css: styleText() };
}

/**
 * Captures `count` frames: `show(i)` puts frame i on the canvas, then it is drawn into a bitmap.
 * @param {SVGSVGElement} svg
 * @param {number} count
 * @param {(i: number) => void} show
 * @returns {Promise<{frames: ImageData[], size: FrameSize}>}
 */
export async function captureFrames(svg, count, show) {
  const { ctx, size, css } = frameCanvas(svg, { willReadFrequently: true });
  /** @type {ImageData[]} */
  const frames = [];
  for (let i = 0; i < count; i++) {
    show(i);
    await drawSvg(svg, ctx, size, css);
    frames.push(ctx.getImageData(0, 0, size.width, size.height));
  }
  return { frames, size };
}

/**
 * The 256 most used colours of `frames` (5 bits a channel), and a map from every 15-bit colour to
 * its nearest palette entry. The drawing has few colours, so this keeps them exactly enough.
 * @param {ImageData[]} frames
 */
function palette(frames) {
  const counts = new Uint32Array(1 << 15);
  for (const f of frames) {
    const d = f.data;
    for (let p = 0; p < d.length; p += 16) counts[((d[p] >> 3) << 10) | ((d[p + 1] >> 3) << 5) | (d[p + 2] >> 3)]++;
  }
  /** @type {number[]} */
  const used = [];
  for (let key = 0; key < counts.length; key++) if (counts[key] > 0) used.push(key);
  used.sort((a, b) => counts[b] - counts[a]);
  const keys = used.slice(0, 256);
  while (keys.length < 2) keys.push(keys.length ? 0 : 0x7fff);
  const rgb = keys.map((k) => [((k >> 10) & 31) * 255 / 31, ((k >> 5) & 31) * 255 / 31, (k & 31) * 255 / 31].map(Math.round));
  const nearest = new Int16Array(1 << 15).fill(-1);
  /** @type {(key: number) => number} */
  const lookup = (key) => {
    if (nearest[key] >= 0) return nearest[key];
    const r = ((key >> 10) & 31) * 255 / 31, g = ((key >> 5) & 31) * 255 / 31, b = (key & 31) * 255 / 31;
    let best = 0, bestD = Infinity;
    for (let i = 0; i < rgb.length; i++) {
      const d = (rgb[i][0] - r) ** 2 + (rgb[i][1] - g) ** 2 + (rgb[i][2] - b) ** 2;
      if (d < bestD) [best, bestD] = [i, d];
    }
    nearest[key] = best;
    return best;
  };
  return { rgb, lookup };
}

/** A growing byte buffer. */
class Bytes {
  constructor() {
    this.buf = new Uint8Array(1 << 16);
    this.len = 0;
  }
  /** @param {number} b */
  byte(b) {
    if (this.len === this.buf.length) {
      const bigger = new Uint8Array(this.buf.length * 2);
      bigger.set(this.buf);
      this.buf = bigger;
    }
    this.buf[this.len++] = b;
  }
  /** @param {number} w  a 16-bit number, little-endian */
  word(w) {
    this.byte(w & 255);
    this.byte((w >> 8) & 255);
  }
  /** @param {string} s  ASCII */
  text(s) {
    for (const c of s) this.byte(c.charCodeAt(0));
  }
  bytes() {
    return this.buf.slice(0, this.len);
  }
}

/**
 * The GIF LZW code stream of `indices` (colour indices, 8-bit minimum code size), in sub-blocks.
 * @param {Uint8Array} indices
 * @param {Bytes} out
 */
function lzw(indices, out) {
  const minSize = 8, clear = 1 << minSize, end = clear + 1;
  let size = minSize + 1, next = end + 1;
  /** @type {Map<number, number>} */
  let dict = new Map();
  let bits = 0, acc = 0;
  /** @type {number[]} */
  const block = [];
  const flushBlock = () => {
    out.byte(block.length);
    for (const b of block) out.byte(b);
    block.length = 0;
  };
  /** @type {(code: number) => void} */
  const emit = (code) => {
    acc |= code << bits;
    bits += size;
    while (bits >= 8) {
      block.push(acc & 255);
      acc >>>= 8;
      bits -= 8;
      if (block.length === 255) flushBlock();
    }
  };
  out.byte(minSize);
  emit(clear);
  let prefix = indices[0];
  for (let i = 1; i < indices.length; i++) {
    const c = indices[i];
    const key = prefix * 256 + c;
    const known = dict.get(key);
    if (known !== undefined) {
      prefix = known;
      continue;
    }
    emit(prefix);
    if (next < 4096) {
      dict.set(key, next++);
      // The decoder widens its codes one code later than the table grows past the width.
      if (next - 1 === 1 << size && size < 12) size++;
    } else {
      emit(clear);
      dict = new Map();
      size = minSize + 1;
      next = end + 1;
    }
    prefix = c;
  }
  emit(prefix);
  // The decoder adds its last entry on reading that code, and may widen before the end code.
  if (next === 1 << size && size < 12) size++;
  emit(end);
  if (bits > 0) block.push(acc & 255);
  if (block.length) flushBlock();
  out.byte(0);
}

/**
 * An animated, looping GIF89a of `frames` (ImageData of one size), `delay` hundredths of a second each.
 * @param {ImageData[]} frames
 * @param {number} delay
 */
export function encodeGif(frames, delay) {
  const { width, height } = frames[0];
  const { rgb, lookup } = palette(frames);
  const out = new Bytes();
  out.text('GIF89a');
  out.word(width);
  out.word(height);
  out.byte(0xf7); // a global colour table of 256 entries, 8 bits a channel
  out.byte(0);
  out.byte(0);
  for (let i = 0; i < 256; i++) for (const c of rgb[i] || [0, 0, 0]) out.byte(c);
  // Loop for ever (the NETSCAPE2.0 application extension).
  out.byte(0x21);
  out.byte(0xff);
  out.byte(11);
  out.text('NETSCAPE2.0');
  out.byte(3);
  out.byte(1);
  out.word(0);
  out.byte(0);
  let indices = new Uint8Array(width * height), previous = new Uint8Array(width * height);
  for (const [k, f] of frames.entries()) {
    const d = f.data;
    for (let p = 0, i = 0; i < indices.length; i++, p += 4) {
      indices[i] = lookup(((d[p] >> 3) << 10) | ((d[p + 1] >> 3) << 5) | (d[p + 2] >> 3));
    }
    // Only the rectangle that changed since the last frame is stored (the rest is left in place):
    // the linkage moves, the drawing around it does not.
    let [x0, y0, x1, y1] = [0, 0, width - 1, height - 1];
    if (k > 0) {
      [x0, y0, x1, y1] = [width, height, -1, -1];
      for (let y = 0; y < height; y++) {
        for (let x = 0, i = y * width; x < width; x++, i++) {
          if (indices[i] !== previous[i]) {
            if (x < x0) x0 = x;
            if (x > x1) x1 = x;
            if (y < y0) y0 = y;
            y1 = y;
          }
        }
      }
      if (x1 < 0) [x0, y0, x1, y1] = [0, 0, 0, 0];
    }
    const w = x1 - x0 + 1, h = y1 - y0 + 1;
    const part = new Uint8Array(w * h);
    for (let y = 0; y < h; y++) part.set(indices.subarray((y0 + y) * width + x0, (y0 + y) * width + x0 + w), y * w);
    out.byte(0x21); // graphic control: the frame's delay, and leave it in place for the next
    out.byte(0xf9);
    out.byte(4);
    out.byte(1 << 2);
    out.word(delay);
    out.byte(0);
    out.byte(0);
    out.byte(0x2c); // the image: the changed rectangle, no local colour table
    out.word(x0);
    out.word(y0);
    out.word(w);
    out.word(h);
    out.byte(0);
    lzw(part, out);
    [indices, previous] = [previous, indices];
  }
  out.byte(0x3b);
  return out.bytes();
}

/** The video codec: VP8, which every WebM player reads. */
const VIDEO_CODEC = 'vp8';

/**
 * A WebM video of `count` frames at `fps`: `show(i)` puts frame i on the canvas, it is drawn, and the
 * browser's video encoder takes it as the video's frame i, at i / fps seconds. The encoder is fed
 * frame by frame, so however long a frame takes to draw, every frame is in the video at its own time
 * (a recorder of the screen as it changes would miss the frames drawn faster than it looks). Null
 * when the browser cannot encode VP8.
 * @param {SVGSVGElement} svg
 * @param {number} count
 * @param {number} fps
 * @param {(i: number) => void} show
 * @returns {Promise<Blob | null>}
 */
export async function recordWebm(svg, count, fps, show) {
  if (typeof VideoEncoder === 'undefined') return null;
  const { canvas, ctx, size, css } = frameCanvas(svg, {}, { even: true });
  const config = { codec: VIDEO_CODEC, width: size.width, height: size.height, bitrate: 4e6, framerate: fps };
  if (!(await VideoEncoder.isConfigSupported(config)).supported) return null;
  /** @type {import('./webm.js').VideoChunk[]} */
  const frames = [];
  /** @type {Error | null} */
  let failure = null;
  const encoder = new VideoEncoder({
    output: (chunk) => {
      const data = new Uint8Array(chunk.byteLength);
      chunk.copyTo(data);
      frames.push({ data, ms: Math.round(chunk.timestamp / 1000), key: chunk.type === 'key' });
    },
    error: (e) => { failure = e; },
  });
  encoder.configure(config);
  for (let i = 0; i < count && !failure; i++) {
    show(i);
    await drawSvg(svg, ctx, size, css);
    const frame = new VideoFrame(canvas, { timestamp: Math.round((i * 1e6) / fps), duration: Math.round(1e6 / fps) });
    // A key frame every second, so a player can seek.
    encoder.encode(frame, { keyFrame: i % Math.max(1, Math.round(fps)) === 0 });
    frame.close();
  }
  if (!failure) await encoder.flush();
  encoder.close();
  if (failure) throw failure;
  return new Blob([webmFile({ width: size.width, height: size.height, fps, frames })], { type: 'video/webm' });
}
