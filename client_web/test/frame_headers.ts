// A frame header as the server sends one for a session's still, for tests to vary.

import type { FrameHeader } from '../src/protocol/frame_header';

export const stillHeader: FrameHeader = {
  frame: 3,
  request: 9,
  session: 'ab12',
  width: 64,
  height: 64,
  encoding: 'jpeg',
  mode: 'sbrc',
  interactive: false,
  light_buffer: 'reused',
  passes: [],
  timings: { queued_ms: 0, render_ms: 1, readback_ms: 0, encode_ms: 0 },
  quality: 'still: full quality',
};
