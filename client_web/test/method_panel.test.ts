import { describe, expect, it } from 'vitest';
import {
  methodControls,
  offeredEncodings,
  settingPatch,
  settingUsed,
  settingValue,
  toggleControls,
} from '../src/panels/method_panel';
import {
  SETTINGS,
  DEFAULT_OUTPUT,
  DEFAULT_SETTINGS,
  parseServerMessage,
  type ModeCapabilities,
  type OpenedMessage,
} from '../src/protocol/messages';
import { checkClientMessage } from './client_checks';
import { recordedHello, recordedMessages, recordedRanges, recordedTerms } from './recorded';

const mode = (name: string): ModeCapabilities => recordedHello.modes.find((m) => m.name === name)!;
const state = (parseServerMessage(recordedMessages[2]!) as OpenedMessage).state;

describe('the frame encodings offered', () => {
  it("are hello's, H.264 only where the browser has WebCodecs", () => {
    expect(recordedHello.encodings).toEqual(['jpeg', 'png', 'h264']);
    expect(offeredEncodings(true)).toEqual(['jpeg', 'png', 'h264']);
    expect(offeredEncodings(false)).toEqual(['jpeg', 'png']);
    for (const encoding of offeredEncodings(true)) {
      expect(
        checkClientMessage({ v: 1, type: 'set', output: { encoding } }, recordedTerms),
      ).toBeNull();
    }
  });
});

