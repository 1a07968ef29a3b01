// The canvas the frames are drawn on: sized to its container in device pixels (device-pixel-ratio
// aware). JPEG and PNG frames are decoded off the main thread with createImageBitmap,
// replace-if-busy: while one frame decodes, only the newest waiting frame is kept. H.264 frames are
// one stream, decoded in order by WebCodecs' VideoDecoder (every frame needs the ones before it
// back to a keyframe, so none is skipped; after a decoder error the frames wait for a keyframe).

import type { Frame, FrameHeader } from '../protocol/frame_header';
import { H264_CODEC } from './video_support';

export interface ShownFrame {
  header: FrameHeader;
  bytes: number;
  /** When the frame arrived (performance.now()). */
  receivedAt: number;
}

/** A frame on its way to the canvas: when it arrived, and in which stream (see restartStream). */
interface Pending {
  frame: Frame;
  receivedAt: number;
  stream: number;
}

/** Where an image drawn to fit a view lies in it: scaled to fit whole, centred (letterboxed). */
export function fitImage(
  viewWidth: number,
  viewHeight: number,
  imageWidth: number,
  imageHeight: number,
): { left: number; top: number; scale: number } {
  const scale = Math.min(viewWidth / imageWidth, viewHeight / imageHeight);
  return {
    left: (viewWidth - imageWidth * scale) / 2,
    top: (viewHeight - imageHeight * scale) / 2,
    scale,
  };
}

export class FrameView {
  readonly canvas: HTMLCanvasElement;
  private readonly context: CanvasRenderingContext2D;
  private decoding = false;
  private waiting: Pending | null = null;
  private bitmap: ImageBitmap | null = null;
  private resizeListeners: (() => void)[] = [];
  private shownListeners: ((shown: ShownFrame) => void)[] = [];
  private undecodableListeners: (() => void)[] = [];
  private undecodableTold = false;
  /** Frames dropped because a newer one arrived while decoding (or an H.264 frame before a keyframe). */
  dropped = 0;
  private video: VideoDecoder | null = null;
  /** The H.264 frames given to the decoder and not yet out, by their frame number. */
  private videoPending = new Map<number, Pending>();
  private videoNeedsKeyframe = true;
  /**
   * The frame drawn last, by its session and number. Numbers start again where the stream does
   * (another replica re-created the session after a failover): `stream` counts those restarts,
   * and a frame from before one is never drawn after it.
   */
  private shown = { session: '', frame: -1 };
  private stream = 0;
  background = '#000';

  constructor(private readonly container: HTMLElement) {
    this.canvas = document.createElement('canvas');
    this.canvas.className = 'frame-canvas';
    this.canvas.tabIndex = 0;
    this.canvas.setAttribute('aria-label', 'rendered volume; drag to orbit, wheel to zoom');
    container.appendChild(this.canvas);
    const context = this.canvas.getContext('2d');
    if (!context) throw new Error('no 2D canvas context');
    this.context = context;
    new ResizeObserver(() => this.resize()).observe(container);
    this.watchPixelRatio();
    this.resize();
  }

  private watchPixelRatio(): void {
    // Fires when the window moves to a screen with another DPR, or on browser zoom.
    const query = matchMedia(`(resolution: ${window.devicePixelRatio}dppx)`);
    query.addEventListener(
      'change',
      () => {
        this.resize();
        this.watchPixelRatio();
      },
      { once: true },
    );
  }

  onResize(listener: () => void): void {
    this.resizeListeners.push(listener);
  }

  /**
   * `listener` hears, once, that H.264 frames came that this browser cannot decode (no WebCodecs,
   * or its decoder refuses the stream): a viewer of an owner who chose H.264 sees the stills only
   * (the server sends a still's last frame as a JPEG).
   */
  onUndecodable(listener: () => void): void {
    this.undecodableListeners.push(listener);
  }

  private undecodable(): void {
    if (this.undecodableTold) return;
    this.undecodableTold = true;
    for (const l of this.undecodableListeners) l();
  }

  onShown(listener: (shown: ShownFrame) => void): void {
    this.shownListeners.push(listener);
  }

  /** The canvas size in device pixels. */
  get devicePixels(): [number, number] {
    return [this.canvas.width, this.canvas.height];
  }

  /** The image size to ask the server for: device pixels × scale, each side ≤ maxSide. */
  renderSize(scale: number, maxSide: number): [number, number] {
    const [w, h] = this.devicePixels;
    let width = Math.max(16, Math.round(w * scale));
    let height = Math.max(16, Math.round(h * scale));
    const over = Math.max(width / maxSide, height / maxSide);
    if (over > 1) {
      width = Math.max(1, Math.floor(width / over));
      height = Math.max(1, Math.floor(height / over));
    }
    return [width, height];
  }

  private resize(): void {
    const dpr = window.devicePixelRatio || 1;
    const rect = this.container.getBoundingClientRect();
    const width = Math.max(1, Math.round(rect.width * dpr));
    const height = Math.max(1, Math.round(rect.height * dpr));
    if (width === this.canvas.width && height === this.canvas.height) return;
    this.canvas.width = width;
    this.canvas.height = height;
    this.draw();
    for (const l of this.resizeListeners) l();
  }

