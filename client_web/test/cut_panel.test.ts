import { describe, expect, it } from 'vitest';
import {
  boundsCentre,
  cropWithin,
  cutPatch,
  dragFace,
  freePlane,
  PLANE_KEYS,
  planeDepth,
  planePatch,
  viewPlane,
} from '../src/panels/cut_panel';
import type { Vec3 } from '../src/protocol/messages';
import { checkClientMessage } from './client_checks';
import { recordedTerms } from './recorded';

// ch2's bounds in patient millimetres, as its `opened` volume gives them.
const bounds: [Vec3, Vec3] = [
  [-90.5, -125.5, -71.5],
  [90.5, 91.5, 109.5],
];

describe('the crop box', () => {
  it('stays within the volume and keeps its faces apart', () => {
    expect(cropWithin([-200, -10, 5], [300, -10, 4], bounds)).toEqual({
      min: [-90.5, -10, 5],
      max: [90.5, -9.5, 5.5],
    });
  });

  it('pushes the opposite face ahead of a dragged one', () => {
    // The left face dragged past the right one: the right one gives way.
    expect(dragFace([20, -125.5, -71.5], [10, 90.5, 109.5], 'left', bounds)).toEqual({
      min: [20, -125.5, -71.5],
      max: [20.5, 90.5, 109.5],
    });
    // The superior face dragged below the inferior one: the inferior one gives way.
    expect(dragFace([-90.5, -125.5, 0], [90.5, 91.5, -30], 'superior', bounds)).toEqual({
      min: [-90.5, -125.5, -30.5],
      max: [90.5, 91.5, -30],
    });
    // Past the volume's end, the dragged face stops there.
    expect(dragFace([-90.5, -125.5, -71.5], [90.5, 91.5, 500], 'superior', bounds).max[2]).toBe(
      109.5,
    );
  });

  it('sends a cut that the server takes', () => {
    const { min, max } = dragFace([0, -125.5, -71.5], [90.5, 91.5, 109.5], 'left', bounds);
    for (const castsShadows of [false, true]) {
      const set = { v: 1, type: 'set', ...cutPatch(true, min, max, castsShadows) };
      expect(checkClientMessage(set, recordedTerms)).toBeNull();
    }
    // The server's reach is ten metres: a corner beyond it is refused.
    const far = { v: 1, type: 'set', ...cutPatch(true, [-20000, 0, 0], [0, 1, 1], false) };
    expect(checkClientMessage(far, recordedTerms)).toMatchObject({
      code: 'out_of_range',
      field: '/cut/crop/min/0',
    });
  });
});

describe('clip planes', () => {
  const centre = boundsCentre(bounds);

  it('are as many as the server holds, each off until used', () => {
    expect(PLANE_KEYS).toEqual(['plane_1', 'plane_2', 'plane_3', 'plane_4', 'plane_5', 'plane_6']);
    expect(freePlane(undefined)).toBe('plane_1');
  });

  it('cut across the view, keeping what lies beyond the plane', () => {
    // Looking from the patient's left (-x) toward the centre: the plane faces +x, so the left
    // part, between the eye and the plane, goes.
    const camera = {
      eye: [-2.6, 0, 0] as Vec3,
      target: [0, 0, 0] as Vec3,
      up: [0, 0, 1] as Vec3,
      fov: 30,
    };
    const plane = viewPlane(camera, centre, 20);
    expect(plane.enabled).toBe(true);
    expect(plane.normal).toEqual([1, 0, 0]);
    expect(plane.point).toEqual([20, centre[1], centre[2]]);
    expect(planeDepth(plane, centre)).toBeCloseTo(20, 12);
    // A tilted view: the depth is measured along the view, whatever the plane's point.
    const tilted = viewPlane({ ...camera, eye: [1, 2, -2] }, centre, -35);
    expect(Math.hypot(...tilted.normal)).toBeCloseTo(1, 12);
    expect(planeDepth(tilted, centre)).toBeCloseTo(-35, 9);
  });

  it('take the first plane that is off, else the last', () => {
    const on = { enabled: true, point: [0, 0, 0] as Vec3, normal: [1, 0, 0] as Vec3 };
    const off = { ...on, enabled: false };
    const cut = {
      crop: { enabled: false, min: bounds[0], max: bounds[1] },
      casts_shadows: false,
      plane_1: on,
      plane_2: on,
      plane_3: off,
      plane_4: on,
      plane_5: off,
      plane_6: off,
    };
    expect(freePlane(cut)).toBe('plane_3');
    expect(freePlane({ ...cut, plane_3: on, plane_5: on, plane_6: on })).toBe('plane_6');
  });

  it('send a plane that the server takes, and a normal beyond its range is refused', () => {
    const camera = {
      eye: [1, -2, 0.5] as Vec3,
      target: [0, 0, 0] as Vec3,
      up: [0, 0, 1] as Vec3,
      fov: 30,
    };
    const set = { v: 1, type: 'set', ...planePatch('plane_4', viewPlane(camera, centre, 10)) };
    expect(checkClientMessage(set, recordedTerms)).toBeNull();
    const bent = { v: 1, type: 'set', cut: { plane_2: { normal: [0, 0, 2] } } };
    expect(checkClientMessage(bent, recordedTerms)).toMatchObject({
      code: 'out_of_range',
      field: '/cut/plane_2/normal/2',
    });
  });
});
