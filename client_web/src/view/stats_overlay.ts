// The stats overlay over the canvas: frames per second, latency (render request sent → frame
// shown), the server's time split, passes with their GPU and wall times, bytes per frame and
// whether the light buffer was reused or rebuilt (all from the frame header), and the browser's
// own decode time (arrived → drawn) with, for an H.264 stream, its keyframes.

import type { FrameHeader } from '../protocol/frame_header';

export interface FrameSample {
  header: FrameHeader;
  bytes: number;
  /** performance.now() when shown. */
  at: number;
  /** Request sent → frame shown, ms; undefined when the frame answered someone else's request. */
  latencyMs: number | undefined;
}

const WINDOW_MS = 2000;

function ms(v: number): string {
  return v < 0 ? 'n/a' : v < 10 ? v.toFixed(2) : v < 100 ? v.toFixed(1) : v.toFixed(0);
}

function kb(bytes: number): string {
  return bytes < 1024 ? `${bytes} B` : `${(bytes / 1024).toFixed(1)} kB`;
}

function row(label: string, value: string, key: string): HTMLTableRowElement {
  const tr = document.createElement('tr');
  const th = document.createElement('th');
  th.textContent = label;
  const td = document.createElement('td');
  td.textContent = value;
  td.dataset['stat'] = key;
  tr.append(th, td);
  return tr;
}

export class StatsOverlay {
  readonly element: HTMLElement;
  private readonly table: HTMLTableElement;
  private samples: FrameSample[] = [];
  private latencies: number[] = [];
  private decodes: number[] = [];
  private last: FrameSample | null = null;
  // H.264 frames since the session's stream began, and how many of them were keyframes.
  private streamFrames = 0;
  private keyframes = 0;

  constructor(parent: HTMLElement) {
    this.element = document.createElement('div');
    this.element.className = 'stats-overlay';
    this.element.setAttribute('aria-live', 'off');
    this.table = document.createElement('table');
    this.element.appendChild(this.table);
    parent.appendChild(this.element);
    this.render(null);
  }

  set visible(visible: boolean) {
    this.element.hidden = !visible;
  }

  get visible(): boolean {
    return !this.element.hidden;
  }

  reset(): void {
    this.samples = [];
    this.latencies = [];
    this.decodes = [];
    this.last = null;
    this.streamFrames = 0;
    this.keyframes = 0;
    this.render(null);
  }

  add(sample: FrameSample): void {
    this.last = sample;
    if (sample.header.encoding === 'h264') {
      this.streamFrames += 1;
      if (sample.header.independent ?? true) this.keyframes += 1;
    }
    this.samples.push(sample);
    this.samples = this.samples.filter((s) => sample.at - s.at <= WINDOW_MS);
    if (sample.latencyMs !== undefined) {
      this.latencies.push(sample.latencyMs);
      if (this.latencies.length > 20) this.latencies.shift();
    }
    this.render(sample);
  }

  /** A frame was drawn `decodeMs` after it arrived (its image decoded: JPEG, PNG or H.264). */
  decoded(decodeMs: number): void {
    this.decodes.push(decodeMs);
    if (this.decodes.length > 20) this.decodes.shift();
    this.render(this.last);
  }

  private fps(): number {
    const first = this.samples[0];
    const last = this.samples[this.samples.length - 1];
    if (!first || !last || this.samples.length < 2) return 0;
    const span = last.at - first.at;
    return span > 0 ? ((this.samples.length - 1) * 1000) / span : 0;
  }

  private render(sample: FrameSample | null): void {
    const rows: HTMLTableRowElement[] = [];
    if (!sample) {
      rows.push(row('frames', 'waiting for the first frame…', 'frame'));
    } else {
      const h = sample.header;
      const t = h.timings;
      const avg = this.latencies.length
        ? this.latencies.reduce((a, b) => a + b, 0) / this.latencies.length
        : undefined;
      rows.push(row('fps', this.samples.length < 2 ? '–' : this.fps().toFixed(1), 'fps'));
      rows.push(
        row(
          'latency',
          sample.latencyMs === undefined
            ? '– (not our request)'
            : `${ms(sample.latencyMs)} ms (avg ${ms(avg ?? sample.latencyMs)})`,
          'latency',
        ),
      );
      rows.push(
        row(
          'server',
          `queued ${ms(t.queued_ms)} · render ${ms(t.render_ms)} · readback ${ms(t.readback_ms)} · encode ${ms(t.encode_ms)} ms`,
          'timings',
        ),
      );
      rows.push(row('frame', `#${h.frame} (request ${h.request})`, 'frame'));
      const kind = h.encoding !== 'h264' ? '' : (h.independent ?? true) ? ' keyframe' : ' delta';
      rows.push(
        row('image', `${h.width}×${h.height} ${h.encoding}${kind} · ${kb(sample.bytes)}`, 'image'),
      );
      const decode = this.decodes[this.decodes.length - 1];
      if (decode !== undefined) {
        const mean = this.decodes.reduce((a, b) => a + b, 0) / this.decodes.length;
        const stream =
          this.streamFrames > 0
            ? ` · ${this.keyframes} keyframe${this.keyframes === 1 ? '' : 's'} in ${this.streamFrames} H.264 frames`
            : '';
        rows.push(row('decode', `${ms(decode)} ms (avg ${ms(mean)})${stream}`, 'decode'));
      }
      rows.push(row('mode', `${h.mode}${h.interactive ? ' (interactive)' : ' (still)'}`, 'mode'));
      rows.push(row('light buffer', h.light_buffer, 'light_buffer'));
      for (const p of h.passes) {
        rows.push(
          row(`pass ${p.name}`, `gpu ${ms(p.gpu_ms)} · wall ${ms(p.wall_ms)} ms`, `pass:${p.name}`),
        );
      }
      rows.push(row('quality', h.quality, 'quality'));
    }
    this.table.replaceChildren(...rows);
  }
}
