// Binary frames (proto/README.md §6): "PNBF", u16 LE version, u32 LE header length H, H bytes of
// UTF-8 JSON header, then the JPEG or PNG bytes. No DOM.

import { ENCODINGS } from './generated/server_tables';
import type { Encoding, Mode } from './messages';

export const FRAME_MAGIC = [0x50, 0x4e, 0x42, 0x46] as const; // "PNBF"
export const FRAME_VERSION = 1;
export const FRAME_PREFIX_BYTES = 10;

export interface FramePass {
  name: string;
  gpu_ms: number;
  wall_ms: number;
}

export interface FrameTimings {
  queued_ms: number;
  render_ms: number;
  readback_ms: number;
  encode_ms: number;
}

export interface FrameHeader {
  frame: number;
  request: number;
  session: string;
  width: number;
  height: number;
  encoding: Encoding;
  mode: Mode;
  interactive: boolean;
  light_buffer: 'none' | 'built' | 'reused';
  passes: FramePass[];
  timings: FrameTimings;
  quality: string;
  /** Progressive stills: the still frame refined this many times (absent or 0: not refined). */
  refinement?: number;
  /** Progressive stills: another refinement step of this still follows (absent: false). */
  refining?: boolean;
  /** A still's smaller first frame; the still at the requested size follows (absent: false). */
  preview?: boolean;
  /**
   * Decodable without the frames before it (absent: true): every JPEG or PNG frame, an H.264
   * keyframe. An H.264 frame that is not needs every frame since the last keyframe.
   */
  independent?: boolean;
}

export interface Frame {
  header: FrameHeader;
  /** The encoded image, a view into the message's buffer. */
  image: Uint8Array;
  /** MIME type of `image`. */
  mime: string;
  /** Size of the whole binary message. */
  bytes: number;
}

export class FrameError extends Error {
  constructor(message: string) {
    super(message);
    this.name = 'FrameError';
  }
}

function isRecord(v: unknown): v is Record<string, unknown> {
  return typeof v === 'object' && v !== null && !Array.isArray(v);
}

/** How the browser names each format the server writes frames in (a new one fails to compile here). */
const MIME_TYPES: Record<Encoding, string> = {
  jpeg: 'image/jpeg',
  png: 'image/png',
  h264: 'video/h264',
};

function checkHeader(value: unknown): FrameHeader {
  if (!isRecord(value)) throw new FrameError('frame header is not a JSON object');
  const need = (key: string, type: 'number' | 'string' | 'boolean'): void => {
    if (typeof value[key] !== type) throw new FrameError(`frame header: "${key}" is not a ${type}`);
  };
  need('frame', 'number');
  need('request', 'number');
  need('session', 'string');
  need('width', 'number');
  need('height', 'number');
  need('encoding', 'string');
  need('mode', 'string');
  need('interactive', 'boolean');
  need('light_buffer', 'string');
  need('quality', 'string');
  if (!(ENCODINGS as readonly unknown[]).includes(value['encoding'])) {
    throw new FrameError(`frame header: unknown encoding "${String(value['encoding'])}"`);
  }
  const passes = value['passes'];
  if (!Array.isArray(passes)) throw new FrameError('frame header: "passes" is not an array');
  for (const p of passes) {
    if (
      !isRecord(p) ||
      typeof p['name'] !== 'string' ||
      typeof p['gpu_ms'] !== 'number' ||
      typeof p['wall_ms'] !== 'number'
    ) {
      throw new FrameError('frame header: a pass lacks name, gpu_ms or wall_ms');
    }
  }
  for (const [key, type] of [
    ['refinement', 'number'],
    ['refining', 'boolean'],
    ['preview', 'boolean'],
    ['independent', 'boolean'],
  ] as const) {
    if (key in value && typeof value[key] !== type) {
      throw new FrameError(`frame header: "${key}" is not a ${type}`);
    }
  }
  const t = value['timings'];
  if (!isRecord(t)) throw new FrameError('frame header: "timings" is not an object');
  for (const key of ['queued_ms', 'render_ms', 'readback_ms', 'encode_ms']) {
    if (typeof t[key] !== 'number') throw new FrameError(`frame header: timings.${key} missing`);
  }
  return value as unknown as FrameHeader;
}

/** Parses one binary WebSocket message. Throws FrameError on anything but a v1 frame. */
export function parseFrame(data: ArrayBuffer | Uint8Array): Frame {
  const bytes = data instanceof Uint8Array ? data : new Uint8Array(data);
  if (bytes.length < FRAME_PREFIX_BYTES) {
    throw new FrameError(`frame too short (${bytes.length} bytes)`);
  }
  for (let i = 0; i < 4; ++i) {
    if (bytes[i] !== FRAME_MAGIC[i]) throw new FrameError('not a Penumbra frame (magic)');
  }
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const version = view.getUint16(4, true);
  if (version !== FRAME_VERSION) throw new FrameError(`unsupported frame version ${version}`);
  const headerLength = view.getUint32(6, true);
  if (FRAME_PREFIX_BYTES + headerLength > bytes.length) {
    throw new FrameError(`frame header length ${headerLength} beyond the message`);
  }
  const headerBytes = bytes.subarray(FRAME_PREFIX_BYTES, FRAME_PREFIX_BYTES + headerLength);
  let json: unknown;
  try {
    json = JSON.parse(new TextDecoder('utf-8', { fatal: true }).decode(headerBytes));
  } catch {
    throw new FrameError('frame header is not UTF-8 JSON');
  }
  const header = checkHeader(json);
  return {
    header,
    image: bytes.subarray(FRAME_PREFIX_BYTES + headerLength),
    mime: MIME_TYPES[header.encoding],
    bytes: bytes.length,
  };
}

/** Builds a frame message (tests and tools; the server is the one that sends frames). */
export function packFrame(header: FrameHeader, image: Uint8Array): Uint8Array {
  const json = new TextEncoder().encode(JSON.stringify(header));
  const out = new Uint8Array(FRAME_PREFIX_BYTES + json.length + image.length);
  out.set(FRAME_MAGIC, 0);
  const view = new DataView(out.buffer);
  view.setUint16(4, FRAME_VERSION, true);
  view.setUint32(6, json.length, true);
  out.set(json, FRAME_PREFIX_BYTES);
  out.set(image, FRAME_PREFIX_BYTES + json.length);
  return out;
}
