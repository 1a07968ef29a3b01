import { describe, expect, it } from 'vitest';
import {
  attachOrbitControls,
  cameraBasis,
  OrbitCamera,
  orbitLimits,
  viewAngles,
} from '../src/interaction/orbit_camera';
import { TapTracker } from '../src/interaction/tap';
import { VIEW_POSES } from '../src/protocol/generated/server_tables';
import { orbitEye } from '../src/interaction/orbit_camera';
import { VIEWS, type Camera, type SettingRanges } from '../src/protocol/messages';
import { checkClientMessage } from './client_checks';
import { recordedRanges, recordedTerms } from './recorded';

const start: Camera = { eye: [0, 2.6, 0], target: [0, 0, 0], up: [0, 0, 1], fov: 30 };

function close(a: number[], b: number[], digits = 9): void {
  a.forEach((v, i) => expect(v).toBeCloseTo(b[i]!, digits));
}

describe('OrbitCamera', () => {
  it("turns each of the server's view poses into orbit angles on the pose's side", () => {
    // VIEW_POSES is written from scene::view_camera (SchemaAgreement.TheClientTablesHold...).
    for (const view of VIEWS) {
      const { side, up } = VIEW_POSES[view];
      const angles = viewAngles(view);
      close(orbitEye([0, 0, 0], { ...angles, distance: 1 }), [...side], 2);
      // Short of the pole, the image's up leans the way the pose's up points.
      const camera = new OrbitCamera();
      camera.setView(view);
      const imageUp = cameraBasis(camera.toCamera()).up;
      expect(imageUp[0] * up[0] + imageUp[1] * up[1] + imageUp[2] * up[2]).toBeGreaterThan(0.99);
    }
  });

  it('round-trips a protocol camera', () => {
    const c = new OrbitCamera();
    c.setFrom({
      eye: [1.082114125889637, 2.320601231751478, 0.4514852619340189],
      target: [0, 0, 0],
      up: [0, 0, 1],
      fov: 30,
    });
    expect(c.azimuth).toBeCloseTo(25, 9);
    expect(c.elevation).toBeCloseTo(10, 9);
    close(c.toCamera().eye, [1.082114125889637, 2.320601231751478, 0.4514852619340189]);
  });

  it('orbits half a turn per view height and clamps the elevation short of the pole', () => {
    const c = new OrbitCamera();
    c.setFrom(start);
    c.rotate(-100, 0, 200); // drag left by half the height: +90 degrees azimuth
    expect(c.azimuth).toBeCloseTo(90, 9);
    close(c.toCamera().eye, [2.6, 0, 0]);
    c.rotate(0, 10_000, 200);
    expect(c.elevation).toBe(89);
    expect(c.toCamera().eye[2]).toBeGreaterThan(2.5);
  });

  it('pans in the view plane: the target moves, the view direction stays', () => {
    const c = new OrbitCamera();
    c.setFrom(start);
    const before = cameraBasis(c.toCamera());
    c.pan(-50, 0, 100);
    // Looking along -y from +y, "right" is -x; dragging left moves the target right.
    expect(c.target[1]).toBeCloseTo(0, 12);
    expect(c.target[2]).toBeCloseTo(0, 12);
    expect(Math.abs(c.target[0])).toBeGreaterThan(0.1);
    close(cameraBasis(c.toCamera()).back, before.back);
  });

  it("zooms within the server's orbit distances and resets to the camera it started from", () => {
    const c = new OrbitCamera();
    c.setRanges(recordedRanges);
    c.setFrom(start, true);
    c.zoom(0.5);
    expect(c.distance).toBeCloseTo(1.3, 12);
    c.zoom(1e-9);
    expect(c.distance).toBe(recordedRanges['camera/orbit/distance']!.min);
    c.zoom(Number.NaN);
    expect(c.distance).toBe(0.01);
    c.zoom(1e9);
    expect(c.distance).toBe(100);
    expect(
      checkClientMessage({ v: 1, type: 'set', camera: c.toCamera() }, recordedTerms),
    ).toBeNull();
    c.reset();
    close(c.toCamera().eye, start.eye);
  });

  it("takes its limits from the server's ranges", () => {
    expect(orbitLimits(recordedRanges)).toEqual({
      distance: { min: 0.01, max: 100 },
      elevation: { min: -89, max: 89 },
      // Any eye 100 from a target within ±900 is within the server's ±1000.
      target: { min: -900, max: 900 },
    });
    const narrow: SettingRanges = {
      ...recordedRanges,
      'camera/orbit/distance': { min: 0.5, max: 10, integer: false },
      'camera/orbit/elevation': { min: -45, max: 60, integer: false },
      vec3: { min: -5, max: 5, integer: false },
    };
    expect(orbitLimits(narrow)).toEqual({
      distance: { min: 0.5, max: 10 },
      elevation: { min: -45, max: 60 },
      target: { min: 0, max: 0 },
    });
    const c = new OrbitCamera();
    c.setFrom(start);
    c.setRanges(narrow);
    c.zoom(100);
    expect(c.distance).toBe(10);
    c.rotate(0, 10_000, 200);
    expect(c.elevation).toBe(60);
    c.setView('inferior');
    expect(c.elevation).toBe(-45);
    c.pan(-5000, 0, 100);
    expect(c.target).toEqual([0, 0, 0]);
  });

  it("pans the target no farther than the eye stays within the server's coordinates", () => {
    const c = new OrbitCamera();
    c.setRanges(recordedRanges);
    c.setFrom(start);
    for (let i = 0; i < 200; ++i) c.zoom(10);
    for (let i = 0; i < 200; ++i) c.pan(-1e6, 1e6, 100);
    expect(Math.max(...c.target.map(Math.abs))).toBeLessThanOrEqual(900);
    expect(
      checkClientMessage({ v: 1, type: 'set', camera: c.toCamera() }, recordedTerms),
    ).toBeNull();
  });

  it('produces cameras the server accepts', () => {
    const c = new OrbitCamera();
    c.setFrom(start);
    c.rotate(123, -45, 300);
    c.pan(10, 20, 300);
    c.zoom(3);
    expect(
      checkClientMessage({ v: 1, type: 'set', camera: c.toCamera() }, recordedTerms),
    ).toBeNull();
  });
});

