// What lies under a point tapped on the image (the server's `picked`): a marker at the point and,
// beside it, where that is in the patient (RAS millimetres), the scan's value there and the label
// drawn there, or that nothing is. The point is kept as fractions of the frame image, placed as
// the frame view draws it (letterboxed); it goes when the camera moves, the view is resized, the
// session's state changes (what lies at the point may show otherwise), or its close button is
// pressed.

import type { PickedMessage, Rgb, Vec3 } from '../protocol/messages';
import { fitImage } from './frame_view';

/** A point of the frame image as fractions of its width and height from its top-left. */
export interface FramePoint {
  x: number;
  y: number;
}

/**
 * The point of the frame image under (px, py), CSS pixels from the view's top-left, with the
 * image drawn to fit the view; null on the bands beside a letterboxed image.
 */
export function framePoint(
  px: number,
  py: number,
  viewWidth: number,
  viewHeight: number,
  imageWidth: number,
  imageHeight: number,
): FramePoint | null {
  if (!(imageWidth > 0 && imageHeight > 0 && viewWidth > 0 && viewHeight > 0)) return null;
  const { left, top, scale } = fitImage(viewWidth, viewHeight, imageWidth, imageHeight);
  const x = (px - left) / (imageWidth * scale);
  const y = (py - top) / (imageHeight * scale);
  return x >= 0 && x <= 1 && y >= 0 && y <= 1 ? { x, y } : null;
}

function millimetres(v: number): string {
  const text = v.toFixed(1);
  return text === '-0.0' ? '0.0' : text;
}

/** "R -14.6 · A -0.4 · S 48.5 mm": RAS, +x toward the patient's right. */
export function formatPosition(position: Vec3): string {
  const [r, a, s] = position.map(millimetres);
  return `R ${r} · A ${a} · S ${s} mm`;
}

/** The scan's value: Hounsfield units whole, other scales (MRI) to a tenth. */
export function formatValue(value: number, hounsfield: boolean): string {
  return hounsfield ? `${Math.round(value)} HU` : value.toFixed(1);
}

/** What the callout says of an answer. */
export interface PickText {
  hit: boolean;
  label?: { id: number; name: string };
  position?: string;
  value?: string;
}

export function pickText(picked: PickedMessage): PickText {
  if (!picked.hit || !picked.position || picked.value === undefined) return { hit: false };
  const text: PickText = {
    hit: true,
    position: formatPosition(picked.position),
    value: `value ${formatValue(picked.value, picked.hounsfield ?? false)}`,
  };
  if (picked.label) text.label = { ...picked.label };
  return text;
}

const SVG = 'http://www.w3.org/2000/svg';

export class PickOverlay {
  readonly element: HTMLElement;
  private readonly marker: SVGSVGElement;
  private readonly callout: HTMLElement;
  private readonly body: HTMLElement;
  private point: FramePoint | null = null;
  private frame: { width: number; height: number } | null = null;
  /** The pick on screen: an answer to an older one is not shown. */
  private ticket = 0;

  constructor(private readonly container: HTMLElement) {
    this.element = document.createElement('div');
    this.element.className = 'pick-overlay';
    this.marker = document.createElementNS(SVG, 'svg');
    this.marker.classList.add('pick-marker');
    this.marker.setAttribute('viewBox', '-12 -12 24 24');
    this.marker.setAttribute('aria-hidden', 'true');
    for (const [className, d] of [
      ['pick-marker-halo', 'M0,-9V-3M0,3V9M-9,0H-3M3,0H9'],
      ['pick-marker-line', 'M0,-9V-3M0,3V9M-9,0H-3M3,0H9'],
    ] as const) {
      const path = document.createElementNS(SVG, 'path');
      path.classList.add(className);
      path.setAttribute('d', d);
      this.marker.appendChild(path);
    }
    const ring = document.createElementNS(SVG, 'circle');
    ring.classList.add('pick-marker-line');
    ring.setAttribute('r', '5');
    this.marker.appendChild(ring);
    this.callout = document.createElement('div');
    this.callout.className = 'pick-callout';
    this.callout.setAttribute('role', 'status');
    const close = document.createElement('button');
    close.type = 'button';
    close.className = 'close';
    close.textContent = '×';
    close.setAttribute('aria-label', 'close');
    close.addEventListener('click', () => this.clear());
    this.body = document.createElement('div');
    this.callout.append(close, this.body);
    this.element.append(this.marker, this.callout);
    this.element.hidden = true;
    container.appendChild(this.element);
    new ResizeObserver(() => this.place()).observe(container);
  }

