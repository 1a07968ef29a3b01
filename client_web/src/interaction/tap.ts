// A tap (or a click) on the view, told apart from the gestures that move the camera: one pointer
// down and up again within a few pixels and a short while. A second finger (a pinch), a button
// other than the main one, a modifier (shift or ctrl pans), a move further, or a long press makes
// it no tap. The model takes plain pointer samples, so tests need no DOM.

import { MOUSE_SLOP_PX, TOUCH_SLOP_PX } from './slop';

export interface PointerSample {
  pointerId: number;
  clientX: number;
  clientY: number;
  /** Milliseconds, as events' timeStamp. */
  timeStamp: number;
  pointerType?: string;
  button?: number;
  shiftKey?: boolean;
  ctrlKey?: boolean;
  metaKey?: boolean;
  altKey?: boolean;
}

export interface TapOptions {
  /** How far a mouse may move between down and up, CSS pixels. */
  mouseSlopPx?: number;
  /** How far a finger or a pen may move: a finger wobbles more. */
  touchSlopPx?: number;
  /** The longest a tap lasts. */
  maxMs?: number;
}

interface Down {
  pointerId: number;
  x: number;
  y: number;
  at: number;
  slop: number;
  spoiled: boolean;
}

export class TapTracker {
  private down: Down | null = null;
  private readonly pointers = new Set<number>();
  private readonly mouseSlop: number;
  private readonly touchSlop: number;
  private readonly maxMs: number;

  constructor(options: TapOptions = {}) {
    this.mouseSlop = options.mouseSlopPx ?? MOUSE_SLOP_PX;
    this.touchSlop = options.touchSlopPx ?? TOUCH_SLOP_PX;
    this.maxMs = options.maxMs ?? 500;
  }

  pointerDown(e: PointerSample): void {
    this.pointers.add(e.pointerId);
    if (this.pointers.size > 1) {
      if (this.down) this.down.spoiled = true;
      return;
    }
    const mouse = (e.pointerType ?? 'mouse') === 'mouse';
    const plain = (e.button ?? 0) === 0 && !e.shiftKey && !e.ctrlKey && !e.metaKey && !e.altKey;
    this.down = {
      pointerId: e.pointerId,
      x: e.clientX,
      y: e.clientY,
      at: e.timeStamp,
      slop: mouse ? this.mouseSlop : this.touchSlop,
      spoiled: !plain,
    };
  }

  pointerMove(e: PointerSample): void {
    const down = this.down;
    if (down && e.pointerId === down.pointerId && this.moved(down, e)) down.spoiled = true;
  }

  /** The point tapped (where the pointer went down) when this up ends a tap, else null. */
  pointerUp(e: PointerSample): { clientX: number; clientY: number } | null {
    this.pointers.delete(e.pointerId);
    const down = this.down;
    if (!down || e.pointerId !== down.pointerId) return null;
    this.down = null;
    const tap = !down.spoiled && !this.moved(down, e) && e.timeStamp - down.at <= this.maxMs;
    return tap ? { clientX: down.x, clientY: down.y } : null;
  }

  pointerCancel(e: PointerSample): void {
    this.pointers.delete(e.pointerId);
    if (this.down?.pointerId === e.pointerId) this.down = null;
  }

  private moved(down: Down, e: PointerSample): boolean {
    return Math.hypot(e.clientX - down.x, e.clientY - down.y) > down.slop;
  }
}

/** Calls `onTap` with the point of each tap on `element`; returns a detach function. */
export function attachTap(
  element: HTMLElement,
  onTap: (clientX: number, clientY: number) => void,
  options: TapOptions = {},
): () => void {
  const tracker = new TapTracker(options);
  const down = (e: PointerEvent): void => tracker.pointerDown(e);
  const move = (e: PointerEvent): void => tracker.pointerMove(e);
  const up = (e: PointerEvent): void => {
    const tap = tracker.pointerUp(e);
    if (tap) onTap(tap.clientX, tap.clientY);
  };
  const cancel = (e: PointerEvent): void => tracker.pointerCancel(e);
  element.addEventListener('pointerdown', down);
  element.addEventListener('pointermove', move);
  element.addEventListener('pointerup', up);
  element.addEventListener('pointercancel', cancel);
  return () => {
    element.removeEventListener('pointerdown', down);
    element.removeEventListener('pointermove', move);
    element.removeEventListener('pointerup', up);
    element.removeEventListener('pointercancel', cancel);
  };
}
