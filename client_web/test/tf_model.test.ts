import { describe, expect, it } from 'vitest';
import { parseServerMessage, type OpenedMessage } from '../src/protocol/messages';
import { checkClientMessage } from './client_checks';
import { presetsFor } from '../src/panels/tf_editor';
import { COLOR_MAPS, histogramCurve, TfModel } from '../src/panels/tf_model';
import { recordedHello, recordedMessages, recordedTerms, recordedTfTerms } from './recorded';

const presetNames = recordedHello.presets.map((p) => p.name);
const inHounsfield = recordedHello.presets
  .filter((p) => p.space === 'hounsfield')
  .map((p) => p.name);

function sorted(xs: number[]): boolean {
  return xs.every((x, i) => i === 0 || xs[i - 1]! <= x);
}

describe('TfModel', () => {
  it("holds a preset as the server's hello announced it and a real server's state reported it (mri_skin)", () => {
    const opened = parseServerMessage(recordedMessages[2]!) as OpenedMessage;
    const tf = opened.state.transfer_function;
    expect(tf.name).toBe('mri_skin');
    const m = new TfModel(recordedTfTerms);
    expect(m.preset('mri_skin')).toEqual(tf);
    m.loadPreset('mri_skin');
    expect({ name: m.name, colors: m.colors, opacities: m.opacities }).toEqual({
      name: tf.name,
      colors: tf.colors,
      opacities: tf.opacities,
    });
    expect(m.preset('no_such_preset')).toBeUndefined();
    expect(() => m.loadPreset('no_such_preset')).toThrow();
  });

  it('has no presets and takes no points before a server said what it holds', () => {
    const m = new TfModel();
    expect(m.addOpacity(0.5, 0.5)).toBe(-1);
    expect(() => m.loadPreset('mri_skin')).toThrow();
  });

  it('loads points sorted and clamped', () => {
    const m = new TfModel();
    m.load({
      colors: [
        { x: 2, rgb: [2, -1, 0.5] },
        { x: 0.2, rgb: [0, 0, 0] },
      ],
      opacities: [
        { x: 0.9, alpha: 3 },
        { x: -1, alpha: 0 },
      ],
    });
    expect(m.colors).toEqual([
      { x: 0.2, rgb: [0, 0, 0] },
      { x: 1, rgb: [1, 0, 0.5] },
    ]);
    expect(m.opacities).toEqual([
      { x: 0, alpha: 0 },
      { x: 0.9, alpha: 1 },
    ]);
  });

  it('inserts opacity points in order and keeps moved points between their neighbours', () => {
    const m = new TfModel(recordedTfTerms, {
      colors: [],
      opacities: [
        { x: 0, alpha: 0 },
        { x: 1, alpha: 1 },
      ],
    });
    const i = m.addOpacity(0.5, 0.25);
    expect(i).toBe(1);
    expect(m.opacities.map((p) => p.x)).toEqual([0, 0.5, 1]);
    m.moveOpacity(1, 1.5, -2); // past the right neighbour and below 0
    expect(m.opacities[1]).toEqual({ x: 1, alpha: 0 });
    m.moveOpacity(1, -3, 0.7);
    expect(m.opacities[1]).toEqual({ x: 0, alpha: 0.7 });
    expect(sorted(m.opacities.map((p) => p.x))).toBe(true);
    m.removeOpacity(1);
    expect(m.opacities).toHaveLength(2);
    expect(m.name).toBe('custom');
  });

  it('adds colour stops with the colour already there, moves and recolours them', () => {
    const m = new TfModel(recordedTfTerms, { colors: COLOR_MAPS['grey']!, opacities: [] });
    const i = m.addColor(0.25);
    expect(m.colors[i]!.rgb).toEqual([0.25, 0.25, 0.25]);
    m.setColor(i, [1, 0, 0]);
    m.moveColor(i, 0.75);
    expect(m.colors[i]).toEqual({ x: 0.75, rgb: [1, 0, 0] });
    m.moveColor(i, 5);
    expect(m.colors[i]!.x).toBe(1);
    m.removeColor(0);
    expect(m.colors).toHaveLength(2);
  });

  it('interpolates like the server: linear inside, constant beyond the ends', () => {
    const m = new TfModel(recordedTfTerms, {
      colors: [
        { x: 0.2, rgb: [0, 0, 0] },
        { x: 0.6, rgb: [1, 0.5, 0] },
      ],
      opacities: [
        { x: 0.5, alpha: 0.2 },
        { x: 1, alpha: 1 },
      ],
    });
    expect(m.opacityAt(0)).toBe(0.2);
    expect(m.opacityAt(0.75)).toBeCloseTo(0.6, 12);
    m.colorAt(0.4).forEach((c, k) => expect(c).toBeCloseTo([0.5, 0.25, 0][k]!, 12));
    expect(m.colorAt(0.9)).toEqual([1, 0.5, 0]);
    expect(new TfModel().opacityAt(0.5)).toBe(0);
  });

  it('picks the nearest point within the radius', () => {
    const m = new TfModel(recordedTfTerms, {
      colors: [{ x: 0.5, rgb: [0, 0, 0] }],
      opacities: [
        { x: 0.1, alpha: 0.1 },
        { x: 0.15, alpha: 0.9 },
      ],
    });
    expect(m.pickOpacity(0.12, 0.85, 0.08)).toBe(1);
    expect(m.pickOpacity(0.5, 0.5, 0.05)).toBe(-1);
    expect(m.pickColor(0.52, 0.05)).toBe(0);
    expect(m.pickColor(0.7, 0.05)).toBe(-1);
  });

  it("stops at the server's point limit (hello.limits)", () => {
    const most = recordedHello.limits.max_transfer_function_points;
    const m = new TfModel(recordedTfTerms);
    for (let k = 0; k < most; ++k) expect(m.addOpacity(k / most, 0.5)).toBeGreaterThanOrEqual(0);
    expect(m.addOpacity(0.5, 0.5)).toBe(-1);
    expect(m.addColor(0.5)).toBeGreaterThanOrEqual(0);
    const few = new TfModel(
      { ...recordedTfTerms, maxPoints: 2 },
      { colors: [], opacities: [{ x: 0, alpha: 1 }] },
    );
    expect(few.addOpacity(0.5, 1)).toBe(1);
    expect(few.addOpacity(0.7, 1)).toBe(-1);
  });

  it('notifies on every change', () => {
    const m = new TfModel(recordedTfTerms);
    let calls = 0;
    m.onChange(() => (calls += 1));
    m.addOpacity(0.5, 0.5);
    m.moveOpacity(0, 0.4, 0.4);
    m.applyColorMap('hot');
    m.loadPreset('ct_bone');
    expect(calls).toBe(4);
    expect(m.name).toBe('ct_bone');
    expect(() => m.applyColorMap('nope')).toThrow();
  });

  it('places the CT presets in Hounsfield units on the volume range', () => {
    const m = new TfModel(recordedTfTerms);
    m.domain = { min: -2048, max: 4095, hounsfield: true };
    m.loadPreset('ct_bone');
    const at = (hu: number) => (hu + 2048) / 6143;
    expect(m.opacities[0]!.x).toBeCloseTo(at(150), 12);
    expect(m.opacities[1]!.x).toBeCloseTo(at(300), 12);
    expect(m.opacities[1]!.alpha).toBe(0.6);
    // A volume not marked HU: read over the server's nominal CT range, as it bakes it.
    const [low, high] = recordedHello.nominal_ct_range;
    m.domain = { min: 0, max: 255, hounsfield: false };
    m.loadPreset('ct_bone');
    expect(m.opacities[1]!.x).toBeCloseTo((300 - low) / (high - low), 12);
    const wider = new TfModel({ ...recordedTfTerms, nominalCtRange: [-2000, 6000] });
    wider.domain = m.domain;
    wider.loadPreset('ct_bone');
    expect(wider.opacities[1]!.x).toBeCloseTo(2300 / 8000, 12);
  });

  it("offers the client's colour maps and the colours of the server's normalised presets", () => {
    const m = new TfModel(recordedTfTerms);
    expect(Object.keys(m.colorMaps)).toEqual(
      expect.arrayContaining([...Object.keys(COLOR_MAPS), 'mri_skin']),
    );
    expect(m.colorMaps['mri_skin']).toEqual(m.preset('mri_skin')!.colors);
    expect(m.colorMaps['ct_bone']).toBeUndefined(); // in HU: no fractions of the range
  });

  it('offers the presets in Hounsfield units first for a volume in Hounsfield units', () => {
    const presets = recordedHello.presets;
    expect(inHounsfield.length).toBeGreaterThan(0);
    expect(presetsFor(presets, true).slice(0, inHounsfield.length)).toEqual(inHounsfield);
    expect([...presetsFor(presets, true)].sort()).toEqual([...presetNames].sort());
    expect(presetsFor(presets, false)).toEqual(presetNames);
  });

  it.each(presetNames)('sends preset %s as a set the server accepts', (preset) => {
    const m = new TfModel(recordedTfTerms);
    m.loadPreset(preset);
    m.addOpacity(0.33, 0.5);
    m.applyColorMap('viridis');
    expect(
      checkClientMessage(
        { v: 1, type: 'set', id: 1, transfer_function: m.toProtocol() },
        recordedTerms,
      ),
    ).toBeNull();
  });
});

describe('histogramCurve', () => {
  it('is log-scaled, skips the dominant bin and stays within [0, 1]', () => {
    const curve = histogramCurve([1_000_000, 0, 99, 9, 999]);
    expect(curve[0]).toBe(1); // clipped
    expect(curve[1]).toBe(0);
    expect(curve[4]).toBe(1); // the largest after skipping
    expect(curve[2]!).toBeCloseTo(Math.log(100) / Math.log(1000), 12);
    expect(histogramCurve([])).toEqual([]);
    expect(histogramCurve([0, 0])).toEqual([0, 0]);
  });
});
