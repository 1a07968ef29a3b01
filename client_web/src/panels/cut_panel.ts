// Cut: the crop box as six faces in patient millimetres (RAS: x toward the patient's right, y
// anterior, z superior), each a slider over the volume's bounds (the `opened` volume's `bounds`);
// clip planes made from the view (each cutting away what lies between the eye and it, at a depth
// along the view that a slider moves); whether what is cut away still casts shadows; and a reset.
// Dragging a face or a depth sends interactive frames; letting go, a still.

import type GUI from 'lil-gui';
import type { Controller } from 'lil-gui';
import {
  SETTINGS,
  type Camera,
  type Cut,
  type State,
  type StatePatch,
  type Vec3,
  type VolumeSummary,
} from '../protocol/messages';

/** The cut's plane members, as many as the server's table has: plane_1, plane_2, ... */
export type PlaneKey = Extract<keyof Cut, `plane_${number}`>;
export type ClipPlane = Cut[PlaneKey];

export const PLANE_KEYS = Object.keys(SETTINGS)
  .filter((path) => /^cut\/plane_\d+\/enabled$/.test(path))
  .map((path) => path.split('/')[1] as PlaneKey);

/** A new session's plane: off, through the origin, facing superior. */
export const UNUSED_PLANE: ClipPlane = { enabled: false, point: [0, 0, 0], normal: [0, 0, 1] };