describe("the method panel's numeric settings", () => {
  it('offers every setting hello announces a range for, placed by its path', () => {
    const controls = methodControls(recordedRanges);
    const paths = Object.keys(recordedRanges).filter((p) => p.startsWith('settings/'));
    expect(controls.map((c) => c.path)).toEqual(paths);
    const byPath = new Map(controls.map((c) => [c.path, c]));
    expect(byPath.get('settings/light_buffer/compensation')).toMatchObject({
      part: 'light_buffer',
      label: 'compensation',
      kind: 'slider',
      min: 0,
      max: 1000,
      integer: false,
    });
    expect(byPath.get('settings/light_buffer/slab_samples')).toMatchObject({
      kind: 'slider',
      integer: true,
      max: 16,
    });
    expect(byPath.get('settings/scattering/shell_rings')).toMatchObject({
      part: 'scattering',
      integer: true,
    });
    expect(byPath.get('settings/early_termination')).toMatchObject({ part: '', kind: 'slider' });
    // Distances over many decades: a number field with the decimals their low end needs.
    expect(byPath.get('settings/sample_distance')).toMatchObject({
      part: '',
      kind: 'number',
      decimals: 7,
    });
    expect(byPath.get('settings/opacity_unit_distance')).toMatchObject({
      kind: 'number',
      decimals: 6,
    });
    expect(
      controls
        .filter((c) => c.kind === 'number')
        .map((c) => c.path)
        .sort(),
    ).toEqual(['settings/opacity_unit_distance', 'settings/sample_distance']);
  });

  it('offers a setting new to the client with the patch the server takes, and shows it from the state', () => {
    const glow = { min: 0, max: 4, integer: false, summary: 'light-buffer glow' };
    const ranges = { ...recordedRanges, 'settings/light_buffer/glow': glow };
    const control = methodControls(ranges).find((c) => c.path === 'settings/light_buffer/glow')!;
    expect(control).toMatchObject({
      part: 'light_buffer',
      label: 'glow',
      kind: 'slider',
      hint: 'light-buffer glow; within [0, 4]',
    });
    const patch = settingPatch(control.members, 2.5);
    expect(patch).toEqual({ settings: { light_buffer: { glow: 2.5 } } });
    expect(
      checkClientMessage({ v: 1, type: 'set', ...patch }, { ...recordedTerms, ranges }),
    ).toBeNull();
    const withGlow = structuredClone(state);
    (withGlow.settings.light_buffer as unknown as Record<string, number>)['glow'] = 1.5;
    expect(settingValue(withGlow.settings, control.members)).toBe(1.5);
    expect(settingValue(state.settings, control.members)).toBeUndefined();
  });

  it("offers every boolean and choice of the server's table it places nowhere else, in its part's folder", () => {
    // Today's table: the panel places each of them itself.
    expect(toggleControls(SETTINGS)).toEqual([]);
    const table = {
      ...SETTINGS,
      'settings/light_buffer/soft_edges': { kind: 'boolean', summary: 'blur the buffer' },
      'settings/tone': { kind: 'choice', choices: ['linear', 'filmic'], summary: 'tone curve' },
      'light/glow': { kind: 'boolean', summary: "not the panel's" },
    };
    expect(toggleControls(table)).toEqual([
      {
        path: 'settings/light_buffer/soft_edges',
        members: ['light_buffer', 'soft_edges'],
        part: 'light_buffer',
        label: 'soft edges',
        hint: 'blur the buffer',
      },
      {
        path: 'settings/tone',
        members: ['tone'],
        part: '',
        label: 'tone',
        hint: 'tone curve',
        choices: ['linear', 'filmic'],
      },
    ]);
    expect(settingPatch(['light_buffer', 'soft_edges'], true)).toEqual({
      settings: { light_buffer: { soft_edges: true } },
    });
    // Without its own controls the panel would offer every boolean and choice of the table.
    const all = toggleControls(SETTINGS, new Set()).map((c) => c.path);
    expect(all).toEqual(
      expect.arrayContaining(['settings/mode', 'settings/phong', 'settings/light_buffer/lookup']),
    );
  });

  it('sends patches for the recorded settings that the server accepts', () => {
    for (const control of methodControls(recordedRanges)) {
      const value = control.integer ? control.max : (control.min + control.max) / 2;
      expect(
        checkClientMessage(
          { v: 1, type: 'set', ...settingPatch(control.members, value) },
          recordedTerms,
        ),
      ).toBeNull();
      const held = settingValue(state.settings, control.members);
      expect(held).toBeTypeOf('number');
    }
  });

  it("greys out what the mode does not read, by the part of the settings and hello's capabilities", () => {
    expect(settingUsed(mode('sbrc'), 'light_buffer', 'compensation', true)).toBe(true);
    expect(settingUsed(mode('dvr'), 'light_buffer', 'compensation', true)).toBe(false);
    expect(settingUsed(mode('sbrc_cone'), 'scattering', 'cone_angle', true)).toBe(true);
    expect(settingUsed(mode('sbrc_cone'), 'scattering', 'shell_radius', true)).toBe(false);
    expect(settingUsed(mode('sbrc_shell'), 'scattering', 'shell_rings', true)).toBe(true);
    expect(settingUsed(mode('sbrc'), 'scattering', 'shell_rings', true)).toBe(false);
    expect(settingUsed(mode('phong'), 'shading', 'diffuse', false)).toBe(true);
    expect(settingUsed(mode('sbrc'), 'shading', 'diffuse', true)).toBe(true);
    expect(settingUsed(mode('sbrc'), 'shading', 'diffuse', false)).toBe(false);
    expect(settingUsed(mode('dvr'), 'shading', 'diffuse', true)).toBe(false);
    expect(settingUsed(mode('dvr'), '', 'early_termination', true)).toBe(true);
    // A part the panel does not know matters to every mode; before hello everything does.
    expect(settingUsed(mode('dvr'), 'tone', 'exposure', true)).toBe(true);
    expect(settingUsed(undefined, 'light_buffer', 'compensation', true)).toBe(true);
  });
});

describe('the settings shown before the state arrives', () => {
  it("are a new session's, which the server's own checks take", () => {
    // The recorded session opened on a server configured with nothing else, which started it from
    // them (it was recorded before some of today's settings were).
    expect(DEFAULT_SETTINGS).toMatchObject(state.settings);
    expect(state.output).toEqual(DEFAULT_OUTPUT);
    expect(
      checkClientMessage(
        { v: 1, type: 'set', settings: DEFAULT_SETTINGS, output: DEFAULT_OUTPUT },
        recordedTerms,
      ),
    ).toBeNull();
  });
});
