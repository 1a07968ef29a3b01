import { describe, expect, it } from 'vitest';
import { cropWithin, cutPatch, dragFace } from '../src/panels/cut_panel';
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
