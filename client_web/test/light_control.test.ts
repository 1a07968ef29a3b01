import { describe, expect, it } from 'vitest';
import { lightControls, positionSpan, sceneReach, volumeRadius } from '../src/panels/light_control';
import { nestedAt } from '../src/panels/ranged_controls';
import {
  parseServerMessage,
  type OpenedMessage,
  type SettingRanges,
} from '../src/protocol/messages';
import { checkClientMessage } from './client_checks';
import { recordedMessages, recordedRanges, recordedTerms } from './recorded';

const opened = parseServerMessage(recordedMessages[2]!) as OpenedMessage;
const scene = { volume: opened.volume, camera: opened.state.camera };

describe("the light control's ranges", () => {
  it("offers the light's numbers over the ranges hello announces", () => {
    const byPath = new Map(lightControls(recordedRanges).map((c) => [c.path, c]));
    expect([...byPath.keys()].sort()).toEqual(['light/ambient', 'light/intensity']);
    // The recorded server takes intensities up to 100.
    expect(byPath.get('light/intensity')).toMatchObject({
      members: ['intensity'],
      label: 'intensity',
      kind: 'slider',
      min: 0,
      max: 100,
    });
    expect(byPath.get('light/ambient')).toMatchObject({ kind: 'slider', min: 0, max: 1 });
    const wider: SettingRanges = {
      ...recordedRanges,
      'light/intensity': { min: 0, max: 250, integer: false },
    };
    expect(lightControls(wider).find((c) => c.path === 'light/intensity')).toMatchObject({
      min: 0,
      max: 250,
    });
  });

  it('offers a number of the light new to the client, with a patch the server takes', () => {
    const ranges: SettingRanges = {
      ...recordedRanges,
      'light/falloff': { min: 0, max: 8, integer: true },
    };
    const control = lightControls(ranges).find((c) => c.path === 'light/falloff')!;
    expect(control).toMatchObject({
      label: 'falloff',
      kind: 'slider',
      integer: true,
      hint: 'within 0..8',
    });
    const set = { v: 1, type: 'set', light: nestedAt(control.members, control.max) };
    expect(checkClientMessage(set, { ...recordedTerms, ranges })).toBeNull();
    expect(
      checkClientMessage(set, {
        ...recordedTerms,
        ranges: { ...ranges, 'light/falloff': { min: 0, max: 4, integer: true } },
      }),
    ).toMatchObject({ code: 'out_of_range', field: '/light/falloff' });
  });

  it('sends the ends of the announced ranges, which the server accepts', () => {
    for (const control of lightControls(recordedRanges)) {
      for (const value of [control.min, control.max]) {
        const set = { v: 1, type: 'set', light: nestedAt(control.members, value) };
        expect(checkClientMessage(set, recordedTerms)).toBeNull();
      }
    }
  });

  it("takes the volume's box from its dims and spacing: longest side 1, centred on the origin", () => {
    expect(volumeRadius({ dims: [10, 10, 10], spacing: [1, 1, 1] })).toBeCloseTo(
      Math.sqrt(3) / 2,
      12,
    );
    expect(volumeRadius({ dims: [100, 50, 50], spacing: [1, 2, 2] })).toBeCloseTo(
      Math.sqrt(3) / 2,
      12,
    );
    expect(volumeRadius({ dims: [100, 100, 25], spacing: [1, 1, 2] })).toBeCloseTo(1.5 / 2, 12);
    expect(volumeRadius({ dims: [0, 0, 0], spacing: [1, 1, 1] })).toBeCloseTo(Math.sqrt(3) / 2, 12);
    // The recorded head: its first eye (2.6 from the centre) lies farther out than its box.
    expect(sceneReach(scene)).toBeCloseTo(2.6, 9);
  });

  it("fits the position sliders to the scene, within the server's coordinate range", () => {
    const coords = recordedRanges['vec3']!;
    expect(coords).toMatchObject({ min: -1000, max: 1000 });
    // Twice the scene's reach around the volume; the recorded default light (z = 3) lies within.
    const span = positionSpan(coords, scene, opened.state.light.position);
    expect(span.min).toBeCloseTo(-5.2, 9);
    expect(span.max).toBeCloseTo(5.2, 9);
    // A light put farther (by another client or a restored state) is still on its slider.
    expect(positionSpan(coords, scene, [0, -400, 3])).toEqual({ min: -400, max: 400 });
    // Never beyond what the server takes: a narrower coordinate range narrows the sliders.
    expect(positionSpan({ min: -2, max: 3, integer: false }, scene, [0, 0, 1])).toEqual({
      min: -2,
      max: 3,
    });
    expect(positionSpan(coords, scene, [0, 0, 5000])).toEqual({ min: -1000, max: 1000 });
    // Every position a slider offers is one the server accepts.
    for (const c of [span.min, span.max]) {
      expect(
        checkClientMessage({ v: 1, type: 'set', light: { position: [c, c, c] } }, recordedTerms),
      ).toBeNull();
    }
  });
});
