// Export: the view as a PNG still larger than the frames on screen (up to the server's
// max_export_side), or as an MP4 movie of it turning (a whole turn, or rocking), rendered by the
// server in tiles at the lowest priority, with its progress, a cancel button while it runs and the
// link to download it once done.

import type GUI from 'lil-gui';
import type { ExportStatusMessage } from '../protocol/messages';

/** The long sides offered, in pixels; those above the server's limit are left out. */
export const EXPORT_SIDES = [1024, 2048, 4096, 8192] as const;
/** A movie's long sides offered, and its lengths in frames (at the server's 30 frames/s). */
export const MOVIE_SIDES = [512, 1024, 1920] as const;
export const MOVIE_FRAMES = [60, 120, 240] as const;
/** How far a rocking movie turns each way, in degrees. */
export const ROCK_DEGREES = 30;

/** What the panel offers: the still, a whole turn, the view rocking. */
export type ExportKind = 'still' | 'turntable' | 'rocking';

/** What an export asks the server for. */
export type ExportRequest =
  | { kind: 'still'; width: number; height: number }
  | { kind: 'movie'; width: number; height: number; frames: number; rock: number };

/**
 * The size of an export whose long side is `longSide` (at most `maxSide`), in the view's aspect,
 * so that the still shows what the view shows.
 */
export function exportSize(
  viewWidth: number,
  viewHeight: number,
  longSide: number,
  maxSide: number,
): { width: number; height: number } {
  const side = Math.max(1, Math.min(longSide, maxSide));
  const aspect = Math.max(1, viewWidth) / Math.max(1, viewHeight);
  if (aspect >= 1) return { width: side, height: Math.max(1, Math.round(side / aspect)) };
  return { width: Math.max(1, Math.round(side * aspect)), height: side };
}

/** A movie's size: as exportSize, each side even (its colour is stored at half the resolution). */
export function movieSize(
  viewWidth: number,
  viewHeight: number,
  longSide: number,
  maxSide: number,
): { width: number; height: number } {
  const { width, height } = exportSize(viewWidth, viewHeight, longSide, maxSide);
  const even = (side: number): number => Math.max(2, side - (side % 2));
  return { width: even(width), height: even(height) };
}

/** What an export's status says, for the panel's line. */
export function exportText(status: ExportStatusMessage): string {
  const size = `${status.width}×${status.height}`;
  const frames = status.frames;
  switch (status.state) {
    case 'running': {
      const where =
        frames !== undefined
          ? ` (frame ${Math.min(frames, Math.floor(status.progress * frames) + 1)} of ${frames})`
          : status.tiles > 1
            ? ` (${status.tiles} tiles)`
            : '';
      return `rendering ${size}… ${Math.round(status.progress * 100)}%${where}`;
    }
    case 'done':
      return `${size} ${frames !== undefined ? `MP4, ${frames} frames` : 'PNG'}, ${fileSize(status.bytes ?? 0)}`;
    case 'failed':
      return `failed: ${status.error?.message ?? 'unknown error'}`;
    case 'cancelled':
      return 'cancelled';
  }
}

export interface ExportActions {
  /** Starts an export; resolves with its first status, or throws why the server refused it. */
  start: (request: ExportRequest) => Promise<ExportStatusMessage>;
  cancel: (id: string) => void;
  /** The view's size in device pixels, whose aspect the still keeps. */
  viewSize: () => [number, number];
  /** Where a finished export is downloaded from. */
  downloadUrl: (status: ExportStatusMessage) => string | undefined;
}

export class ExportPanel {
  private readonly kind: HTMLSelectElement;
  private readonly sides: HTMLSelectElement;
  private readonly frames: HTMLSelectElement;
  private readonly start: HTMLButtonElement;
  private readonly cancel: HTMLButtonElement;
  private readonly bar: HTMLProgressElement;
  private readonly line: HTMLElement;
  private readonly link: HTMLAnchorElement;
  private running: string | null = null;
  private readonly ended = new Set<string>();
  private maxSide = 4096;
  private maxMovieSide = 1920;
  private maxMovieFrames = 720;

  constructor(
    folder: GUI,
    private readonly actions: ExportActions,
  ) {
    const root = document.createElement('div');
    root.className = 'export-panel';
    const choices = document.createElement('div');
    choices.className = 'export-row';
    this.kind = document.createElement('select');
    this.kind.className = 'export-kind';
    this.kind.setAttribute('aria-label', 'what to export');
    this.kind.addEventListener('change', () => this.offer());
    this.sides = document.createElement('select');
    this.sides.className = 'export-sides';
    this.sides.setAttribute('aria-label', 'long side of the export, in pixels');
    this.frames = document.createElement('select');
    this.frames.className = 'export-frames';
    this.frames.setAttribute('aria-label', "the movie's length");
    choices.append(this.kind, this.sides);
    const row = document.createElement('div');
    row.className = 'export-row';
    this.start = document.createElement('button');
    this.start.className = 'export-start';
    this.start.textContent = 'Export';
    this.start.addEventListener('click', () => void this.begin());
    this.cancel = document.createElement('button');
    this.cancel.className = 'export-cancel';
    this.cancel.textContent = 'Cancel';
    this.cancel.hidden = true;
    this.cancel.addEventListener('click', () => {
      if (this.running) this.actions.cancel(this.running);
    });
    row.append(this.frames, this.start, this.cancel);
    this.bar = document.createElement('progress');
    this.bar.max = 1;
    this.bar.value = 0;
    this.bar.hidden = true;
    this.line = document.createElement('div');
    this.line.className = 'export-status';
    this.line.textContent = 'the view as a refined still (PNG, with its settings) or turning (MP4)';
    this.link = document.createElement('a');
    this.link.className = 'export-link';
    this.link.textContent = 'Download';
    this.link.hidden = true;
    root.append(choices, row, this.bar, this.line, this.link);
    folder.$children.appendChild(root);
    this.offer();
  }