  /** Shows a frame; if one is being decoded, this one waits, replacing any older waiting one. */
  show(frame: Frame): void {
    const pending = { frame, receivedAt: performance.now(), stream: this.stream };
    if (frame.header.encoding === 'h264') {
      this.decodeVideo(pending);
      return;
    }
    if (this.decoding) {
      if (this.waiting) this.dropped += 1;
      this.waiting = pending;
      return;
    }
    void this.decode(pending);
  }

  /**
   * The frames that follow start a stream anew (another session, a reconnection): their numbers
   * start again, the H.264 decoder and the frames it holds go, and frames wait for a keyframe.
   */
  restartStream(): void {
    this.stream += 1;
    this.shown = { session: '', frame: -1 };
    if (this.video && this.video.state !== 'closed') this.video.close();
    this.video = null;
    this.videoPending.clear();
    this.videoNeedsKeyframe = true;
  }

  /** Feeds an H.264 frame to the decoder, made at the first keyframe (again after an error). */
  private decodeVideo(pending: Pending): void {
    const { frame } = pending;
    const independent = frame.header.independent ?? true;
    if (typeof globalThis.VideoDecoder !== 'function') {
      this.dropped += 1;
      this.undecodable();
      return;
    }
    if (this.videoNeedsKeyframe && !independent) {
      this.dropped += 1;
      return;
    }
    if (!this.video || this.video.state === 'closed') {
      this.video = new VideoDecoder({
        output: (picture) => void this.videoOut(picture),
        error: (e) => {
          console.warn('penumbra: the H.264 stream could not be decoded', e);
          this.videoNeedsKeyframe = true;
          this.videoPending.clear();
          this.undecodable();
        },
      });
      // Annex B with its parameter sets in band: no description. High profile, level 5.1 covers
      // every size the server sends.
      this.video.configure({ codec: H264_CODEC, optimizeForLatency: true });
    }
    this.videoNeedsKeyframe = false;
    this.videoPending.set(frame.header.frame, pending);
    this.video.decode(
      new EncodedVideoChunk({
        type: independent ? 'key' : 'delta',
        timestamp: frame.header.frame,
        data: frame.image,
      }),
    );
  }

  private async videoOut(picture: VideoFrame): Promise<void> {
    const pending = this.videoPending.get(picture.timestamp);
    this.videoPending.delete(picture.timestamp);
    try {
      if (!pending) return;
      const h = pending.frame.header;
      // The picture has even sides; the frame is its top left width x height.
      const bitmap = await createImageBitmap(picture, 0, 0, h.width, h.height);
      this.present(bitmap, pending);
    } catch (e) {
      console.warn('penumbra: could not show a decoded frame', e);
    } finally {
      picture.close();
    }
  }

  private async decode(pending: Pending): Promise<void> {
    this.decoding = true;
    try {
      const { frame } = pending;
      const blob = new Blob([frame.image as Uint8Array<ArrayBuffer>], { type: frame.mime });
      this.present(await createImageBitmap(blob), pending);
    } catch (e) {
      console.warn('penumbra: could not decode a frame', e);
    } finally {
      this.decoding = false;
      const next = this.waiting;
      this.waiting = null;
      if (next) void this.decode(next);
    }
  }

  /**
   * Draws a decoded frame and tells the listeners; not one older than the frame shown (decodes
   * of JPEG and H.264 frames finish in any order when the encoding changes).
   */
  private present(bitmap: ImageBitmap, { frame, receivedAt, stream }: Pending): void {
    const h0 = frame.header;
    const older = h0.session === this.shown.session && h0.frame < this.shown.frame;
    if (stream !== this.stream || older) {
      bitmap.close();
      return;
    }
    this.shown = { session: h0.session, frame: h0.frame };
    this.bitmap?.close();
    this.bitmap = bitmap;
    this.draw();
    const c = this.canvas;
    const h = frame.header;
    c.dataset['frame'] = String(h.frame);
    c.dataset['request'] = String(h.request);
    c.dataset['mode'] = h.mode;
    c.dataset['interactive'] = String(h.interactive);
    c.dataset['size'] = `${h.width}x${h.height}`;
    c.dataset['refinement'] = String(h.refinement ?? 0);
    c.dataset['refining'] = String(h.refining ?? false);
    c.dataset['preview'] = String(h.preview ?? false);
    c.dataset['encoding'] = h.encoding;
    for (const l of this.shownListeners) l({ header: h, bytes: frame.bytes, receivedAt });
  }

  /** Draws the latest bitmap scaled to fit (letterboxed while the sizes differ after a resize). */
  draw(): void {
    const { canvas, context } = this;
    context.fillStyle = this.background;
    context.fillRect(0, 0, canvas.width, canvas.height);
    const bitmap = this.bitmap;
    if (!bitmap) return;
    const { left, top, scale } = fitImage(canvas.width, canvas.height, bitmap.width, bitmap.height);
    context.imageSmoothingEnabled = true;
    context.imageSmoothingQuality = 'high';
    context.drawImage(bitmap, left, top, bitmap.width * scale, bitmap.height * scale);
  }
}
