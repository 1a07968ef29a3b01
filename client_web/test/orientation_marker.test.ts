import { describe, expect, it } from 'vitest';
import { OrbitCamera, viewPose } from '../src/interaction/orbit_camera';
import { VIEWS, type Camera, type ViewName } from '../src/protocol/messages';
import { markerEnds } from '../src/view/orientation_marker';

// Which label lies furthest right and which furthest up on screen.
function screenAxes(view: ViewName): { right: string; up: string } {
  const camera = new OrbitCamera();
  camera.setView(view);
  return screenAxesOf(camera.toCamera());
}

function screenAxesOf(camera: Camera): { right: string; up: string } {
  const ends = markerEnds(camera);
  return {
    right: ends.reduce((a, b) => (b.x > a.x ? b : a)).label,
    up: ends.reduce((a, b) => (b.y < a.y ? b : a)).label,
  };
}

describe('named views and the orientation marker', () => {
  it('shows each view from its side with the anatomical up (RAS world)', () => {
    // Facing the patient, the patient's left is on the viewer's right.
    expect(screenAxes('anterior')).toEqual({ right: 'L', up: 'S' });
    expect(screenAxes('posterior')).toEqual({ right: 'R', up: 'S' });
    expect(screenAxes('left')).toEqual({ right: 'P', up: 'S' });
    expect(screenAxes('right')).toEqual({ right: 'A', up: 'S' });
    expect(screenAxes('superior')).toEqual({ right: 'R', up: 'A' });
    expect(screenAxes('inferior')).toEqual({ right: 'L', up: 'A' });
  });

  it('keeps the target, distance and field of view', () => {
    const camera = new OrbitCamera();
    camera.setFrom({ eye: [0.3, 3, 0.2], target: [0.3, 0, 0.2], up: [0, 0, 1], fov: 40 });
    for (const view of VIEWS) {
      camera.setView(view);
      const c = camera.toCamera();
      expect(Math.hypot(c.eye[0] - 0.3, c.eye[1], c.eye[2] - 0.2)).toBeCloseTo(3, 9);
      expect(c.target).toEqual([0.3, 0, 0.2]);
      expect(c.fov).toBe(40);
    }
  });

  it('points each button view the way the server poses the named view', () => {
    const start: Camera = { eye: [0, 0, 3], target: [0, 0, 0], up: [0, 0, 1], fov: 30 };
    for (const view of VIEWS) {
      const server: Camera = { ...start, ...viewPose(view, start.target, 3) };
      const camera = new OrbitCamera();
      camera.setFrom(start);
      camera.setView(view);
      const client = camera.toCamera();
      // The same side and, on screen, the same up (the orbit stops 1 degree short of the poles).
      const cosine =
        (client.eye[0] * server.eye[0] +
          client.eye[1] * server.eye[1] +
          client.eye[2] * server.eye[2]) /
        9;
      expect(cosine).toBeGreaterThan(Math.cos((1.01 * Math.PI) / 180));
      expect(screenAxes(view)).toEqual(screenAxesOf(server));
    }
  });

  it('turns with the camera', () => {
    const camera = new OrbitCamera();
    const before = markerEnds(camera.toCamera());
    camera.rotate(-50, 0, 200); // a quarter turn toward +x
    const after = markerEnds(camera.toCamera());
    const r = (ends: typeof before) => ends.find((e) => e.label === 'R')!;
    expect(r(before).x).toBeCloseTo(-1, 9);
    expect(r(after).x).not.toBeCloseTo(r(before).x, 3);
  });
});
