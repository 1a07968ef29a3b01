// Cut: the crop box as six faces in patient millimetres (RAS: x toward the patient's right, y
// anterior, z superior), each a slider over the volume's bounds (the `opened` volume's `bounds`),
// whether what is cut away still casts shadows, and a reset. Dragging a face sends interactive
// frames; letting go, a still.

import type GUI from 'lil-gui';
import type { Controller } from 'lil-gui';
import type { Cut, State, StatePatch, Vec3, VolumeSummary } from '../protocol/messages';

/** The six faces: which corner and axis each moves, and the side of the patient it faces. */
export const CROP_FACES = [
  { key: 'left', corner: 'min', axis: 0, label: 'left (x min)' },
  { key: 'right', corner: 'max', axis: 0, label: 'right (x max)' },
  { key: 'posterior', corner: 'min', axis: 1, label: 'posterior (y min)' },
  { key: 'anterior', corner: 'max', axis: 1, label: 'anterior (y max)' },
  { key: 'inferior', corner: 'min', axis: 2, label: 'inferior (z min)' },
  { key: 'superior', corner: 'max', axis: 2, label: 'superior (z max)' },
] as const;

type FaceKey = (typeof CROP_FACES)[number]['key'];

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

export class CutPanel {
  private readonly params: Record<FaceKey, number> & { crop: boolean; casts_shadows: boolean } = {
    left: 0,
    right: 0,
    posterior: 0,
    anterior: 0,
    inferior: 0,
    superior: 0,
    crop: false,
    casts_shadows: false,
  };
  private readonly faces = new Map<FaceKey, Controller>();
  private readonly controllers: Controller[] = [];
  private bounds: [Vec3, Vec3] | null = null;
  private enabled = true;

  constructor(
    folder: GUI,
    private readonly change: (patch: StatePatch, interactive: boolean) => void,
  ) {
    const p = this.params;
    const crop = folder.add(p, 'crop').name('crop to the box');
    crop.onChange(() => this.send(false));
    this.wire(crop, 'crop');
    for (const face of CROP_FACES) {
      const c = folder.add(p, face.key, -1, 1, 0.5).name(face.label);
      c.onChange(() => this.faceMoved(face.key, true));
      c.onFinishChange(() => this.faceMoved(face.key, false));
      this.wire(c, `crop-${face.key}`);
      this.faces.set(face.key, c);
    }
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
    for (const c of this.controllers) c.updateDisplay();
  }

  setEnabled(enabled: boolean): void {
    this.enabled = enabled;
    for (const c of this.controllers) c.enable(enabled);
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
    this.send(interactive);
  }

  private send(interactive: boolean): void {
    const p = this.params;
    const { min, max } = this.corners();
    this.change(cutPatch(p.crop, min, max, p.casts_shadows), interactive);
  }

  /** Back to the whole volume, cut tissue casting no shadow. */
  private reset(): void {
    const p = this.params;
    p.crop = false;
    p.casts_shadows = false;
    if (this.bounds) {
      for (const face of CROP_FACES)
        p[face.key] = this.bounds[face.corner === 'min' ? 0 : 1][face.axis]!;
    }
    for (const c of this.controllers) c.updateDisplay();
    this.send(false);
  }
}
