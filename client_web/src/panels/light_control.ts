// Light: a small sphere to drag the light direction on (as seen from the camera: the handle is
// where the light comes from; hollow when it is behind the volume), type, colour, the point
// light's position, and a slider for every number under `light/` that the server's hello announces
// a range for (intensity, ambient, and any the server adds), spanning that range.

import type GUI from 'lil-gui';
import type { Controller } from 'lil-gui';
import {
  LIGHT_TYPES,
  type Camera,
  type Light,
  type LightType,
  type SettingRange,
  type SettingRanges,
  type StatePatch,
  type Vec3,
  type VolumeSummary,
} from '../protocol/messages';
import { cameraBasis } from '../interaction/orbit_camera';
import {
  nestedAt,
  rangeText,
  settingControls,
  valueAt,
  type SettingControl,
} from './ranged_controls';

export type PatchSink = (patch: StatePatch, interactive: boolean) => void;

const SIZE = 112; // CSS pixels

function normalize(v: Vec3): Vec3 {
  const l = Math.hypot(...v) || 1;
  return [v[0] / l, v[1] / l, v[2] / l];
}

function dot(a: Vec3, b: Vec3): number {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

function clamp(v: number, lo: number, hi: number): number {
  return Math.min(hi, Math.max(lo, v));
}

/** The control of each number of the light (light/intensity, light/ambient) hello.ranges announces. */
export function lightControls(ranges: SettingRanges): SettingControl[] {
  return settingControls(ranges, 'light');
}

/**
 * The radius of the sphere around the origin that holds the volume's box whatever its orientation:
 * the box is centred on the origin with its longest side 1 (proto/README.md §5), so half its
 * diagonal. A volume not loaded yet (dims 0) may be any box, so the largest: half a unit cube's.
 */
export function volumeRadius(volume: Pick<VolumeSummary, 'dims' | 'spacing'>): number {
  const extent = volume.dims.map((n, i) => n * volume.spacing[i]!);
  const longest = Math.max(...extent);
  if (!(longest > 0)) return Math.sqrt(3) / 2;
  return Math.hypot(...extent.map((e) => e / longest)) / 2;
}

/** What a point light's position sliders are fitted to: the opened volume and its first camera. */
export interface LightScene {
  volume: Pick<VolumeSummary, 'dims' | 'spacing'>;
  /** The session's camera when it was opened or joined (the server's view of the volume). */
  camera: Pick<Camera, 'eye'>;
}

/**
 * How far out the scene reaches from the volume's centre (the origin): to the farther of the
 * volume's edge and the session's first eye. Before a volume is open, a unit cube's corner.
 */
export function sceneReach(scene: LightScene | null): number {
  if (scene === null) return Math.sqrt(3) / 2;
  return Math.max(volumeRadius(scene.volume), Math.hypot(...scene.camera.eye));
}

/**
 * What each coordinate of a point light's position offers on its slider. The server takes any
 * world coordinate in its `vec3` range (±1000 world units), a thousand times the volume's size
 * (its longest side is 1): a slider across all of it would move the light by several volume sizes
 * per pixel. So the slider spans a cube around the volume twice as far out as the farther of the
 * volume's edge and the session's first eye, room to stand the light beyond the volume as far as
 * the viewer or behind the viewer, widened to hold the light's current position (another client or
 * a restored state may have put it farther), and never beyond the server's range.
 */
export function positionSpan(
  coords: SettingRange | undefined,
  scene: LightScene | null,
  position: Vec3,
): { min: number; max: number } {
  const reach = Math.max(2 * sceneReach(scene), ...position.map(Math.abs));
  const min = coords === undefined ? -reach : Math.max(coords.min, -reach);
  const max = coords === undefined ? reach : Math.min(coords.max, reach);
  return { min, max };
}

interface RangedLightControl {
  setting: SettingControl;
  controller: Controller;
  /** hello announces it (a later hello may not). */
  announced: boolean;
}

export class LightControl {
  private light: Light | null = null;
  private readonly params = {
    type: LIGHT_TYPES[0] as LightType,
    color: [1, 1, 1] as number[],
    x: 0,
    y: 0,
    z: 0,
    behind: false,
  };
  /** The light's numbers that hello.ranges announces, by path (light/intensity). */
  private readonly values: Record<string, number> = {};
  private readonly ranged = new Map<string, RangedLightControl>();
  /** The server's range of a world coordinate (hello.ranges `vec3`). */
  private coords: SettingRange | undefined;
  private scene: LightScene | null = null;
  private readonly canvas: HTMLCanvasElement;
  private readonly controllers: Controller[] = [];
  private readonly positionControllers: Controller[] = [];
  /** The ranged controls go before it. */
  private readonly color: Controller;
  private enabled = true;
  private dragging = false;

  constructor(
    private readonly folder: GUI,
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
    const add = this.add.bind(this);
    add(folder.add(p, 'behind').name('from behind'), 'behind').onChange(() => this.draw());
    add(folder.add(p, 'type', [...LIGHT_TYPES]), 'type').onChange(() => {
      this.showPosition();
      this.send({ light: { type: p.type } }, false);
    });
    // The light's numbers arrive with hello's ranges (setRanges), placed before the colour.
    this.color = add(folder.addColor(p, 'color', 1), 'color')
      .onChange(() => this.send({ light: { color: this.rgb() } }, true))
      .onFinishChange(() => this.send({ light: { color: this.rgb() } }, false));
    // Number fields until hello's coordinate range and the opened volume give them a span.
    for (const axis of ['x', 'y', 'z'] as const) {
      const c = add(folder.add(p, axis).name(`position ${axis}`), `position.${axis}`);
      c.onChange(() => this.send({ light: { position: [p.x, p.y, p.z] } }, true));
      c.onFinishChange(() => this.send({ light: { position: [p.x, p.y, p.z] } }, false));
      this.positionControllers.push(c);
    }
    this.attachSphere();
    this.draw();
  }

  private add(c: Controller, key: string): Controller {
    c.domElement.dataset['control'] = `light.${key}`;
    c.enable(this.enabled);
    this.controllers.push(c);
    return c;
  }

  /**
   * The server's ranges from `hello`: a slider for each number of the light spanning its range (a
   * later hello's ranges update them; one it no longer announces is hidden), and the coordinate
   * range the position sliders stay within.
   */
  setRanges(ranges: SettingRanges): void {
    for (const control of this.ranged.values()) control.announced = false;
    for (const setting of lightControls(ranges)) {
      const known = this.ranged.get(setting.path);
      if (known) {
        known.announced = true;
        known.setting = setting;
        known.controller.min(setting.min).max(setting.max);
        known.controller.domElement.title = setting.hint;
        continue;
      }
      this.ranged.set(setting.path, {
        setting,
        controller: this.addRanged(setting),
        announced: true,
      });
    }
    this.coords = ranges['vec3'];
    const within = this.coords ? ` (the server takes ${rangeText(this.coords)})` : '';
    for (const c of this.positionControllers) {
      c.domElement.title = `world coordinate of the point light around the volume${within}`;
    }
    this.showRanged();
    this.spanPosition();
  }

  /** A slider across the server's range (a light's numbers are few and linear: no number field). */
  private addRanged(setting: SettingControl): Controller {
    const held = this.light ? valueAt(this.light, setting.members) : undefined;
    this.values[setting.path] = held ?? setting.min;
    const patch = (): StatePatch => ({
      light: nestedAt(setting.members, this.values[setting.path]!) as StatePatch['light'],
    });
    const c = this.folder.add(
      this.values,
      setting.path,
      setting.min,
      setting.max,
      setting.integer ? 1 : undefined,
    );
    c.name(setting.label);
    c.domElement.title = setting.hint;
    c.domElement.dataset['setting'] = setting.path;
    c.onChange(() => this.send(patch(), true));
    c.onFinishChange(() => this.send(patch(), false));
    this.folder.$children.insertBefore(c.domElement, this.color.domElement);
    return this.add(c, setting.members.join('.'));
  }

  /** A number is shown where hello announces it and the session's light holds it. */
  private showRanged(): void {
    for (const { setting, controller, announced } of this.ranged.values()) {
      const held = this.light === null || valueAt(this.light, setting.members) !== undefined;
      controller.show(announced && held);
    }
  }

  /** The opened volume and the session's camera then, which the position sliders are fitted to. */
  setScene(scene: LightScene): void {
    this.scene = { volume: structuredClone(scene.volume), camera: { eye: [...scene.camera.eye] } };
    this.spanPosition();
  }

  /** Fits the position sliders to the scene and the light's position (positionSpan). */
  private spanPosition(): void {
    if (this.scene === null) return;
    const p = this.params;
    const { min, max } = positionSpan(this.coords, this.scene, [p.x, p.y, p.z]);
    for (const c of this.positionControllers) c.min(min).max(max);
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
    p.color = [...light.color];
    [p.x, p.y, p.z] = light.position;
    for (const { setting } of this.ranged.values()) {
      const value = valueAt(light, setting.members);
      if (value !== undefined) this.values[setting.path] = value;
    }
    this.spanPosition();
    for (const c of this.controllers) c.updateDisplay();
    this.showRanged();
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
    const world = normalize(
      [0, 1, 2].map((i) => view[0] * right[i]! + view[1] * up[i]! + view[2] * back[i]!) as Vec3,
    );
    const light = this.light;
    if (!light) return;
    if (light.type === 'point') {
      // Keeps the light's distance from the target; a light on the target goes as far out as the
      // scene reaches.
      const distance =
        Math.hypot(
          light.position[0] - camera.target[0],
          light.position[1] - camera.target[1],
          light.position[2] - camera.target[2],
        ) || sceneReach(this.scene);
      const { min = -Infinity, max = Infinity } = this.coords ?? {};
      const position = world.map((c, i) =>
        clamp(camera.target[i]! + c * distance, min, max),
      ) as Vec3;
      light.position = position;
      [this.params.x, this.params.y, this.params.z] = position;
      this.spanPosition();
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
