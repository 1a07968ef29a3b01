// Render pacing: at most `maxInFlight` render requests outstanding, so nothing queues up on a slow
// link. A wish for a frame while the window is full is remembered (latest wins) and sent when a
// frame comes back. While the user drags, frames are interactive; when they let go, one still
// (full-quality) frame follows. The server coalesces renders and answers with the newest it ran:
// a frame for request r answers every outstanding request <= r. No DOM.

import { answersOlderRenders, DEFAULT_LIMITS } from '../protocol/messages';

/**
 * Requests one paced send may make: its render, the `set` of the changes since the last, and one
 * to spare for the panels' other requests (stats, the volume list).
 */
const REQUESTS_PER_SEND = 3;

/** The least time between two sends that keeps a client within `maxRequestsPerSecond` (hello.limits). */
export function minSendIntervalMs(maxRequestsPerSecond: number): number {
  return (REQUESTS_PER_SEND * 1000) / maxRequestsPerSecond;
}

export interface PacerOptions {
  maxInFlight?: number;
  /**
   * Least time between two sends, so a fast link stays below the server's request rate; by default
   * that of the server's default rate until setRequestRate gives its own.
   */
  minIntervalMs?: number;
  /** An outstanding request with no frame after this long is given up (its slot freed). */
  staleMs?: number;
  now?: () => number;
  setTimer?: (callback: () => void, ms: number) => unknown;
  clearTimer?: (handle: unknown) => void;
}

/** Sends one render; returns its request id, or null when it could not be sent. */
export type SendRender = (interactive: boolean) => number | null;

/**
 * What answers renders (the connection's events): a frame for request r, or an error carrying the
 * id of the render that asked for it (`too_much_work`, `render_failed`, `rate_limited`, ...).
 */
export interface RenderAnswers {
  on(event: 'frame', listener: (frame: { header: { request: number } }) => void): void;
  on(event: 'renderFailed', listener: (requestId: number, error: { code: string }) => void): void;
}

export class RenderPacer {
  private readonly maxInFlight: number;
  private minIntervalMs: number;
  private readonly staleMs: number;
  private readonly now: () => number;
  private readonly setTimer: (callback: () => void, ms: number) => unknown;
  private readonly clearTimer: (handle: unknown) => void;
  /** Outstanding request id → time sent. */
  private readonly outstanding = new Map<number, number>();
  /** A frame wished for but not yet sent; true when only an interactive one is needed. */
  private wanted: { interactive: boolean } | null = null;
  private lastSend = -Infinity;
  private timer: unknown = null;
  private interacting = false;
  /** Whether the gesture under way asked for a frame: one that did not (a tap) needs no still. */
  private askedWhileInteracting = false;
  /** Render requests sent so far. */
  sent = 0;

  constructor(
    private readonly send: SendRender,
    options: PacerOptions = {},
  ) {
    this.maxInFlight = options.maxInFlight ?? 2;
    this.minIntervalMs =
      options.minIntervalMs ?? minSendIntervalMs(DEFAULT_LIMITS.max_requests_per_second);
    this.staleMs = options.staleMs ?? 10000;
    this.now = options.now ?? (() => performance.now());
    this.setTimer = options.setTimer ?? ((cb, ms) => setTimeout(cb, ms));
    this.clearTimer =
      options.clearTimer ?? ((h) => clearTimeout(h as ReturnType<typeof setTimeout>));
  }

  /** The server's request rate (its hello's max_requests_per_second), which the sends keep below. */
  setRequestRate(maxRequestsPerSecond: number): void {
    this.minIntervalMs = minSendIntervalMs(maxRequestsPerSecond);
  }

  get inFlight(): number {
    return this.outstanding.size;
  }

  get interactive(): boolean {
    return this.interacting;
  }

  /** Whether a frame is wished for and not yet sent. */
  get hasWanted(): boolean {
    return this.wanted !== null;
  }

  /** Asks for a frame of the current state: interactive while dragging, else a still one. */
  request(interactive = this.interacting): void {
    if (this.interacting) this.askedWhileInteracting = true;
    this.wanted = { interactive: interactive && (this.wanted?.interactive ?? true) };
    this.pump();
  }

  startInteraction(): void {
    if (!this.interacting) this.askedWhileInteracting = false;
    this.interacting = true;
  }

  /** The user let go: ask for the still frame, unless the gesture changed nothing (a tap). */
  endInteraction(): void {
    if (!this.interacting) return;
    this.interacting = false;
    if (this.askedWhileInteracting) this.request(false);
  }

  /** A frame answering `requestId` arrived: every outstanding request up to it is answered. */
  frameArrived(requestId: number): number | undefined {
    const sentAt = this.outstanding.get(requestId);
    for (const id of [...this.outstanding.keys()]) {
      if (id <= requestId) this.outstanding.delete(id);
    }
    this.pump();
    return sentAt;
  }

  /**
   * A request was answered by an error (`code`) instead of a frame. The scheduler's errors come in
   * order, so an older request still outstanding was superseded and gets nothing either; any other
   * error answers its own request only, while the older ones still wait for theirs.
   */
  failed(requestId: number, code: string): void {
    if (!this.outstanding.has(requestId)) return;
    if (answersOlderRenders(code)) {
      for (const id of [...this.outstanding.keys()]) {
        if (id <= requestId) this.outstanding.delete(id);
      }
    } else {
      this.outstanding.delete(requestId);
    }
    this.pump();
  }

  /** Takes every answer to its renders from `answers` (the connection): frames and errors. */
  listenTo(answers: RenderAnswers): void {
    answers.on('frame', (frame) => this.frameArrived(frame.header.request));
    answers.on('renderFailed', (requestId, error) => this.failed(requestId, error.code));
  }

  /** The connection went away: nothing is outstanding any more (a wish stays). */
  reset(): void {
    this.outstanding.clear();
    if (this.timer !== null) {
      this.clearTimer(this.timer);
      this.timer = null;
    }
  }

  /** Sends the wished-for frame if a slot is free and the interval allows; else waits. */
  pump(): void {
    if (!this.wanted) return;
    const now = this.now();
    for (const [id, at] of this.outstanding) {
      if (now - at > this.staleMs) this.outstanding.delete(id);
    }
    if (this.outstanding.size >= this.maxInFlight) return;
    const wait = this.lastSend + this.minIntervalMs - now;
    if (wait > 0) {
      if (this.timer === null) {
        this.timer = this.setTimer(() => {
          this.timer = null;
          this.pump();
        }, wait);
      }
      return;
    }
    const { interactive } = this.wanted;
    const id = this.send(interactive);
    if (id === null) return; // not connected: keep the wish for later
    this.wanted = null;
    this.lastSend = now;
    this.sent += 1;
    this.outstanding.set(id, now);
  }
}
