// The crop box drawn over the image in the projection of the frame on screen (its camera and size,
// letterboxed as the frame view draws it), with a handle on each face that a mouse or a finger
// drags along the face's axis: interactive frames while it moves, a still when it is let go.
// Shown while the cut panel offers a box (the crop is on and its box is to be shown). SVG: each handle's place on
// screen is an attribute, which the browser test reads.

import {
  boxEdges,
  faceHandles,
  faceUnderPointer,
  type CropBox,
  type FaceHandle,
  type FrameProjection,
  type Placement,
} from '../panels/crop_box';
import { CROP_FACES, type FaceKey } from '../panels/cut_panel';
import { fitImage } from './frame_view';

const SVG = 'http://www.w3.org/2000/svg';

export interface CropBoxSource {
  /** The box to draw, null for none. */
  box(): CropBox | null;
  /** Whether its faces may be dragged. */
  readonly editable: boolean;
  /** A face dragged to `millimetres` on its axis; `interactive` until it is let go. */
  moveFace(face: FaceKey, millimetres: number, interactive: boolean): void;
}

interface Drag {
  face: FaceKey;
  pointer: number;
  /** Where the pointer was from the handle's centre when the drag began, CSS pixels. */
  offsetX: number;
  offsetY: number;
  /** Where the face was last moved to, mm: a cancelled drag ends there. */
  last: number | null;
}

export class CropBoxOverlay {
  readonly element: SVGSVGElement;
  private readonly edges: SVGPathElement;
  /** One handle per face, kept across redraws so that a drag keeps its pointer capture. */
  private readonly handles = new Map<FaceKey, SVGCircleElement>();
  private current = new Map<FaceKey, FaceHandle>();
  private frame: FrameProjection | null = null;
  private placement: Placement | null = null;
  private drag: Drag | null = null;

  constructor(
    private readonly container: HTMLElement,
    private readonly source: CropBoxSource,
  ) {
    this.element = document.createElementNS(SVG, 'svg');
    this.element.classList.add('crop-box-overlay');
    this.element.setAttribute('aria-hidden', 'true');
    this.edges = document.createElementNS(SVG, 'path');
    this.edges.classList.add('crop-box-edges');
    this.element.appendChild(this.edges);
    for (const face of CROP_FACES) {
      const circle = document.createElementNS(SVG, 'circle');
      circle.classList.add('crop-box-handle');
      circle.dataset.face = face.key;
      circle.setAttribute('r', '9');
      circle.addEventListener('pointerdown', (e) => this.start(e, face.key));
      circle.addEventListener('pointermove', (e) => this.moved(e, true));
      circle.addEventListener('pointerup', (e) => this.end(e));
      circle.addEventListener('pointercancel', (e) => this.end(e));
      circle.addEventListener('lostpointercapture', (e) => this.end(e));
      this.element.appendChild(circle);
      this.handles.set(face.key, circle);
    }
    container.appendChild(this.element);
    new ResizeObserver(() => this.draw()).observe(container);
  }

  /** The volume's placement in world space (null: none loaded). */
  setPlacement(placement: Placement | null): void {
    this.placement = placement;
    this.draw();
  }

  /** The frame now on screen: the box is drawn in its projection. */
  setFrame(frame: FrameProjection): void {
    this.frame = frame;
    this.draw();
  }

  /** Where the frame's image lies in the container, CSS pixels, as the frame view draws it. */
  private imageRect(frame: FrameProjection): { left: number; top: number; scale: number } {
    const { clientWidth, clientHeight } = this.container;
    return fitImage(clientWidth, clientHeight, frame.width, frame.height);
  }

  draw(): void {
    const box = this.source.box();
    const { frame, placement } = this;
    const visible = box !== null && frame !== null && placement !== null;
    this.element.style.display = visible ? '' : 'none';
    this.current = new Map();
    if (!visible) return;
    const rect = this.imageRect(frame);
    const x = (v: number): string => (rect.left + v * rect.scale).toFixed(1);
    const y = (v: number): string => (rect.top + v * rect.scale).toFixed(1);
    this.edges.setAttribute(
      'd',
      boxEdges(frame, placement, box)
        .map(([a, b]) => `M${x(a.x)},${y(a.y)}L${x(b.x)},${y(b.y)}`)
        .join(''),
    );
    if (this.source.editable) {
      for (const handle of faceHandles(frame, placement, box))
        this.current.set(handle.face, handle);
    }
    for (const [face, circle] of this.handles) {
      const handle = this.current.get(face);
      circle.style.display = handle ? '' : 'none';
      circle.classList.toggle('dragging', this.drag?.face === face);
      if (!handle) continue;
      circle.setAttribute('cx', x(handle.at.x));
      circle.setAttribute('cy', y(handle.at.y));
    }
  }

  private start(e: PointerEvent, face: FaceKey): void {
    const handle = this.current.get(face);
    if (this.drag || !handle || !this.frame || !this.source.editable) return;
    if (e.pointerType === 'mouse' && e.button !== 0) return;
    e.preventDefault();
    e.stopPropagation();
    (e.currentTarget as Element).setPointerCapture(e.pointerId);
    const rect = this.imageRect(this.frame);
    const bounds = this.element.getBoundingClientRect();
    this.drag = {
      face,
      pointer: e.pointerId,
      offsetX: e.clientX - bounds.left - (rect.left + handle.at.x * rect.scale),
      offsetY: e.clientY - bounds.top - (rect.top + handle.at.y * rect.scale),
      last: null,
    };
    this.draw();
  }

  /** The face follows the pointer: its handle stays under it, in the frame's projection. */
  private moved(e: PointerEvent, interactive: boolean): void {
    const drag = this.drag;
    const box = this.source.box();
    const { frame, placement } = this;
    if (!drag || e.pointerId !== drag.pointer || !box || !frame || !placement) return;
    const rect = this.imageRect(frame);
    const bounds = this.element.getBoundingClientRect();
    const x = (e.clientX - bounds.left - drag.offsetX - rect.left) / rect.scale;
    const y = (e.clientY - bounds.top - drag.offsetY - rect.top) / rect.scale;
    const millimetres = faceUnderPointer(frame, placement, box, drag.face, x, y);
    if (millimetres === null) return;
    drag.last = millimetres;
    this.source.moveFace(drag.face, millimetres, interactive);
  }

  /**
   * Let go: a still where the pointer left the face, else (cancelled, capture lost, or let go
   * where the face cannot follow) where it last was.
   */
  private end(e: PointerEvent): void {
    const drag = this.drag;
    if (!drag || e.pointerId !== drag.pointer) return;
    const before = drag.last;
    if (e.type === 'pointerup') this.moved(e, false);
    if (drag.last !== null && (e.type !== 'pointerup' || drag.last === before)) {
      this.source.moveFace(drag.face, drag.last, false);
    }
    this.drag = null;
    this.draw();
  }
}
