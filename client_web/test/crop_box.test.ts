import { describe, expect, it } from 'vitest';
import {
  boxEdges,
  faceHandles,
  faceUnderPointer,
  placementOf,
  project,
  toWorld,
  type FrameProjection,
} from '../src/panels/crop_box';
import { parseServerMessage, type OpenedMessage, type Vec3 } from '../src/protocol/messages';
import { recordedMessages } from './recorded';

// The ch2 head as the server described it when it opened it (181×217×181 voxels of 1 mm).
const opened = parseServerMessage(
  recordedMessages.find((line) => line.includes('"type":"opened"'))!,
) as OpenedMessage;
const volume = opened.volume;
const placement = placementOf(volume)!;
const bounds = volume.bounds!;
const whole = { min: bounds[0], max: bounds[1] };

// The server's default camera: the anterior view (eye on +y, up +z).
const anterior: FrameProjection = {
  camera: { eye: [0, 2.5, 0], target: [0, 0, 0], up: [0, 0, 1], fov: 30 },
  width: 200,
  height: 100,
};

describe('the volume in world space', () => {
  it('is its box centred on the origin with the longest side 1 (proto/README.md §5)', () => {
    const low = toWorld(placement, bounds[0]);
    const high = toWorld(placement, bounds[1]);
    for (let axis = 0; axis < 3; ++axis) expect(low[axis]! + high[axis]!).toBeCloseTo(0, 9);
    const sides = [0, 1, 2].map((axis) => high[axis]! - low[axis]!);
    expect(Math.max(...sides)).toBeCloseTo(1, 9);
    expect(sides[0]).toBeCloseTo(181 / 217, 9);
  });

  it('is unknown until the volume is loaded', () => {
    expect(placementOf({ ...volume, bounds: undefined })).toBeNull();
  });
});

describe('the pinhole projection', () => {
  it('puts the target at the centre and the edge of the field of view at the top', () => {
    const centre = project(anterior, [0, 0, 0]);
    expect(centre.x).toBeCloseTo(100, 9);
    expect(centre.y).toBeCloseTo(50, 9);
    expect(centre.depth).toBeCloseTo(2.5, 9);
    const top = project(anterior, [0, 0, 2.5 * Math.tan(Math.PI / 12)]);
    expect(top.y).toBeCloseTo(0, 9);
    // The field of view is vertical: the image is twice as wide, so the same offset sideways
    // goes halfway to the side.
    const side = project(anterior, [2.5 * Math.tan(Math.PI / 12), 0, 0]);
    expect(side.x).toBeCloseTo(50, 9); // the patient's right is on the image's left
  });
});

describe('the box on the image', () => {
  it('has twelve edges within the image when the whole volume is in view', () => {
    const edges = boxEdges(anterior, placement, whole);
    expect(edges).toHaveLength(12);
    for (const point of edges.flat()) {
      expect(point.depth).toBeGreaterThan(0);
      expect(point.x).toBeGreaterThan(0);
      expect(point.x).toBeLessThan(200);
      expect(point.y).toBeGreaterThan(0);
      expect(point.y).toBeLessThan(100);
    }
  });

  it('cuts its edges at the eye when the eye is inside it', () => {
    const inside: FrameProjection = {
      ...anterior,
      camera: { ...anterior.camera, eye: [0, 0.2, 0] },
    };
    const edges = boxEdges(inside, placement, whole);
    // The four edges along the view pass the eye and are cut; the four on the near face are gone.
    expect(edges).toHaveLength(8);
    for (const point of edges.flat()) expect(point.depth).toBeGreaterThanOrEqual(1e-3 - 1e-12);
  });

  it('has handles on the faces that can be dragged across the view', () => {
    const handles = faceHandles(anterior, placement, whole);
    // Seen from the front, the anterior and posterior faces lie across the view: no handle.
    expect(handles.map((h) => h.face).sort()).toEqual(['inferior', 'left', 'right', 'superior']);
    const right = handles.find((h) => h.face === 'right')!;
    const left = handles.find((h) => h.face === 'left')!;
    const superior = handles.find((h) => h.face === 'superior')!;
    expect(right.at.x).toBeLessThan(100); // the patient's right on the image's left
    expect(left.at.x).toBeGreaterThan(100);
    expect(superior.at.y).toBeLessThan(50);
    expect(right.at.y).toBeCloseTo(50, 9);
  });
});

describe('a face dragged by its handle', () => {
  const oblique: FrameProjection = {
    camera: { eye: [-1.6, 1.2, 0.9], target: [0.05, -0.02, 0.03], up: [0, 0, 1], fov: 35 },
    width: 160,
    height: 120,
  };

  it('stays where it is while the pointer stays on its handle', () => {
    for (const handle of faceHandles(oblique, placement, whole)) {
      const face = handle.face;
      const at = faceUnderPointer(oblique, placement, whole, face, handle.at.x, handle.at.y)!;
      const corner = face === 'left' || face === 'posterior' || face === 'inferior' ? 0 : 1;
      const axis = ['left', 'right'].includes(face)
        ? 0
        : ['posterior', 'anterior'].includes(face)
          ? 1
          : 2;
      expect(at).toBeCloseTo(bounds[corner]![axis]!, 6);
    }
  });

  it('goes where its handle lands under the pointer, however the perspective bends the way', () => {
    for (const [face, axis, corner, to] of [
      ['left', 0, 'min', 12.5],
      ['superior', 2, 'max', -20],
      ['anterior', 1, 'max', 40],
    ] as const) {
      const moved = { min: [...whole.min] as Vec3, max: [...whole.max] as Vec3 };
      moved[corner][axis] = to;
      const target = faceHandles(oblique, placement, moved).find((h) => h.face === face)!;
      expect(
        faceUnderPointer(oblique, placement, whole, face, target.at.x, target.at.y),
      ).toBeCloseTo(to, 6);
    }
  });

  it('does not move where the pointer lies beyond where its axis vanishes', () => {
    // From below and in front, looking up: +z recedes and vanishes on the image. A pointer past
    // that point finds the nearest point of its ray to the axis behind the eye.
    const below: FrameProjection = {
      camera: { eye: [0, 2.5, -1.5], target: [0, 0, 0.5], up: [0, 0, 1], fov: 60 },
      width: 160,
      height: 120,
    };
    const vanishing = project(below, [0, 0.2, 1e9]);
    expect(vanishing.depth).toBeGreaterThan(0);
    expect(
      faceUnderPointer(below, placement, whole, 'superior', vanishing.x, vanishing.y - 30),
    ).toBeNull();
    expect(
      faceUnderPointer(below, placement, whole, 'superior', vanishing.x, vanishing.y + 30),
    ).not.toBeNull();
  });

  it('does not move when seen edge-on', () => {
    // From the front, the anterior face's axis runs along the ray through its centre.
    expect(faceUnderPointer(anterior, placement, whole, 'anterior', 100, 50)).toBeNull();
  });
});
