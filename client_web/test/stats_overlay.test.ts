import { beforeEach, describe, expect, it } from 'vitest';
import { StatsOverlay } from '../src/view/stats_overlay';
import { FakeElement, useFakeDom } from './fake_dom';
import { stillHeader } from './frame_headers';

beforeEach(() => useFakeDom());

function stat(root: FakeElement, key: string): string | undefined {
  const all = [root];
  while (all.length > 0) {
    const element = all.shift() as FakeElement;
    if (element.dataset['stat'] === key) return element.textContent;
    all.push(...element.children);
  }
  return undefined;
}

describe('stats overlay', () => {
  it("shows the browser's decode time and an H.264 stream's keyframes", () => {
    const parent = new FakeElement('div');
    const stats = new StatsOverlay(parent as unknown as HTMLElement);
    const h264 = { ...stillHeader, encoding: 'h264' as const, interactive: true };
    stats.add({ header: { ...h264, independent: true }, bytes: 9000, at: 0, latencyMs: 20 });
    expect(stat(parent, 'image')).toBe('64×64 h264 keyframe · 8.8 kB');
    expect(stat(parent, 'decode')).toBeUndefined();
    stats.decoded(2.5);
    expect(stat(parent, 'decode')).toBe('2.50 ms (avg 2.50) · 1 keyframe in 1 H.264 frames');
    stats.add({ header: { ...h264, independent: false }, bytes: 300, at: 30, latencyMs: 20 });
    stats.decoded(1.5);
    expect(stat(parent, 'image')).toBe('64×64 h264 delta · 300 B');
    expect(stat(parent, 'decode')).toBe('1.50 ms (avg 2.00) · 1 keyframe in 2 H.264 frames');
    // A still's last frame as a JPEG: no stream frame, the count stays.
    stats.add({ header: stillHeader, bytes: 20000, at: 60, latencyMs: undefined });
    expect(stat(parent, 'image')).toBe('64×64 jpeg · 19.5 kB');
    stats.reset();
    stats.add({ header: stillHeader, bytes: 20000, at: 90, latencyMs: undefined });
    stats.decoded(4);
    expect(stat(parent, 'decode')).toBe('4.00 ms (avg 4.00)');
  });
});
