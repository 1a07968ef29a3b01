import { describe, expect, it } from 'vitest';
import { TapTracker, type PointerSample } from '../src/interaction/tap';

const at = (
  clientX: number,
  clientY: number,
  timeStamp: number,
  more: Partial<PointerSample> = {},
): PointerSample => ({ pointerId: 1, clientX, clientY, timeStamp, ...more });

describe('a tap on the view', () => {
  it('is a press and a release within a few pixels and a short while, at the press', () => {
    const tracker = new TapTracker();
    tracker.pointerDown(at(100, 100, 0));
    tracker.pointerMove(at(102, 101, 50));
    expect(tracker.pointerUp(at(103, 102, 120))).toEqual({ clientX: 100, clientY: 100 });
  });

  it('is no drag: a pointer that moved further orbits, even if it comes back', () => {
    const tracker = new TapTracker();
    tracker.pointerDown(at(100, 100, 0));
    tracker.pointerMove(at(130, 100, 50));
    expect(tracker.pointerUp(at(100, 100, 120))).toBeNull();
    tracker.pointerDown(at(100, 100, 200));
    expect(tracker.pointerUp(at(100, 108, 250))).toBeNull();
  });

  it('lets a finger wobble more than a mouse', () => {
    const tracker = new TapTracker();
    tracker.pointerDown(at(100, 100, 0, { pointerType: 'touch' }));
    tracker.pointerMove(at(107, 104, 40, { pointerType: 'touch' }));
    expect(tracker.pointerUp(at(107, 104, 90, { pointerType: 'touch' }))).not.toBeNull();
  });

  it('is no long press', () => {
    const tracker = new TapTracker();
    tracker.pointerDown(at(100, 100, 0));
    expect(tracker.pointerUp(at(100, 100, 900))).toBeNull();
  });

  it('is no pinch: a second finger spoils it', () => {
    const tracker = new TapTracker();
    tracker.pointerDown(at(100, 100, 0, { pointerType: 'touch' }));
    tracker.pointerDown(at(200, 200, 20, { pointerType: 'touch', pointerId: 2 }));
    expect(tracker.pointerUp(at(200, 200, 80, { pointerType: 'touch', pointerId: 2 }))).toBeNull();
    expect(tracker.pointerUp(at(100, 100, 100, { pointerType: 'touch' }))).toBeNull();
    // The next single tap counts again.
    tracker.pointerDown(at(100, 100, 300, { pointerType: 'touch' }));
    expect(tracker.pointerUp(at(100, 100, 350, { pointerType: 'touch' }))).not.toBeNull();
  });

  it('is the main button alone: another button or a modifier pans', () => {
    const tracker = new TapTracker();
    for (const more of [{ button: 2 }, { shiftKey: true }, { ctrlKey: true }]) {
      tracker.pointerDown(at(100, 100, 0, more));
      expect(tracker.pointerUp(at(100, 100, 50, more))).toBeNull();
    }
  });

  it('is forgotten when the pointer is cancelled (the browser took the gesture)', () => {
    const tracker = new TapTracker();
    tracker.pointerDown(at(100, 100, 0));
    tracker.pointerCancel(at(100, 100, 30));
    expect(tracker.pointerUp(at(100, 100, 50))).toBeNull();
  });
});