/** An element the controls listen to, 200 pixels tall; pointer events as plain events. */
class FakeView extends EventTarget {
  clientHeight = 200;
  focus(): void {}
  setPointerCapture(): void {}
  pointer(type: string, x: number, y: number, pointerType = 'mouse', pointerId = 1): void {
    const e = Object.assign(new Event(type, { cancelable: true }), {
      pointerId,
      pointerType,
      clientX: x,
      clientY: y,
      button: 0,
      shiftKey: false,
      ctrlKey: false,
      metaKey: false,
      altKey: false,
    });
    this.dispatchEvent(e);
  }
}

function controlled(): { view: FakeView; camera: OrbitCamera; changes: () => number } {
  const view = new FakeView();
  const camera = new OrbitCamera();
  camera.setFrom(start);
  let changes = 0;
  attachOrbitControls(view as unknown as HTMLElement, camera, {
    change: () => (changes += 1),
    start: () => {},
    end: () => {},
    enabled: () => true,
  });
  return { view, camera, changes: () => changes };
}

describe('the orbit controls', () => {
  it('turn nothing while a press wobbles within what a tap allows', () => {
    for (const [pointerType, wobble] of [
      ['mouse', [4, 3]],
      ['touch', [8, 6]],
    ] as const) {
      const { view, camera, changes } = controlled();
      const tap = new TapTracker();
      const sample = (x: number, y: number) => ({
        pointerId: 1,
        clientX: x,
        clientY: y,
        timeStamp: 0,
        pointerType,
      });
      view.pointer('pointerdown', 100, 100, pointerType);
      tap.pointerDown(sample(100, 100));
      view.pointer('pointermove', 100 + wobble[0], 100 + wobble[1], pointerType);
      tap.pointerMove(sample(100 + wobble[0], 100 + wobble[1]));
      view.pointer('pointerup', 100 + wobble[0], 100 + wobble[1], pointerType);
      expect(tap.pointerUp(sample(100 + wobble[0], 100 + wobble[1]))).not.toBeNull();
      expect(changes()).toBe(0);
      expect(camera.azimuth).toBe(0);
      expect(camera.elevation).toBe(0);
    }
  });

  it('past it, turn as far as the drag went from the press, as without the slop', () => {
    const { view, camera, changes } = controlled();
    view.pointer('pointerdown', 100, 100);
    view.pointer('pointermove', 104, 100);
    expect(changes()).toBe(0);
    view.pointer('pointermove', 106, 100); // 1 pixel past the mouse's 5
    expect(changes()).toBe(1);
    expect(camera.azimuth).toBeCloseTo((-6 * 180) / 200, 9);
    view.pointer('pointermove', 126, 100); // then as the pointer moves
    expect(camera.azimuth).toBeCloseTo((-26 * 180) / 200, 9);
    view.pointer('pointerup', 126, 100);
  });
});
