// The crop box on the image: where its edges and the handles of its six faces fall in a frame
// drawn with a given camera, and how far a face moves when its handle is dragged across the
// screen. No DOM (view/crop_box_overlay.ts draws it).
//
// The box is in patient millimetres (RAS), the camera in world units; proto/README.md §5 states
// the relation: world space is patient space moved so that the volume's box is centred on the
// origin and scaled so that its longest side is 1, without a turn.

import { cameraBasis } from '../interaction/orbit_camera';
import type { Camera, Vec3, VolumeSummary } from '../protocol/messages';
import { boundsCentre, CROP_FACES, type FaceKey } from './cut_panel';

/** world = (patient − centre) / millimetresPerUnit. */
export interface Placement {
  centre: Vec3;
  millimetresPerUnit: number;
}

/** Where a volume's patient space lies in world space; null until it is loaded (no bounds). */
export function placementOf(volume: VolumeSummary): Placement | null {
  if (!volume.bounds) return null;
  const longest = Math.max(...volume.dims.map((d, i) => d * volume.spacing[i]!));
  return { centre: boundsCentre(volume.bounds), millimetresPerUnit: longest > 0 ? longest : 1 };
}

/** A patient point (mm) in world units. */
export function toWorld(placement: Placement, patient: Vec3): Vec3 {
  return [0, 1, 2].map(
    (i) => (patient[i]! - placement.centre[i]!) / placement.millimetresPerUnit,
  ) as Vec3;
}

/** A frame as drawn: the camera it was rendered with and its size in image pixels. */
export interface FrameProjection {
  camera: Camera;
  width: number;
  height: number;
}

/** A point of the image in its pixels (x right, y down) and how far before the eye it lies. */
export interface ImagePoint {
  x: number;
  y: number;
  depth: number;
}

/** Points nearer the eye than this (world units) are not drawn: the server's near plane. */
const NEAR = 1e-3;

/** Where a world point falls in the frame: the pinhole camera the server renders with. */
export function project(frame: FrameProjection, world: Vec3): ImagePoint {
  const { camera, width, height } = frame;
  const { right, up, back } = cameraBasis(camera);
  const d = [0, 1, 2].map((i) => world[i]! - camera.eye[i]!) as Vec3;
  const dot = (a: Vec3): number => a[0] * d[0] + a[1] * d[1] + a[2] * d[2];
  const depth = -dot(back);
  const halfHeight = Math.tan((camera.fov * Math.PI) / 360) * Math.max(depth, NEAR);
  const halfWidth = halfHeight * (width / height);
  return {
    x: 0.5 * width * (1 + dot(right) / halfWidth),
    y: 0.5 * height * (1 - dot(up) / halfHeight),
    depth,
  };
}

export interface CropBox {
  min: Vec3;
  max: Vec3;
}

/** The box's corner with bit `axis` of `corner` choosing max over min on that axis. */
function corner(box: CropBox, bits: number): Vec3 {
  return [0, 1, 2].map((axis) => ((bits >> axis) & 1 ? box.max[axis]! : box.min[axis]!)) as Vec3;
}

/** The box's twelve edges in the image, each cut where it passes behind the eye. */
export function boxEdges(
  frame: FrameProjection,
  placement: Placement,
  box: CropBox,
): [ImagePoint, ImagePoint][] {
  const edges: [ImagePoint, ImagePoint][] = [];
  for (let bits = 0; bits < 8; ++bits) {
    for (let axis = 0; axis < 3; ++axis) {
      if ((bits >> axis) & 1) continue;
      let a = toWorld(placement, corner(box, bits));
      let b = toWorld(placement, corner(box, bits | (1 << axis)));
      const depthA = project(frame, a).depth;
      const depthB = project(frame, b).depth;
      if (depthA < NEAR && depthB < NEAR) continue;
      // The part before the near plane: depth is linear along the edge.
      if (depthA < NEAR || depthB < NEAR) {
        const t = (NEAR - depthA) / (depthB - depthA);
        const cut = [0, 1, 2].map((i) => a[i]! + t * (b[i]! - a[i]!)) as Vec3;
        if (depthA < NEAR) a = cut;
        else b = cut;
      }
      edges.push([project(frame, a), project(frame, b)]);
    }
  }
  return edges;
}

/** A face's handle: the centre of the face in the image. */
export interface FaceHandle {
  face: FaceKey;
  at: ImagePoint;
}

/**
 * A face whose axis runs within 10 degrees of the eye's ray to its centre has no handle: the
 * handle would hardly move on the image as the face moves, so a drag would throw the face far.
 */
const EDGE_ON_COSINE = Math.cos((10 * Math.PI) / 180);

type Face = (typeof CROP_FACES)[number];

function faceCentre(box: CropBox, face: Face): Vec3 {
  return [0, 1, 2].map((i) =>
    i === face.axis ? box[face.corner][i]! : 0.5 * (box.min[i]! + box.max[i]!),
  ) as Vec3;
}

/** The handles of the faces that lie before the eye and can be dragged along their axis. */
export function faceHandles(
  frame: FrameProjection,
  placement: Placement,
  box: CropBox,
): FaceHandle[] {
  const handles: FaceHandle[] = [];
  for (const face of CROP_FACES) {
    const centre = toWorld(placement, faceCentre(box, face));
    const at = project(frame, centre);
    if (at.depth < NEAR) continue;
    const ray = [0, 1, 2].map((i) => centre[i]! - frame.camera.eye[i]!);
    if (Math.abs(ray[face.axis]!) > EDGE_ON_COSINE * Math.hypot(...ray)) continue;
    handles.push({ face: face.key, at });
  }
  return handles;
}

/**
 * Where face `key` goes (mm on its axis) so that its handle lies under image point (x, y): the
 * point of the line the handle moves on nearest to the eye's ray through (x, y). So the handle
 * follows the pointer however far the perspective bends the way. Null where the two lines are
 * parallel (the face seen edge-on) or the pointer lies beyond where the axis vanishes.
 */
export function faceUnderPointer(
  frame: FrameProjection,
  placement: Placement,
  box: CropBox,
  key: FaceKey,
  x: number,
  y: number,
): number | null {
  const face = CROP_FACES.find((f) => f.key === key)!;
  const { camera, width, height } = frame;
  const { right, up, back } = cameraBasis(camera);
  const halfHeight = Math.tan((camera.fov * Math.PI) / 360);
  const sx = ((2 * x) / width - 1) * halfHeight * (width / height);
  const sy = (1 - (2 * y) / height) * halfHeight;
  const ray = [0, 1, 2].map((i) => -back[i]! + sx * right[i]! + sy * up[i]!) as Vec3;
  // The face's axis is a world axis too: patient and world space are not turned.
  const axis: Vec3 = [0, 0, 0];
  axis[face.axis] = 1;
  const start = toWorld(placement, faceCentre(box, face));
  const w = [0, 1, 2].map((i) => start[i]! - camera.eye[i]!) as Vec3;
  const dot = (a: Vec3, b: Vec3): number => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const b = dot(axis, ray);
  const c = dot(ray, ray);
  const denominator = c - b * b; // |axis|² = 1
  if (denominator < 1e-9 * c) return null;
  // Past the axis's vanishing point the nearest point of the ray lies behind the eye.
  const along = (dot(ray, w) - b * dot(axis, w)) / denominator;
  if (along <= NEAR) return null;
  const t = (b * dot(ray, w) - c * dot(axis, w)) / denominator;
  return box[face.corner][face.axis]! + t * placement.millimetresPerUnit;
}