  /** The size of the frame image on screen, which the point's fractions are of. */
  setFrame(frame: { width: number; height: number }): void {
    this.frame = frame;
    this.place();
  }

  /** The frame point under a point of the page (clientX, clientY), or null beside the image. */
  pointAt(clientX: number, clientY: number): FramePoint | null {
    if (!this.frame) return null;
    const rect = this.container.getBoundingClientRect();
    return framePoint(
      clientX - rect.left,
      clientY - rect.top,
      rect.width,
      rect.height,
      this.frame.width,
      this.frame.height,
    );
  }

  /** A pick sent for `point`: the marker shows at once; returns the ticket its answer takes. */
  start(point: FramePoint): number {
    this.ticket += 1;
    this.point = point;
    this.callout.dataset['state'] = 'pending';
    this.body.replaceChildren(line('pick-wait', '…'));
    this.element.hidden = false;
    this.place();
    return this.ticket;
  }

  /**
   * Shows the answer to pick `ticket`, the label's colour as the state draws it; false, showing
   * nothing, where the pick is no longer the one on screen (another, or cleared since).
   */
  answer(ticket: number, picked: PickedMessage, labelColor?: Rgb): boolean {
    if (ticket !== this.ticket || this.point === null) return false;
    const text = pickText(picked);
    this.callout.dataset['state'] = text.hit ? 'hit' : 'miss';
    delete this.callout.dataset['label'];
    if (!text.hit) {
      this.body.replaceChildren(line('pick-nothing', 'nothing here'));
    } else {
      const lines: HTMLElement[] = [];
      if (text.label) {
        this.callout.dataset['label'] = String(text.label.id);
        const label = line('pick-label', '');
        const swatch = document.createElement('span');
        swatch.className = 'label-swatch';
        if (labelColor) {
          swatch.style.background = `rgb(${labelColor.map((c) => Math.round(c * 255)).join(',')})`;
        }
        const name = document.createElement('strong');
        name.textContent = text.label.name;
        const id = document.createElement('span');
        id.className = 'label-id';
        id.textContent = ` ${text.label.id}`;
        label.append(swatch, name, id);
        lines.push(label);
      }
      lines.push(line('pick-position', text.position!), line('pick-value', text.value!));
      this.body.replaceChildren(...lines);
    }
    this.place();
    return true;
  }

  /** The pick `ticket` failed: says why, beside its marker. */
  fail(ticket: number, reason: string): void {
    if (ticket !== this.ticket || this.point === null) return;
    this.callout.dataset['state'] = 'error';
    this.body.replaceChildren(line('pick-error', `could not pick: ${reason}`));
    this.place();
  }

  /** Takes the marker and its callout away; an answer still on its way is not shown. */
  clear(): void {
    this.ticket += 1;
    this.point = null;
    this.element.hidden = true;
  }

  get shown(): boolean {
    return this.point !== null;
  }

  /** The marker on the point, the callout beside it on the side where it fits. */
  private place(): void {
    const point = this.point;
    const frame = this.frame;
    if (!point || !frame) return;
    const width = this.container.clientWidth;
    const height = this.container.clientHeight;
    const { left, top, scale } = fitImage(width, height, frame.width, frame.height);
    const x = left + point.x * frame.width * scale;
    const y = top + point.y * frame.height * scale;
    this.marker.style.left = `${x}px`;
    this.marker.style.top = `${y}px`;
    const gap = 14;
    const w = this.callout.offsetWidth;
    const h = this.callout.offsetHeight;
    const calloutLeft = x + gap + w <= width - 4 ? x + gap : Math.max(4, x - gap - w);
    const calloutTop = Math.min(Math.max(4, y - h / 2), Math.max(4, height - h - 4));
    this.callout.style.left = `${calloutLeft}px`;
    this.callout.style.top = `${calloutTop}px`;
  }
}

function line(className: string, content: string): HTMLElement {
  const e = document.createElement('div');
  e.className = className;
  e.textContent = content;
  return e;
}
