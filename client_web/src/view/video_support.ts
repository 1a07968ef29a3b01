// Which encoding a new session's frames come in: H.264 where the server offers it and this
// browser's WebCodecs can decode it (fewer bytes a frame, so less latency on a slow link; the
// server sends a still's last frame as a JPEG all the same), JPEG otherwise; `?encoding=` in the
// page's address chooses for itself.

import type { Encoding } from '../protocol/messages';

/** The codec the frame view's VideoDecoder is configured with (High profile, level 5.1). */
export const H264_CODEC = 'avc1.640033';

/** Whether this browser decodes the server's H.264 stream (VideoDecoder.isConfigSupported). */
export async function canDecodeH264(
  decoder: typeof VideoDecoder | undefined = globalThis.VideoDecoder,
): Promise<boolean> {
  if (typeof decoder !== 'function') return false;
  try {
    const support = await decoder.isConfigSupported({
      codec: H264_CODEC,
      optimizeForLatency: true,
    });
    return support.supported === true;
  } catch {
    return false;
  }
}

/**
 * The encoding a new session asks for: the one `asked` for where the server offers it (and, for
 * H.264, the browser decodes it), else H.264 where both can, else JPEG.
 */
export function chooseEncoding(
  offered: readonly Encoding[],
  asked: string | null,
  h264Decodable: boolean,
): Encoding {
  const usable = (e: Encoding): boolean => offered.includes(e) && (e !== 'h264' || h264Decodable);
  const wanted = offered.find((e) => e === asked);
  if (wanted !== undefined && usable(wanted)) return wanted;
  return usable('h264') ? 'h264' : 'jpeg';
}
