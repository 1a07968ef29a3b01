// Export: the view as a PNG still larger than the frames on screen (up to the server's
// max_export_side), rendered by the server in tiles at the lowest priority, with its progress, a
// cancel button while it runs and the link to download it once done.

import type GUI from 'lil-gui';
import type { ExportStatusMessage } from '../protocol/messages';

/** The long sides offered, in pixels; those above the server's limit are left out. */
export const EXPORT_SIDES = [1024, 2048, 4096, 8192] as const;

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

/** What an export's status says, for the panel's line. */
export function exportText(status: ExportStatusMessage): string {
  const size = `${status.width}×${status.height}`;
  switch (status.state) {
    case 'running':
      return (
        `rendering ${size}… ${Math.round(status.progress * 100)}%` +
        (status.tiles > 1 ? ` (${status.tiles} tiles)` : '')
      );
    case 'done':
      return `${size} PNG, ${((status.bytes ?? 0) / 1e6).toFixed(1)} MB`;
    case 'failed':
      return `failed: ${status.error?.message ?? 'unknown error'}`;
    case 'cancelled':
      return 'cancelled';
  }
}

export interface ExportActions {
  /** Starts an export; resolves with its first status, or throws why the server refused it. */
  start: (width: number, height: number) => Promise<ExportStatusMessage>;
  cancel: (id: string) => void;
  /** The view's size in device pixels, whose aspect the still keeps. */
  viewSize: () => [number, number];
  /** Where a finished export is downloaded from. */
  downloadUrl: (status: ExportStatusMessage) => string | undefined;
}

export class ExportPanel {
  private readonly sides: HTMLSelectElement;
  private readonly start: HTMLButtonElement;
  private readonly cancel: HTMLButtonElement;
  private readonly bar: HTMLProgressElement;
  private readonly line: HTMLElement;
  private readonly link: HTMLAnchorElement;
  private running: string | null = null;
  private readonly ended = new Set<string>();
  private maxSide = 4096;

  constructor(
    folder: GUI,
    private readonly actions: ExportActions,
  ) {
    const root = document.createElement('div');
    root.className = 'export-panel';
    const row = document.createElement('div');
    row.className = 'export-row';
    this.sides = document.createElement('select');
    this.sides.setAttribute('aria-label', 'long side of the exported still, in pixels');
    this.start = document.createElement('button');
    this.start.className = 'export-start';
    this.start.textContent = 'Export PNG';
    this.start.addEventListener('click', () => void this.begin());
    this.cancel = document.createElement('button');
    this.cancel.className = 'export-cancel';
    this.cancel.textContent = 'Cancel';
    this.cancel.hidden = true;
    this.cancel.addEventListener('click', () => {
      if (this.running) this.actions.cancel(this.running);
    });
    row.append(this.sides, this.start, this.cancel);
    this.bar = document.createElement('progress');
    this.bar.max = 1;
    this.bar.value = 0;
    this.bar.hidden = true;
    this.line = document.createElement('div');
    this.line.className = 'export-status';
    this.line.textContent = 'the view as a still, refined, in the PNG its settings';
    this.link = document.createElement('a');
    this.link.className = 'export-link';
    this.link.textContent = 'Download';
    this.link.hidden = true;
    root.append(row, this.bar, this.line, this.link);
    folder.$children.appendChild(root);
    this.setMaxSide(this.maxSide);
  }

  /** The server's max_export_side: the sizes offered. */
  setMaxSide(maxSide: number): void {
    this.maxSide = maxSide;
    const chosen = Number(this.sides.value) || 2048;
    const offered: number[] = EXPORT_SIDES.filter((side) => side <= maxSide);
    if (offered.length === 0 || offered[offered.length - 1] !== maxSide) offered.push(maxSide);
    this.sides.replaceChildren(...offered.map((side) => new Option(`${side} px`, String(side))));
    this.sides.value = String(offered.includes(chosen) ? chosen : offered[offered.length - 1]);
  }

  private async begin(): Promise<void> {
    const [viewWidth, viewHeight] = this.actions.viewSize();
    const { width, height } = exportSize(
      viewWidth,
      viewHeight,
      Number(this.sides.value),
      this.maxSide,
    );
    this.start.disabled = true;
    this.link.hidden = true;
    try {
      this.show(await this.actions.start(width, height));
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
