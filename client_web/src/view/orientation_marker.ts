// The orientation marker: the patient's axes (RAS world, proto/README.md) seen from the camera, in
// a corner of the view, like Slicer's and ParaView's. Each axis is drawn from the centre to both
// ends, labelled L/R, P/A, I/S; it turns with every camera change. SVG, so each label's place on
// screen is an attribute (the browser test reads them).

import { cameraBasis } from '../interaction/orbit_camera';
import type { Camera, Vec3 } from '../protocol/messages';

const SVG = 'http://www.w3.org/2000/svg';
const SIZE = 96; // CSS pixels
const RADIUS = 34; // axis length

/** The six ends of the patient's axes: the label at each and its world direction. */
export const AXIS_ENDS: readonly { label: string; direction: Vec3; color: string }[] = [
  { label: 'R', direction: [1, 0, 0], color: '#e05050' },
  { label: 'L', direction: [-1, 0, 0], color: '#e05050' },
  { label: 'A', direction: [0, 1, 0], color: '#50c050' },
  { label: 'P', direction: [0, -1, 0], color: '#50c050' },
  { label: 'S', direction: [0, 0, 1], color: '#5080f0' },
  { label: 'I', direction: [0, 0, -1], color: '#5080f0' },
];

function dot(a: Vec3, b: Vec3): number {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

export interface MarkerEnd {
  label: string;
  /** Screen offset from the marker's centre, y down, in units of the axis length. */
  x: number;
  y: number;
  /** Toward the viewer (> 0) or away. */
  depth: number;
}

/** Where each axis end appears for `camera` (orthographic: the marker shows directions only). */
export function markerEnds(camera: Camera): MarkerEnd[] {
  const { right, up, back } = cameraBasis(camera);
  return AXIS_ENDS.map((end) => ({
    label: end.label,
    x: dot(end.direction, right),
    y: -dot(end.direction, up),
    depth: dot(end.direction, back),
  }));
}

export class OrientationMarker {
  readonly element: SVGSVGElement;

  constructor(container: HTMLElement) {
    this.element = document.createElementNS(SVG, 'svg');
    this.element.classList.add('orientation-marker');
    this.element.setAttribute('viewBox', `${-SIZE / 2} ${-SIZE / 2} ${SIZE} ${SIZE}`);
    this.element.setAttribute('width', String(SIZE));
    this.element.setAttribute('height', String(SIZE));
    this.element.setAttribute('role', 'img');
    container.appendChild(this.element);
  }

  update(camera: Camera): void {
    const ends = markerEnds(camera);
    // Far ends first, so nearer axes and labels cover them.
    const order = ends
      .map((end, i) => ({ end, style: AXIS_ENDS[i]! }))
      .sort((a, b) => a.end.depth - b.end.depth);
    const parts: SVGElement[] = [];
    for (const { end, style } of order) {
      const x = end.x * RADIUS;
      const y = end.y * RADIUS;
      const positive = 'RAS'.includes(end.label);
      const line = document.createElementNS(SVG, 'line');
      line.setAttribute('x1', '0');
      line.setAttribute('y1', '0');
      line.setAttribute('x2', x.toFixed(2));
      line.setAttribute('y2', y.toFixed(2));
      line.setAttribute('stroke', style.color);
      line.setAttribute('stroke-width', positive ? '3' : '1.5');
      line.setAttribute('opacity', end.depth < -0.2 ? '0.55' : '1');
      const text = document.createElementNS(SVG, 'text');
      text.textContent = end.label;
      text.dataset.axis = end.label;
      text.setAttribute('x', (x * 1.25).toFixed(2));
      text.setAttribute('y', (y * 1.25).toFixed(2));
      text.setAttribute('fill', style.color);
      text.setAttribute('opacity', end.depth < -0.2 ? '0.55' : '1');
      parts.push(line, text);
    }
    this.element.replaceChildren(...parts);
    const rightmost = ends.reduce((a, b) => (b.x > a.x ? b : a));
    const topmost = ends.reduce((a, b) => (b.y < a.y ? b : a));
    this.element.dataset.screenRight = rightmost.label;
    this.element.dataset.screenUp = topmost.label;
    this.element.setAttribute(
      'aria-label',
      `orientation: ${rightmost.label} to the right, ${topmost.label} up`,
    );
  }
}
