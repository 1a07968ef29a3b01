// Light: a small sphere to drag the light direction on (as seen from the camera: the handle is
// where the light comes from; hollow when it is behind the volume), type, intensity, colour,
// ambient, and the point light's position.

import type GUI from 'lil-gui';
import type { Controller } from 'lil-gui';
import type { Camera, Light, StatePatch, Vec3 } from '../protocol/messages';
import { cameraBasis } from '../interaction/orbit_camera';

export type PatchSink = (patch: StatePatch, interactive: boolean) => void;

const SIZE = 112; // CSS pixels

function normalize(v: Vec3): Vec3 {
  const l = Math.hypot(...v) || 1;
  return [v[0] / l, v[1] / l, v[2] / l];
}

function dot(a: Vec3, b: Vec3): number {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

export class LightControl {
  private light: Light | null = null;
  private readonly params = {
    type: 'directional',
    intensity: 1,
    ambient: 0.25,
    color: [1, 1, 1] as number[],
    x: 0,
    y: 0,
    z: 3,
    behind: false,
  };
  private readonly canvas: HTMLCanvasElement;
  private readonly controllers: Controller[] = [];
  private readonly positionControllers: Controller[] = [];
  private enabled = true;
  private dragging = false;

  constructor(
    folder: GUI,
    private readonly camera: () => Camera,
    private readonly send: PatchSink,
  ) {
    const wrap = document.createElement('div');
    wrap.className = 'light-sphere';
    this.canvas = document.createElement('canvas');
    this.canvas.style.width = `${SIZE}px`;
    this.canvas.style.height = `${SIZE}px`;
    this.canvas.title = 'drag: light direction as seen from the camera';
    this.canvas.dataset['control'] = 'light-sphere';
    const hint = document.createElement('div');
    hint.className = 'hint';
    hint.textContent = 'drag the handle: where the light comes from';
    wrap.append(this.canvas, hint);
    folder.$children.appendChild(wrap);

    const p = this.params;
    const add = (c: Controller, key: string): Controller => {
      c.domElement.dataset['control'] = `light.${key}`;
      this.controllers.push(c);
      return c;
    };
    add(folder.add(p, 'behind').name('from behind'), 'behind').onChange(() => this.draw());
    add(folder.add(p, 'type', ['directional', 'point']), 'type').onChange(() => {
      this.showPosition();
      this.send({ light: { type: p.type as Light['type'] } }, false);
    });
    add(folder.add(p, 'intensity', 0, 10, 0.05), 'intensity')
      .onChange(() => this.send({ light: { intensity: p.intensity } }, true))
      .onFinishChange(() => this.send({ light: { intensity: p.intensity } }, false));
    add(folder.add(p, 'ambient', 0, 1, 0.01), 'ambient')
      .onChange(() => this.send({ light: { ambient: p.ambient } }, true))
      .onFinishChange(() => this.send({ light: { ambient: p.ambient } }, false));
    add(folder.addColor(p, 'color', 1), 'color')
      .onChange(() => this.send({ light: { color: this.rgb() } }, true))
      .onFinishChange(() => this.send({ light: { color: this.rgb() } }, false));
    for (const axis of ['x', 'y', 'z'] as const) {
      const c = add(folder.add(p, axis, -5, 5, 0.05).name(`position ${axis}`), `position.${axis}`);
      c.onChange(() => this.send({ light: { position: [p.x, p.y, p.z] } }, true));
      c.onFinishChange(() => this.send({ light: { position: [p.x, p.y, p.z] } }, false));
      this.positionControllers.push(c);
    }
    this.attachSphere();
    this.draw();
  }

  private rgb(): [number, number, number] {
    const [r = 1, g = 1, b = 1] = this.params.color;
    return [r, g, b];
  }

  private showPosition(): void {
    for (const c of this.positionControllers) c.show(this.params.type === 'point');
  }

  /** Shows the session's light. */
  update(light: Light): void {
    this.light = structuredClone(light);
    const p = this.params;
    p.type = light.type;
    p.intensity = light.intensity;
    p.ambient = light.ambient;
    p.color = [...light.color];
    [p.x, p.y, p.z] = light.position;
    for (const c of this.controllers) c.updateDisplay();
    this.showPosition();
    this.draw();
  }

  /** Redraw when the camera moved (the sphere shows the light as seen from the camera). */
  cameraMoved(): void {
    this.draw();
  }

  setEnabled(enabled: boolean): void {
    this.enabled = enabled;
    for (const c of this.controllers) c.enable(enabled);
    this.canvas.style.cursor = enabled ? 'grab' : 'not-allowed';
  }

  /** The light's direction (toward the light) in camera space: x right, y up, z toward the eye. */
  private viewDirection(): Vec3 {
    const light = this.light;
    if (!light) return [0.3, 0.5, 0.8];
    const camera = this.camera();
    const world: Vec3 =
      light.type === 'point'
        ? [
            light.position[0] - camera.target[0],
            light.position[1] - camera.target[1],
            light.position[2] - camera.target[2],
          ]
        : light.direction;
    const { right, up, back } = cameraBasis(camera);
    return normalize([dot(world, right), dot(world, up), dot(world, back)]);
  }

  private attachSphere(): void {
    const handle = (e: PointerEvent, interactive: boolean): void => {
      const rect = this.canvas.getBoundingClientRect();
      let x = ((e.clientX - rect.left) / rect.width) * 2 - 1;
      let y = -(((e.clientY - rect.top) / rect.height) * 2 - 1);
      const r = Math.hypot(x, y);
      if (r > 0.999) {
        x /= r / 0.999;
        y /= r / 0.999;
      }
      const z = Math.sqrt(Math.max(0, 1 - x * x - y * y)) * (this.params.behind ? -1 : 1);
      this.setViewDirection([x, y, z], interactive);
    };
    this.canvas.addEventListener('pointerdown', (e) => {
      if (!this.enabled) return;
      this.dragging = true;
      this.canvas.setPointerCapture(e.pointerId);
      handle(e, true);
    });
    this.canvas.addEventListener('pointermove', (e) => {
      if (this.dragging) handle(e, true);
    });
    const up = (e: PointerEvent): void => {
      if (!this.dragging) return;
      this.dragging = false;
      handle(e, false);
    };
    this.canvas.addEventListener('pointerup', up);
    this.canvas.addEventListener('pointercancel', up);
  }

  private setViewDirection(view: Vec3, interactive: boolean): void {
    const camera = this.camera();
    const { right, up, back } = cameraBasis(camera);
    const world = normalize([0, 1, 2].map(
      (i) => view[0] * right[i]! + view[1] * up[i]! + view[2] * back[i]!,
    ) as Vec3);
    const light = this.light;
    if (!light) return;
    if (light.type === 'point') {
      const distance =
        Math.hypot(
          light.position[0] - camera.target[0],
          light.position[1] - camera.target[1],
          light.position[2] - camera.target[2],
        ) || 3;
      const position = world.map((c, i) => camera.target[i]! + c * distance) as Vec3;
      light.position = position;
      [this.params.x, this.params.y, this.params.z] = position;
      for (const c of this.positionControllers) c.updateDisplay();
      this.send({ light: { position } }, interactive);
    } else {
      light.direction = world;
      this.send({ light: { direction: world } }, interactive);
    }
    this.draw();
  }

  private draw(): void {
    const dpr = window.devicePixelRatio || 1;
    const px = Math.round(SIZE * dpr);
    if (this.canvas.width !== px) {
      this.canvas.width = px;
      this.canvas.height = px;
    }
    const ctx = this.canvas.getContext('2d');
    if (!ctx) return;
    const l = this.viewDirection();
    // A Lambert-shaded sphere lit from l, drawn at a low resolution and scaled up.
    const n = 64;
    const image = ctx.createImageData(n, n);
    const [cr, cg, cb] = this.rgb();
    for (let j = 0; j < n; ++j) {
      for (let i = 0; i < n; ++i) {
        const x = ((i + 0.5) / n) * 2 - 1;
        const y = -(((j + 0.5) / n) * 2 - 1);
        const rr = x * x + y * y;
        const k = (j * n + i) * 4;
        if (rr > 1) continue;
        const z = Math.sqrt(1 - rr);
        const shade = 0.12 + 0.88 * Math.max(0, x * l[0] + y * l[1] + z * l[2]);
        image.data[k] = 255 * shade * (0.35 + 0.65 * cr);
        image.data[k + 1] = 255 * shade * (0.35 + 0.65 * cg);
        image.data[k + 2] = 255 * shade * (0.35 + 0.65 * cb);
        image.data[k + 3] = 255;
      }
    }
    const scratch = document.createElement('canvas');
    scratch.width = n;
    scratch.height = n;
    scratch.getContext('2d')?.putImageData(image, 0, 0);
    ctx.clearRect(0, 0, px, px);
    ctx.imageSmoothingEnabled = true;
    ctx.drawImage(scratch, 0, 0, px, px);
    // The handle: where the light comes from.
    const hx = ((l[0] + 1) / 2) * px;
    const hy = ((1 - l[1]) / 2) * px;
    ctx.lineWidth = 2 * dpr;
    ctx.strokeStyle = '#ffcc33';
    ctx.fillStyle = '#ffcc33';
    ctx.beginPath();
    ctx.arc(hx, hy, 6 * dpr, 0, 2 * Math.PI);
    if (l[2] >= 0) ctx.fill();
    else ctx.stroke();
    ctx.beginPath();
    ctx.moveTo(px / 2, px / 2);
    ctx.lineTo(hx, hy);
    ctx.stroke();
  }
}
