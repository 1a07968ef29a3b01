import { describe, expect, it } from 'vitest';
import { minSendIntervalMs, RenderPacer } from '../src/interaction/pacing';
import { FakeClock } from './fake_timers';
import { recordedHello } from './recorded';

function setup(options: { minIntervalMs?: number; staleMs?: number; maxInFlight?: number } = {}) {
  const clock = new FakeClock();
  const sent: { id: number; interactive: boolean }[] = [];
  let connected = true;
  let nextId = 1;
  const pacer = new RenderPacer(
    (interactive) => {
      if (!connected) return null;
      const id = nextId++;
      sent.push({ id, interactive });
      return id;
    },
    {
      maxInFlight: options.maxInFlight ?? 2,
      minIntervalMs: options.minIntervalMs ?? 0,
      staleMs: options.staleMs ?? 10000,
      now: () => clock.now,
      setTimer: clock.setTimer,
      clearTimer: clock.clearTimer,
    },
  );
  return { clock, sent, pacer, setConnected: (c: boolean) => (connected = c) };
}

describe('RenderPacer', () => {
  it('keeps at most two renders in flight; wishes in between collapse into one', () => {
    const { sent, pacer } = setup();
    for (let k = 0; k < 10; ++k) pacer.request(true);
    expect(sent.map((s) => s.id)).toEqual([1, 2]);
    expect(pacer.inFlight).toBe(2);
    expect(pacer.hasWanted).toBe(true);
    pacer.frameArrived(1);
    expect(sent.map((s) => s.id)).toEqual([1, 2, 3]); // one for all eight wishes
    expect(pacer.hasWanted).toBe(false);
    pacer.frameArrived(3); // answers 2 as well: the server dropped it as superseded
    expect(pacer.inFlight).toBe(0);
  });

  it('treats older outstanding requests as answered by a newer frame', () => {
    const { pacer } = setup();
    pacer.request(false);
    pacer.request(false);
    expect(pacer.inFlight).toBe(2);
    pacer.frameArrived(2);
    expect(pacer.inFlight).toBe(0);
  });

  it('sends interactive frames while dragging and one still frame on release', () => {
    const { sent, pacer } = setup();
    pacer.startInteraction();
    pacer.request();
    pacer.request();
    pacer.request();
    expect(sent.every((s) => s.interactive)).toBe(true);
    pacer.endInteraction(); // the window is full: the still waits
    expect(sent).toHaveLength(2);
    pacer.frameArrived(1);
    expect(sent[2]).toEqual({ id: 3, interactive: false });
    pacer.endInteraction(); // not interacting any more: nothing new
    expect(sent).toHaveLength(3);
  });

  it('a gesture that asked for no frame (a tap) asks for no still', () => {
    const { sent, pacer } = setup();
    pacer.startInteraction();
    pacer.endInteraction();
    expect(sent).toEqual([]);
    // A gesture joined by another (a wheel turned while dragging) that moved asks for its still.
    pacer.startInteraction();
    pacer.request();
    pacer.startInteraction();
    pacer.endInteraction();
    expect(sent).toEqual([
      { id: 1, interactive: true },
      { id: 2, interactive: false },
    ]);
  });

  it('a still wish is not downgraded by a later interactive one', () => {
    const { sent, pacer } = setup();
    pacer.request(false);
    pacer.request(false);
    pacer.request(false); // waits
    pacer.request(true);
    pacer.frameArrived(2);
    expect(sent[2]!.interactive).toBe(false);
  });

  it('spaces sends by the minimum interval', () => {
    const { clock, sent, pacer } = setup({ minIntervalMs: 25 });
    pacer.request(true);
    pacer.frameArrived(1);
    pacer.request(true);
    expect(sent).toHaveLength(1);
    clock.advance(24);
    expect(sent).toHaveLength(1);
    clock.advance(1);
    expect(sent).toHaveLength(2);
  });

  it("spaces sends so that a send's requests stay within the server's rate", () => {
    expect(minSendIntervalMs(recordedHello.limits.max_requests_per_second)).toBeCloseTo(25, 12);
    const { clock, sent, pacer } = setup();
    pacer.setRequestRate(40); // a render, a set and one spare request per send: 75 ms apart
    pacer.request(true);
    pacer.frameArrived(1);
    pacer.request(true);
    clock.advance(74);
    expect(sent).toHaveLength(1);
    clock.advance(1);
    expect(sent).toHaveLength(2);
  });

  it('gives up on a request that never got a frame', () => {
    const { clock, sent, pacer } = setup({ staleMs: 1000 });
    pacer.request(true);
    pacer.request(true);
    pacer.request(true);
    expect(sent).toHaveLength(2);
    clock.advance(1001);
    pacer.pump();
    expect(sent).toHaveLength(3);
  });

  it('frees the slot of a render answered by an error', () => {
    const { sent, pacer } = setup();
    pacer.request(false);
    pacer.request(false);
    pacer.request(false);
    pacer.failed(1, 'render_failed');
    expect(sent).toHaveLength(3);
  });

  it('answers the older renders too when a newer one failed: they were superseded', () => {
    const { sent, pacer } = setup();
    pacer.request(false);
    pacer.request(false);
    pacer.failed(2, 'too_much_work');
    expect(pacer.inFlight).toBe(0);
    pacer.failed(7, 'render_failed'); // none of its own: nothing changes
    expect(sent).toHaveLength(2);
  });

  it("answers only the refused render when the error is not the scheduler's: older ones still wait", () => {
    const { sent, pacer } = setup({ maxInFlight: 3 });
    pacer.request(false);
    pacer.request(false);
    pacer.request(false);
    expect(sent.map((s) => s.id)).toEqual([1, 2, 3]);
    pacer.failed(3, 'rate_limited');
    expect(pacer.inFlight).toBe(2);
    pacer.request(false);
    pacer.request(false); // the window is full again: one wish waits
    expect(sent).toHaveLength(4);
    expect(pacer.hasWanted).toBe(true);
    pacer.failed(4, 'invalid_message'); // its slot alone is freed: the wish takes it
    expect(sent).toHaveLength(5);
    expect(pacer.inFlight).toBe(3);
    pacer.frameArrived(2); // the older renders get their frame after all
    expect(pacer.inFlight).toBe(1);
  });

  it('keeps the wish while disconnected and forgets what was in flight on reset', () => {
    const { sent, pacer, setConnected } = setup();
    pacer.request(false);
    setConnected(false);
    pacer.reset();
    expect(pacer.inFlight).toBe(0);
    pacer.request(false);
    expect(sent).toHaveLength(1);
    expect(pacer.hasWanted).toBe(true);
    setConnected(true);
    pacer.pump();
    expect(sent).toHaveLength(2);
  });

  it('reports when the answered request was sent (for the latency)', () => {
    const { clock, pacer } = setup();
    clock.now = 100;
    pacer.request(false);
    clock.now = 250;
    expect(pacer.frameArrived(1)).toBe(100);
    expect(pacer.frameArrived(7)).toBeUndefined();
  });
});