function dot(a: Vec3, b: Vec3): number {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

function unit(v: Vec3): Vec3 {
  const length = Math.hypot(v[0], v[1], v[2]);
  return length > 0 ? [v[0] / length, v[1] / length, v[2] / length] : [0, 0, 1];
}

/** The centre of the volume's bounds, which planes' depths are measured from. */
export function boundsCentre(bounds: [Vec3, Vec3]): Vec3 {
  return [0, 1, 2].map((i) => 0.5 * (bounds[0][i]! + bounds[1][i]!)) as Vec3;
}

/**
 * The plane across the view at `depth` mm beyond the volume's centre, keeping what lies beyond
 * it: world and patient space differ by a move and a scale, so the view's direction is the same
 * in both.
 */
export function viewPlane(camera: Camera, centre: Vec3, depth: number): ClipPlane {
  const normal = unit([0, 1, 2].map((i) => camera.target[i]! - camera.eye[i]!) as Vec3);
  return { enabled: true, point: planePoint(normal, centre, depth), normal };
}

/** How far beyond the volume's centre a plane lies along its normal, in mm. */
export function planeDepth(plane: ClipPlane, centre: Vec3): number {
  const n = unit(plane.normal);
  return dot([0, 1, 2].map((i) => plane.point[i]! - centre[i]!) as Vec3, n);
}

function planePoint(normal: Vec3, centre: Vec3, depth: number): Vec3 {
  const n = unit(normal);
  return [0, 1, 2].map((i) => centre[i]! + depth * n[i]!) as Vec3;
}

/** The plane a new view plane takes: the first one off, else the last. */
export function freePlane(cut: Cut | undefined): PlaneKey {
  return PLANE_KEYS.find((key) => !cut?.[key]?.enabled) ?? PLANE_KEYS[PLANE_KEYS.length - 1]!;
}

/** The six faces: which corner and axis each moves, and the side of the patient it faces. */
export const CROP_FACES = [
  { key: 'left', corner: 'min', axis: 0, label: 'left (x min)' },
  { key: 'right', corner: 'max', axis: 0, label: 'right (x max)' },
  { key: 'posterior', corner: 'min', axis: 1, label: 'posterior (y min)' },
  { key: 'anterior', corner: 'max', axis: 1, label: 'anterior (y max)' },
  { key: 'inferior', corner: 'min', axis: 2, label: 'inferior (z min)' },
  { key: 'superior', corner: 'max', axis: 2, label: 'superior (z max)' },
] as const;

export type FaceKey = (typeof CROP_FACES)[number]['key'];

/** The crop box within `bounds`, each face kept at least `gap` mm inside the opposite one. */
export function cropWithin(
  min: Vec3,
  max: Vec3,
  bounds: [Vec3, Vec3],
  gap = 0.5,
): { min: Vec3; max: Vec3 } {
  const lo: Vec3 = [0, 0, 0];
  const hi: Vec3 = [0, 0, 0];
  for (let axis = 0; axis < 3; ++axis) {
    const b0 = bounds[0][axis]!;
    const b1 = bounds[1][axis]!;
    lo[axis] = Math.min(Math.max(min[axis]!, b0), b1 - gap);
    hi[axis] = Math.max(Math.min(max[axis]!, b1), lo[axis]! + gap);
  }
  return { min: lo, max: hi };
}

/**
 * The crop box after face `key` was dragged to where `min`/`max` now put it: the dragged face
 * wins, the opposite one gives way to stay `gap` mm beyond it, and the box stays within `bounds`.
 */
export function dragFace(
  min: Vec3,
  max: Vec3,
  key: FaceKey,
  bounds: [Vec3, Vec3],
  gap = 0.5,
): { min: Vec3; max: Vec3 } {
  const face = CROP_FACES.find((f) => f.key === key)!;
  const lo: Vec3 = [...min];
  const hi: Vec3 = [...max];
  if (lo[face.axis]! > hi[face.axis]! - gap) {
    if (face.corner === 'min') hi[face.axis] = lo[face.axis]! + gap;
    else lo[face.axis] = hi[face.axis]! - gap;
  }
  return cropWithin(lo, hi, bounds, gap);
}

/** The `set` patch of a cut. */
export function cutPatch(crop: boolean, min: Vec3, max: Vec3, castsShadows: boolean): StatePatch {
  return { cut: { crop: { enabled: crop, min, max }, casts_shadows: castsShadows } };
}

/** The `set` patch of one plane. */
export function planePatch(key: PlaneKey, plane: ClipPlane): StatePatch {
  return { cut: { [key]: plane } };
}

/** A plane's row of the panel: its switch and its depth. */
interface PlaneRow {
  on: Controller;
  depth: Controller;
}

export class CutPanel {
  private readonly params: Record<FaceKey, number> & {
    crop: boolean;
    show_box: boolean;
    casts_shadows: boolean;
  } = {
    left: 0,
    right: 0,
    posterior: 0,
    anterior: 0,
    inferior: 0,
    superior: 0,
    crop: false,
    show_box: true,
    casts_shadows: false,
  };
  private readonly planeParams: Record<string, number | boolean> = {};
  private readonly planes = new Map<PlaneKey, PlaneRow>();
  private planeState: Partial<Record<PlaneKey, ClipPlane>> = {};
  private readonly faces = new Map<FaceKey, Controller>();
  private readonly controllers: Controller[] = [];
  private bounds: [Vec3, Vec3] | null = null;
  private enabled = true;
  private readonly boxListeners: (() => void)[] = [];

  constructor(
    folder: GUI,
    private readonly change: (patch: StatePatch, interactive: boolean) => void,
    private readonly currentCamera: () => Camera,
  ) {
    const p = this.params;
    const crop = folder.add(p, 'crop').name('crop to the box');
    crop.onChange(() => {
      this.boxChanged();
      this.send(false);
    });
    this.wire(crop, 'crop');
    // The viewer's own choice, not the session's: nothing is sent.
    const showBox = folder.add(p, 'show_box').name('box on the image');
    showBox.onChange(() => this.boxChanged());
    showBox.domElement.dataset['control'] = 'crop-box-shown';
    for (const face of CROP_FACES) {
      const c = folder.add(p, face.key, -1, 1, 0.5).name(face.label).decimals(1);
      c.onChange(() => this.faceMoved(face.key, true));
      c.onFinishChange(() => this.faceMoved(face.key, false));
      this.wire(c, `crop-${face.key}`);
      this.faces.set(face.key, c);
    }
    const viewCut = folder
      .add({ cut: () => this.cutAlongTheView() }, 'cut')
      .name('clip at the view plane');
    this.wire(viewCut, 'clip-view');
    PLANE_KEYS.forEach((key, i) => {
      this.planeParams[`${key}_on`] = false;
      this.planeParams[`${key}_depth`] = 0;
      const on = folder.add(this.planeParams, `${key}_on`).name(`plane ${i + 1}`);
      on.onChange(() => this.planeMoved(key, false));
      const depth = folder
        .add(this.planeParams, `${key}_depth`, -1, 1, 0.5)
        .name(`depth ${i + 1}`)
        .decimals(1);
      depth.onChange(() => this.planeMoved(key, true));
      depth.onFinishChange(() => this.planeMoved(key, false));
      this.wire(on, `plane-${i + 1}`);
      this.wire(depth, `plane-${i + 1}-depth`);
      on.show(false);
      depth.show(false);
      this.planes.set(key, { on, depth });
    });
    const shadows = folder.add(p, 'casts_shadows').name('cut tissue casts shadows');
    shadows.onChange(() => this.send(false));
    this.wire(shadows, 'cut-shadows');
    const reset = folder.add({ reset: () => this.reset() }, 'reset').name('reset the cut');
    this.wire(reset, 'cut-reset');
    const hint = document.createElement('div');
    hint.className = 'hint';
    hint.textContent =
      'Off: what is cut away neither shows nor shadows (a dissection). On: it still shadows.';
    folder.$children.appendChild(hint);
  }

  private wire(c: Controller, key: string): void {
    c.domElement.dataset['control'] = key;
    c.enable(this.enabled);
    this.controllers.push(c);
  }

  /** The volume's bounds (patient mm) are the faces' ranges; a volume without them has no cut. */
  setVolume(volume: VolumeSummary): void {
    this.bounds = volume.bounds ?? null;
    if (!this.bounds) return;
    for (const face of CROP_FACES) {
      this.faces.get(face.key)!.min(this.bounds[0][face.axis]).max(this.bounds[1][face.axis]);
    }
    // A plane through any point of the volume lies within half its diagonal of the centre.
    // Whole millimetres, so that the slider's half-millimetre steps fall on round depths.
    const reach = Math.ceil(
      0.5 *
        Math.hypot(...([0, 1, 2].map((i) => this.bounds![1][i]! - this.bounds![0][i]!) as Vec3)),
    );
    for (const row of this.planes.values()) row.depth.min(-reach).max(reach);
    this.boxChanged();
  }

  /** Called whenever the box the panel shows changes: the session's, or a face moved here. */
  onBoxChange(listener: () => void): void {
    this.boxListeners.push(listener);
  }

  private boxChanged(): void {
    for (const l of this.boxListeners) l();
  }

  /** The crop box to draw over the image: null while the crop is off or the box is hidden. */
  box(): { min: Vec3; max: Vec3 } | null {
    const p = this.params;
    return this.bounds && p.crop && p.show_box ? this.corners() : null;
  }

  /** Whether the user may change the cut (the session's owner). */
  get editable(): boolean {
    return this.enabled;
  }

  /** Moves one face to `millimetres` on its axis, as its slider would. */
  moveFace(key: FaceKey, millimetres: number, interactive: boolean): void {
    if (!this.enabled || !Number.isFinite(millimetres)) return;
    this.params[key] = millimetres;
    this.faceMoved(key, interactive);
  }

  /** Shows the session's cut, its faces within the volume's bounds. */
  update(state: State): void {
    const cut: Cut | undefined = state.cut;
    const p = this.params;
    p.crop = cut?.crop.enabled ?? false;
    p.casts_shadows = cut?.casts_shadows ?? false;
    if (this.bounds) {
      const shown =
        cut && cut.crop.enabled
          ? cropWithin(cut.crop.min, cut.crop.max, this.bounds, 0)
          : { min: this.bounds[0], max: this.bounds[1] };
      for (const face of CROP_FACES) p[face.key] = shown[face.corner][face.axis]!;
    }
    this.planeState = {};
    for (const key of PLANE_KEYS) {
      const plane = cut?.[key] ?? UNUSED_PLANE;
      this.planeState[key] = plane;
      this.showPlane(key, plane);
    }
    for (const c of this.controllers) c.updateDisplay();
    this.boxChanged();
  }

  /** A plane's row shows once the plane was used: on, or moved from a new session's. */
  private showPlane(key: PlaneKey, plane: ClipPlane): void {
    const row = this.planes.get(key)!;
    const used =
      plane.enabled ||
      plane.point.some((v, i) => v !== UNUSED_PLANE.point[i]) ||
      plane.normal.some((v, i) => v !== UNUSED_PLANE.normal[i]);
    this.planeParams[`${key}_on`] = plane.enabled;
    if (this.bounds)
      this.planeParams[`${key}_depth`] = planeDepth(plane, boundsCentre(this.bounds));
    row.on.show(used);
    row.depth.show(used);
  }

  /** A new plane across the view through the volume's centre, cutting away its near half. */
  private cutAlongTheView(): void {
    if (!this.bounds) return;
    const key = freePlane(this.planeState as Cut);
    const plane = viewPlane(this.currentCamera(), boundsCentre(this.bounds), 0);
    this.planeState[key] = plane;
    this.showPlane(key, plane);
    for (const c of this.controllers) c.updateDisplay();
    this.change(planePatch(key, plane), false);
  }

  /** A plane's switch or depth moved. */
  private planeMoved(key: PlaneKey, interactive: boolean): void {
    if (!this.bounds) return;
    const old = this.planeState[key] ?? UNUSED_PLANE;
    const depth = this.planeParams[`${key}_depth`] as number;
    const plane: ClipPlane = {
      enabled: this.planeParams[`${key}_on`] as boolean,
      point: planePoint(old.normal, boundsCentre(this.bounds), depth),
      normal: old.normal,
    };
    this.planeState[key] = plane;
    this.change(planePatch(key, plane), interactive);
  }

  setEnabled(enabled: boolean): void {
    this.enabled = enabled;
    for (const c of this.controllers) c.enable(enabled);
    this.boxChanged(); // the box's handles come and go with it
  }

  private corners(): { min: Vec3; max: Vec3 } {
    const p = this.params;
    return {
      min: [p.left, p.posterior, p.inferior],
      max: [p.right, p.anterior, p.superior],
    };
  }

  /** A face moved: the box turns on, the opposite face gives way, and the cut is sent. */
  private faceMoved(key: FaceKey, interactive: boolean): void {
    if (!this.bounds) return;
    const p = this.params;
    const { min, max } = this.corners();
    const kept = dragFace(min, max, key, this.bounds);
    for (const f of CROP_FACES) p[f.key] = kept[f.corner][f.axis]!;
    p.crop = true;
    for (const c of this.controllers) c.updateDisplay();
    this.boxChanged();
    this.send(interactive);
  }

  private send(interactive: boolean): void {
    const p = this.params;
    const { min, max } = this.corners();
    this.change(cutPatch(p.crop, min, max, p.casts_shadows), interactive);
  }

  /** Back to the whole volume, no plane, cut tissue casting no shadow. */
  private reset(): void {
    const p = this.params;
    p.crop = false;
    p.casts_shadows = false;
    if (this.bounds) {
      for (const face of CROP_FACES)
        p[face.key] = this.bounds[face.corner === 'min' ? 0 : 1][face.axis]!;
    }
    for (const key of PLANE_KEYS) {
      this.planeState[key] = UNUSED_PLANE;
      this.showPlane(key, UNUSED_PLANE);
    }
    for (const c of this.controllers) c.updateDisplay();
    const { min, max } = this.corners();
    const patch = cutPatch(p.crop, min, max, p.casts_shadows);
    for (const key of PLANE_KEYS) Object.assign(patch.cut!, planePatch(key, UNUSED_PLANE).cut);
    this.boxChanged();
    this.change(patch, false);
  }
}
