// What the still on screen is doing: "preview" while a smaller first frame stands for a still the
// server is still rendering, "refining" while its progressive steps keep improving it, then that
// it is done and after how many steps, fading after a moment. Nothing for interactive frames, nor
// for stills that are not refined (refinement off, or a mode that casts no camera rays).

import type { FrameHeader } from '../protocol/frame_header';

export type RefinementStatus =
  | { kind: 'none' }
  | { kind: 'preview'; width: number; height: number }
  | { kind: 'refining'; step: number }
  | { kind: 'done'; steps: number };

export function refinementStatus(header: FrameHeader): RefinementStatus {
  if (header.interactive) return { kind: 'none' };
  if (header.preview === true)
    return { kind: 'preview', width: header.width, height: header.height };
  const step = header.refinement ?? 0;
  if (header.refining === true) return { kind: 'refining', step };
  return step > 0 ? { kind: 'done', steps: step } : { kind: 'none' };
}

export function refinementText(status: RefinementStatus): string {
  switch (status.kind) {
    case 'none':
      return '';
    case 'preview':
      return `preview ${status.width}×${status.height}, rendering the still…`;
    case 'refining':
      return status.step === 0 ? 'refining…' : `refining… step ${status.step}`;
    case 'done':
      return `still done · ${status.steps} step${status.steps === 1 ? '' : 's'}`;
  }
}

/** How long the "done" badge stays before it fades, milliseconds. */
export const DONE_VISIBLE_MS = 2500;

export class RefinementBadge {
  readonly element: HTMLElement;
  private fadeTimer: ReturnType<typeof setTimeout> | undefined;

  constructor(container: HTMLElement) {
    this.element = document.createElement('div');
    this.element.className = 'refinement-badge';
    this.element.setAttribute('role', 'status');
    this.element.hidden = true;
    container.appendChild(this.element);
  }

  show(header: FrameHeader): void {
    const status = refinementStatus(header);
    clearTimeout(this.fadeTimer);
    this.element.dataset['state'] = status.kind;
    this.element.textContent = refinementText(status);
    this.element.hidden = status.kind === 'none';
    if (status.kind === 'done') {
      this.fadeTimer = setTimeout(() => {
        this.element.hidden = true;
      }, DONE_VISIBLE_MS);
    }
  }
}
