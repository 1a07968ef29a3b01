import { describe, expect, it } from 'vitest';
import { canDecodeH264, chooseEncoding, H264_CODEC } from '../src/view/video_support';

function fakeDecoder(answer: boolean | Error): typeof VideoDecoder {
  const asked: VideoDecoderConfig[] = [];
  const decoder = {
    asked,
    isConfigSupported: (config: VideoDecoderConfig) => {
      asked.push(config);
      return answer instanceof Error
        ? Promise.reject(answer)
        : Promise.resolve({ supported: answer, config });
    },
  };
  return Object.assign(function VideoDecoder() {}, decoder) as unknown as typeof VideoDecoder;
}

describe('the encoding a new session asks for', () => {
  it('is H.264 where the server offers it and the browser decodes it, JPEG otherwise', () => {
    expect(chooseEncoding(['jpeg', 'png', 'h264'], null, true)).toBe('h264');
    expect(chooseEncoding(['jpeg', 'png', 'h264'], null, false)).toBe('jpeg');
    expect(chooseEncoding(['jpeg', 'png'], null, true)).toBe('jpeg');
  });

  it("is the page's ?encoding= where that can be had", () => {
    expect(chooseEncoding(['jpeg', 'png', 'h264'], 'jpeg', true)).toBe('jpeg');
    expect(chooseEncoding(['jpeg', 'png', 'h264'], 'png', true)).toBe('png');
    expect(chooseEncoding(['jpeg', 'png', 'h264'], 'h264', false)).toBe('jpeg');
    expect(chooseEncoding(['jpeg', 'png', 'h264'], 'webp', true)).toBe('h264');
  });

  it("asks WebCodecs about the frame view's own codec, and takes no answer for a no", async () => {
    const yes = fakeDecoder(true);
    expect(await canDecodeH264(yes)).toBe(true);
    const asked = (yes as unknown as { asked: VideoDecoderConfig[] }).asked;
    expect(asked).toEqual([{ codec: H264_CODEC, optimizeForLatency: true }]);
    expect(await canDecodeH264(fakeDecoder(false))).toBe(false);
    expect(await canDecodeH264(fakeDecoder(new TypeError('bad config')))).toBe(false);
    expect(await canDecodeH264(undefined)).toBe(false);
  });
});
