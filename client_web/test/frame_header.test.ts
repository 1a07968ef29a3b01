import { readFileSync } from 'node:fs';
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import { FrameError, packFrame, parseFrame, type FrameHeader } from '../src/protocol/frame_header';

const header: FrameHeader = {
  frame: 7,
  request: 42,
  session: 'abc123',
  width: 4,
  height: 2,
  encoding: 'png',
  mode: 'sbrc_shell',
  interactive: true,
  light_buffer: 'reused',
  passes: [
    { name: 'light_buffer_multi_slice', gpu_ms: -1, wall_ms: 3.5 },
    { name: 'raycast', gpu_ms: 1.25, wall_ms: 2 },
  ],
  timings: { queued_ms: 0.5, render_ms: 5.5, readback_ms: 0.1, encode_ms: 0.7 },
  quality: 'interactive: 4x2, sample distance x2',
};

/** The layout of proto/README.md §6, byte by byte, without the code under test. */
function handMade(json: string, image: number[], version = 1, lengthDelta = 0): Uint8Array {
  const body = Array.from(new TextEncoder().encode(json));
  const h = body.length + lengthDelta;
  return new Uint8Array([
    0x50,
    0x4e,
    0x42,
    0x46, // "PNBF"
    version & 0xff,
    version >> 8, // u16 LE
    h & 0xff,
    (h >> 8) & 0xff,
    (h >> 16) & 0xff,
    (h >>> 24) & 0xff, // u32 LE
    ...body,
    ...image,
  ]);
}

const PNG_START = [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a];

describe('parseFrame', () => {
  it('reads a frame built by hand', () => {
    const bytes = handMade(JSON.stringify(header), PNG_START);
    const frame = parseFrame(bytes.buffer as ArrayBuffer);
    expect(frame.header).toEqual(header);
    expect(Array.from(frame.image)).toEqual(PNG_START);
    expect(frame.mime).toBe('image/png');
    expect(frame.bytes).toBe(bytes.length);
  });

  it('reads a header longer than 255 bytes (u32 little endian) with UTF-8 text', () => {
    const long = { ...header, session: 'é'.repeat(40), quality: 'x'.repeat(300) };
    const frame = parseFrame(handMade(JSON.stringify(long), [0xff, 0xd8, 0xff]));
    expect(frame.header.session).toBe('é'.repeat(40));
    expect(frame.image.length).toBe(3);
  });

  it('reads a view into a larger buffer', () => {
    const bytes = handMade(JSON.stringify({ ...header, encoding: 'jpeg' }), [1, 2, 3]);
    const padded = new Uint8Array(bytes.length + 8);
    padded.set(bytes, 5);
    const frame = parseFrame(padded.subarray(5, 5 + bytes.length));
    expect(frame.mime).toBe('image/jpeg');
    expect(Array.from(frame.image)).toEqual([1, 2, 3]);
  });

  it('reads whether an H.264 frame decodes alone, and takes a frame without the member as one that does', () => {
    const key = parseFrame(
      packFrame({ ...header, encoding: 'h264', independent: true }, new Uint8Array(3)),
    );
    expect([key.header.encoding, key.header.independent, key.mime]).toEqual([
      'h264',
      true,
      'video/h264',
    ]);
    const delta = parseFrame(
      packFrame({ ...header, encoding: 'h264', independent: false }, new Uint8Array(3)),
    );
    expect(delta.header.independent).toBe(false);
    expect(parseFrame(packFrame(header, new Uint8Array(3))).header.independent ?? true).toBe(true);
    expect(() =>
      parseFrame(handMade(JSON.stringify({ ...header, independent: 'yes' }), [1])),
    ).toThrow(FrameError);
  });

  it('ignores header members it does not know', () => {
    const frame = parseFrame(handMade(JSON.stringify({ ...header, future: 1 }), []));
    expect(frame.header.request).toBe(42);
  });

  it('reads a frame a real server sent (48x32 dvr JPEG)', () => {
    const bytes = readFileSync(path.join(__dirname, 'fixtures/frame_dvr_48x32.bin'));
    const frame = parseFrame(new Uint8Array(bytes));
    expect(frame.header).toMatchObject({ width: 48, height: 32, mode: 'dvr', encoding: 'jpeg' });
    expect(frame.header.request).toBe(4);
    expect(frame.header.passes.map((p) => p.name)).toContain('raycast');
    expect(Array.from(frame.image.subarray(0, 2))).toEqual([0xff, 0xd8]); // JPEG SOI
    expect(frame.image[frame.image.length - 1]).toBe(0xd9); // ... EOI
  });

  it('round-trips through packFrame', () => {
    const frame = parseFrame(packFrame(header, new Uint8Array(PNG_START)));
    expect(frame.header).toEqual(header);
    expect(Array.from(frame.image)).toEqual(PNG_START);
  });

  it.each([
    ['too short', new Uint8Array([0x50, 0x4e, 0x42]), /too short/],
    [
      'bad magic',
      (() => {
        const b = handMade('{}', []);
        b[0] = 0x51;
        return b;
      })(),
      /magic/,
    ],
    ['another version', handMade(JSON.stringify(header), [], 2), /version 2/],
    ['a length beyond the message', handMade(JSON.stringify(header), [], 1, 1), /beyond/],
    ['a header that is not JSON', handMade('{"frame":', []), /not UTF-8 JSON/],
    ['a header that is not an object', handMade('[1]', []), /not a JSON object/],
    [
      'a header without request',
      handMade(JSON.stringify({ ...header, request: undefined }), []),
      /request/,
    ],
    [
      'an unknown encoding',
      handMade(JSON.stringify({ ...header, encoding: 'webp' }), []),
      /encoding/,
    ],
    [
      'a pass without gpu_ms',
      handMade(JSON.stringify({ ...header, passes: [{ name: 'x', wall_ms: 1 }] }), []),
      /pass/,
    ],
    [
      'timings without encode_ms',
      handMade(
        JSON.stringify({ ...header, timings: { queued_ms: 0, render_ms: 0, readback_ms: 0 } }),
        [],
      ),
      /encode_ms/,
    ],
    [
      'a refining flag that is not a boolean',
      handMade(JSON.stringify({ ...header, refinement: 2, refining: 'yes' }), []),
      /"refining" is not a boolean/,
    ],
    [
      'a preview flag that is not a boolean',
      handMade(JSON.stringify({ ...header, preview: 1 }), []),
      /"preview" is not a boolean/,
    ],
  ])('rejects %s', (_, bytes, message) => {
    expect(() => parseFrame(bytes)).toThrow(FrameError);
    expect(() => parseFrame(bytes)).toThrow(message);
  });
});
