import { beforeEach, describe, expect, it, vi } from 'vitest';
import type { Frame, FrameHeader } from '../src/protocol/frame_header';
import { FrameView } from '../src/view/frame_view';
import { FakeElement, useFakeDom } from './fake_dom';
import { stillHeader } from './frame_headers';

const header: FrameHeader = { ...stillHeader, frame: 0, request: 1 };

function jpeg(frame: number): Frame {
  return { header: { ...header, frame }, image: new Uint8Array(4), mime: 'image/jpeg', bytes: 100 };
}

/** Decodes finish when the test says so, in the order it says. */
let decodes: (() => void)[] = [];

beforeEach(() => {
  useFakeDom();
  decodes = [];
  const context = { fillRect: () => {}, drawImage: () => {}, fillStyle: '' };
  vi.stubGlobal('document', {
    createElement: (tag: string) =>
      Object.assign(new FakeElement(tag), { getContext: () => context }),
  });
  vi.stubGlobal('window', { devicePixelRatio: 1 });
  vi.stubGlobal('matchMedia', () => ({ addEventListener: () => {} }));
  vi.stubGlobal(
    'createImageBitmap',
    () =>
      new Promise((resolve) =>
        decodes.push(() => resolve({ width: 64, height: 64, close: () => {} })),
      ),
  );
});

async function finishDecode(): Promise<void> {
  decodes.shift()?.();
  await new Promise((resolve) => setTimeout(resolve, 0));
}

function view(): FrameView {
  return new FrameView(new FakeElement('div') as unknown as HTMLElement);
}

describe('frame view', () => {
  it('tells once that H.264 frames came that this browser cannot decode, and shows the stills', async () => {
    vi.stubGlobal('VideoDecoder', undefined);
    const v = view();
    let told = 0;
    v.onUndecodable(() => (told += 1));
    const h264 = (frame: number): Frame => ({
      ...jpeg(frame),
      header: { ...header, frame, encoding: 'h264', interactive: true },
      mime: 'video/h264',
    });
    v.show(h264(1));
    v.show(h264(2));
    expect(told).toBe(1);
    expect(v.canvas.dataset['frame']).toBeUndefined();
    v.show(jpeg(3)); // the still's last frame, as a JPEG
    await finishDecode();
    expect(v.canvas.dataset['frame']).toBe('3');
    expect(told).toBe(1);
  });

  it('never draws a frame older than the one it shows', async () => {
    const v = view();
    v.show(jpeg(7));
    await finishDecode();
    expect(v.canvas.dataset['frame']).toBe('7');
    v.show(jpeg(5));
    await finishDecode();
    expect(v.canvas.dataset['frame']).toBe('7');
  });

  it('counts frames again from where a restarted stream starts them (a failover)', async () => {
    // Another replica re-creates the session under its id; its frames are numbered from 1.
    const v = view();
    v.show(jpeg(40));
    await finishDecode();
    v.restartStream();
    v.show(jpeg(1));
    await finishDecode();
    expect(v.canvas.dataset['frame']).toBe('1');
  });

  it('does not draw a frame decoded across a restart, which is of the stream before it', async () => {
    const v = view();
    v.show(jpeg(40)); // decoding
    v.restartStream();
    v.show(jpeg(2)); // waits for the decode of 40
    await finishDecode();
    expect(v.canvas.dataset['frame']).toBeUndefined();
    await finishDecode();
    expect(v.canvas.dataset['frame']).toBe('2');
    v.show(jpeg(3));
    await finishDecode();
    expect(v.canvas.dataset['frame']).toBe('3');
  });
});