  /**
   * The server's limits (hello.limits): the sizes offered, and the movies (none where
   * max_movie_frames is 0: a server that writes none).
   */
  setLimits(limits: {
    max_export_side: number;
    max_movie_side: number;
    max_movie_frames: number;
  }): void {
    this.maxSide = limits.max_export_side;
    this.maxMovieSide = limits.max_movie_side;
    this.maxMovieFrames = limits.max_movie_frames;
    this.offer();
  }

  /** Fills the choices for the kind chosen, keeping what was chosen where it is still offered. */
  private offer(): void {
    const kinds: [ExportKind, string][] = [['still', 'Still (PNG)']];
    if (this.maxMovieFrames > 0) {
      kinds.push(['turntable', 'Turntable (MP4)'], ['rocking', `Rocking ±${ROCK_DEGREES}° (MP4)`]);
    }
    choose(this.kind, kinds, 'still');
    const movie = this.kind.value !== 'still';
    const maxSide = movie ? this.maxMovieSide : this.maxSide;
    const sides: number[] = (movie ? MOVIE_SIDES : EXPORT_SIDES).filter((side) => side <= maxSide);
    if (sides.length === 0 || sides[sides.length - 1] !== maxSide) sides.push(maxSide);
    choose(
      this.sides,
      sides.map((side) => [String(side), `${side} px`]),
      String(movie ? 1024 : 2048),
    );
    const frames: number[] = MOVIE_FRAMES.filter((count) => count <= this.maxMovieFrames);
    if (frames.length === 0) frames.push(this.maxMovieFrames);
    choose(
      this.frames,
      frames.map((count) => [String(count), `${count} frames (${seconds(count / 30)} s)`]),
      '120',
    );
    this.frames.hidden = !movie;
  }

  private request(): ExportRequest {
    const [viewWidth, viewHeight] = this.actions.viewSize();
    const longSide = Number(this.sides.value);
    if (this.kind.value === 'still') {
      return { kind: 'still', ...exportSize(viewWidth, viewHeight, longSide, this.maxSide) };
    }
    return {
      kind: 'movie',
      ...movieSize(viewWidth, viewHeight, longSide, this.maxMovieSide),
      frames: Number(this.frames.value),
      rock: this.kind.value === 'rocking' ? ROCK_DEGREES : 0,
    };
  }

  private async begin(): Promise<void> {
    const request = this.request();
    this.start.disabled = true;
    this.link.hidden = true;
    // The last export's end is no longer what the panel says.
    this.line.textContent = 'starting…';
    this.line.dataset['state'] = 'starting';
    try {
      this.show(await this.actions.start(request));
    } catch (e) {
      this.start.disabled = false;
      this.line.textContent = `not started: ${e instanceof Error ? e.message : String(e)}`;
    }
  }

  /**
   * The connection closed: the server cancelled the export that was running, and its last status
   * cannot come.
   */
  connectionEnded(): void {
    if (this.running === null) return;
    this.ended.add(this.running);
    this.running = null;
    this.start.disabled = false;
    this.cancel.hidden = true;
    this.bar.hidden = true;
    this.line.textContent = 'stopped: the connection to the server was lost';
    this.line.dataset['state'] = 'cancelled';
  }

  /** Shows an export's status: progress while it runs, then the download or why not. */
  show(status: ExportStatusMessage): void {
    // A status that comes after the export's end (its last word overtook it) changes nothing.
    if (this.ended.has(status.export)) return;
    const runs = status.state === 'running';
    if (!runs) this.ended.add(status.export);
    this.running = runs ? status.export : null;
    this.start.disabled = runs;
    this.cancel.hidden = !runs;
    this.bar.hidden = !runs;
    this.bar.value = status.progress;
    this.line.textContent = exportText(status);
    this.line.dataset['state'] = status.state;
    const url = status.state === 'done' ? this.actions.downloadUrl(status) : undefined;
    this.link.hidden = url === undefined;
    if (url !== undefined) {
      this.link.href = url;
      // Saved under the name the server gives it (the volume and the size).
      this.link.download = '';
    }
  }
}

/**
 * Offers `options` ([value, label]) in `select`, keeping its value where it is still offered,
 * else `preferred` where offered, else the last.
 */
function choose(select: HTMLSelectElement, options: [string, string][], preferred: string): void {
  const chosen = select.value;
  select.replaceChildren(...options.map(([value, label]) => new Option(label, value)));
  const values = options.map(([value]) => value);
  select.value = values.includes(chosen)
    ? chosen
    : values.includes(preferred)
      ? preferred
      : (values[values.length - 1] ?? '');
}

/** Seconds as a person reads them: whole where they are, else to a tenth. */
function seconds(value: number): string {
  return Number.isInteger(value) ? String(value) : value.toFixed(1);
}

/** A file's size in MB, or in kB below a tenth of a MB. */
function fileSize(bytes: number): string {
  return bytes < 1e5
    ? `${Math.max(1, Math.round(bytes / 1e3))} kB`
    : `${(bytes / 1e6).toFixed(1)} MB`;
}
