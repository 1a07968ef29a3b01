// Method and quality: the rendering mode (those the server's hello offers, with what each reads),
// compositing, volume filter, ray-caster stage, light-buffer slices, resolution, builder and
// lookup, the toggles (Blinn-Phong, jitter, pre-integration, empty-space skipping), background and
// the output
// encoding, and a control for every numeric setting the server's hello announces a range for
// (hello.ranges), placed by its path: settings/light_buffer/* under the light buffer, settings/scattering/* under shell & cone,
// settings/shading/* under shading, settings/* under sampling, another part in a folder of its own;
// and a checkbox or a list for every boolean or choice of the server's table (SETTINGS) that it
// places nowhere else, in the same folders. A new numeric, boolean or choice setting of the server
// gets its control here with no change to this file.

import type GUI from 'lil-gui';
import type { Controller } from 'lil-gui';
import {
  BUILDERS,
  LIGHT_LOOKUPS,
  COMPOSITINGS,
  DEFAULT_LIMITS,
  DEFAULT_OUTPUT,
  DEFAULT_SETTINGS,
  ENCODINGS,
  RECONSTRUCTIONS,
  STAGES,
  type Builder,
  type Compositing,
  type Encoding,
  type LightLookup,
  type Limits,
  type Mode,
  type ModeCapabilities,
  type Reconstruction,
  type SettingRanges,
  SETTINGS,
  type Stage,
  type State,
  type StatePatch,
} from '../protocol/messages';
import {
  labelOf,
  nestedAt,
  settingControls,
  valueAt,
  type SettingControl,
} from './ranged_controls';

export type PatchSink = (patch: StatePatch, interactive: boolean) => void;

/**
 * Whether a mode reads the settings of a part of `settings` (`light_buffer`: those under
 * settings/light_buffer/), from what the server's hello says the mode computes; the settings
 * outside a part (''), and those of a part not named here, matter to every mode. The others are
 * greyed out, still settable. Before hello, or for a mode hello did not list, all matter.
 */
type PartUsed = (mode: ModeCapabilities, name: string, phong: boolean) => boolean;
const PART_USED: Record<string, PartUsed> = {
  light_buffer: (m) => m.shadows === 'light_buffer',
  // The scattering kind names its settings: shell_radius for `shell`, cone_angle for `cone`.
  scattering: (m, name) => m.scattering !== 'none' && name.startsWith(`${m.scattering}_`),
  shading: (m, _, phong) => m.gradients === 'always' || (m.gradients === 'with_phong' && phong),
};

export function settingUsed(
  mode: ModeCapabilities | undefined,
  part: string,
  name: string,
  phong: boolean,
): boolean {
  return mode === undefined || (PART_USED[part]?.(mode, name, phong) ?? true);
}

/** The control of each numeric setting (settings/...) that hello.ranges announces. */
export function methodControls(ranges: SettingRanges): SettingControl[] {
  return settingControls(ranges, 'settings');
}

/** The `set` patch that gives the setting at `members` (under settings) `value`. */
/**
 * The frame encodings this browser can show: H.264 only where it has WebCodecs' VideoDecoder
 * (which decodes the stream's frames in order); JPEG and PNG everywhere.
 */
export function offeredEncodings(
  webCodecs: boolean = typeof globalThis.VideoDecoder === 'function',
): Encoding[] {
  return ENCODINGS.filter((e) => e !== 'h264' || webCodecs);
}

export function settingPatch(members: string[], value: number | boolean | string): StatePatch {
  return { settings: nestedAt(members, value) as StatePatch['settings'] };
}

/** The booleans and choices under settings/ that the panel has controls of its own for. */
const PLACED = new Set([
  'settings/mode',
  'settings/compositing',
  'settings/reconstruction',
  'settings/stage',
  'settings/phong',
  'settings/jitter',
  'settings/preintegration',
  'settings/empty_space_skipping',
  'settings/light_buffer/builder',
  'settings/light_buffer/lookup',
]);

/** A boolean or a choice of the server's table, offered as a checkbox or a list. */
export interface ToggleControl {
  path: string;
  /** The members under `settings`: ['light_buffer', 'builder']. */
  members: string[];
  part: string;
  label: string;
  hint: string;
  /** A choice's names; none for a boolean. */
  choices?: readonly string[];
}

interface TableSetting {
  kind: string;
  summary: string;
  choices?: readonly string[];
}

/** The booleans and choices of `table` (SETTINGS) under settings/ that `placed` leaves out. */
export function toggleControls(
  table: Readonly<Record<string, TableSetting>>,
  placed: ReadonlySet<string> = PLACED,
): ToggleControl[] {
  return Object.entries(table)
    .filter(
      ([path, s]) =>
        path.startsWith('settings/') &&
        !placed.has(path) &&
        (s.kind === 'boolean' || s.kind === 'choice'),
    )
    .map(([path, s]) => {
      const members = path.split('/').slice(1);
      return {
        path,
        members,
        part: members.length > 1 ? members[0]! : '',
        label: labelOf(members[members.length - 1]!),
        hint: s.summary,
        ...(s.kind === 'choice' ? { choices: s.choices } : {}),
      };
    });
}

/** The value of the setting at `members` in a state's settings, or undefined where it has none. */
export function settingValue(settings: State['settings'], members: string[]): number | undefined {
  return valueAt(settings, members);
}

/** A boolean or a name at `members` in a state's settings, or undefined where it has none. */
function valueIn(
  settings: State['settings'] | undefined,
  members: string[],
): boolean | string | undefined {
  let value: unknown = settings;
  for (const member of members) {
    value =
      typeof value === 'object' && value !== null
        ? (value as Record<string, unknown>)[member]
        : undefined;
  }
  return typeof value === 'boolean' || typeof value === 'string' ? value : undefined;
}

interface RangedControl {
  setting: SettingControl;
  controller: Controller;
  /** hello announces it (a later hello may not). */
  announced: boolean;
}

export class MethodPanel {
  readonly params = {
    /** None until the server's hello names its modes. */
    mode: '' as string,
    // Until the session's state arrives, what a new session of the server starts from.
    compositing: DEFAULT_SETTINGS.compositing as Compositing,
    reconstruction: DEFAULT_SETTINGS.reconstruction as Reconstruction,
    stage: DEFAULT_SETTINGS.stage as Stage,
    slices: DEFAULT_SETTINGS.light_buffer.slices as number,
    resolution: DEFAULT_SETTINGS.light_buffer.resolution as number,
    builder: DEFAULT_SETTINGS.light_buffer.builder as Builder,
    lookup: DEFAULT_SETTINGS.light_buffer.lookup as LightLookup,
    phong: DEFAULT_SETTINGS.phong as boolean,
    background: [...DEFAULT_SETTINGS.background] as number[],
    encoding: DEFAULT_OUTPUT.encoding as Encoding,
    jpeg_quality: DEFAULT_OUTPUT.jpeg_quality as number,
    h264_quality: DEFAULT_OUTPUT.h264_quality as number,
    jitter: DEFAULT_SETTINGS.jitter as boolean,
    preintegration: DEFAULT_SETTINGS.preintegration as boolean,
    empty_space_skipping: DEFAULT_SETTINGS.empty_space_skipping as boolean,
    /** Client side: rendered pixels per device pixel. */
    scale: 1,
  };
  /** The values of the numeric settings, by path (settings/light_buffer/compensation). */
  private readonly values: Record<string, number> = {};
  /** The values of the table's other booleans and choices, by path. */
  private readonly toggles: Record<string, boolean | string> = {};
  private readonly toggled: ToggleControl[] = toggleControls(SETTINGS);
  private readonly controllers: Controller[] = [];
  private readonly byKey = new Map<string, Controller>();
  private readonly ranged = new Map<string, RangedControl>();
  /** The folder of each part of `settings` ('' for the settings directly in it). */
  private readonly parts = new Map<string, GUI>();
  private readonly mode: Controller;
  private modes = new Map<string, ModeCapabilities>();
  private readonly slices: Controller;
  private readonly resolution: Controller;
  private enabled = true;
  private state: State | null = null;

  constructor(
    private readonly folder: GUI,
    private readonly send: PatchSink,
    private readonly scaleChanged: (scale: number) => void,
  ) {
    const p = this.params;
    const add = this.add.bind(this);
    const settings = (s: StatePatch['settings']): StatePatch => ({ settings: s });

    // The server's modes arrive with its hello (setModes).
    this.mode = add(
      folder.add(p, 'mode', [p.mode]),
      'mode',
      () => settings({ mode: p.mode as Mode }),
      false,
    );
    this.mode.onChange(() => this.greyOut());
    add(
      folder.add(p, 'compositing', [...COMPOSITINGS]),
      'compositing',
      () => settings({ compositing: p.compositing }),
      false,
    );
    add(
      folder.add(p, 'reconstruction', [...RECONSTRUCTIONS]).name('volume filter'),
      'reconstruction',
      () => settings({ reconstruction: p.reconstruction }),
      false,
    );
    add(
      folder.add(p, 'stage', [...STAGES]).name('ray caster stage'),
      'stage',
      () => settings({ stage: p.stage }),
      false,
    );

    const lb = folder.addFolder('Light buffer & slices');
    this.slices = add(lb.add(p, 'slices', 1, DEFAULT_LIMITS.max_slices, 1), 'slices', () =>
      settings({ light_buffer: { slices: p.slices } }),
    );
    this.resolution = add(
      lb.add(p, 'resolution', 1, DEFAULT_LIMITS.max_light_resolution, 1).name('resolution R'),
      'resolution',
      () => settings({ light_buffer: { resolution: p.resolution } }),
    );
    add(
      lb.add(p, 'builder', [...BUILDERS]),
      'builder',
      () => settings({ light_buffer: { builder: p.builder } }),
      false,
    );
    add(
      lb.add(p, 'lookup', [...LIGHT_LOOKUPS]).name('light lookup'),
      'lookup',
      () => settings({ light_buffer: { lookup: p.lookup } }),
      false,
    );

    const sampling = folder.addFolder('Sampling');
    add(
      sampling.add(p, 'jitter').name('jittered samples'),
      'jitter',
      () => settings({ jitter: p.jitter }),
      false,
    );
    // Classifies each segment between two samples by both values: no rings on steep TFs.
    add(
      sampling.add(p, 'preintegration').name('pre-integration'),
      'preintegration',
      () => settings({ preintegration: p.preintegration }),
      false,
    );
    // Skips the volume's empty bricks while marching: faster, the same image.
    add(
      sampling.add(p, 'empty_space_skipping').name('empty-space skipping'),
      'empty_space_skipping',
      () => settings({ empty_space_skipping: p.empty_space_skipping }),
      false,
    );

    const scattering = folder.addFolder('Shell & cone scattering');
    scattering.close();

    const shading = folder.addFolder('Shading');
    shading.close();
    const phong = add(
      shading.add(p, 'phong').name('Blinn-Phong'),
      'phong',
      () => settings({ phong: p.phong }),
      false,
    );
    phong.onChange(() => this.greyOut());
    add(shading.addColor(p, 'background', 1), 'background', () =>
      settings({ background: [p.background[0] ?? 0, p.background[1] ?? 0, p.background[2] ?? 0] }),
    );

    // The numeric settings arrive with hello's ranges (setRanges), each in its part's folder.
    this.parts.set('', sampling);
    this.parts.set('light_buffer', lb);
    this.parts.set('scattering', scattering);
    this.parts.set('shading', shading);

    for (const toggle of this.toggled) this.addToggle(toggle);

    const output = folder.addFolder('Image');
    add(
      output.add(p, 'encoding', offeredEncodings()),
      'encoding',
      () => ({ output: { encoding: p.encoding } }),
      false,
    ).onChange(() => this.greyOut());
    // A slider once hello's ranges give its ends (setRanges).
    add(
      output.add(p, 'jpeg_quality').step(1).name('JPEG quality'),
      'jpeg_quality',
      () => ({ output: { jpeg_quality: p.jpeg_quality } }),
      false,
    );
    add(
      output.add(p, 'h264_quality').step(1).name('H.264 rate factor'),
      'h264_quality',
      () => ({ output: { h264_quality: p.h264_quality } }),
      false,
    );
    const scale = output.add(p, 'scale', 0.25, 2, 0.05).name('pixels per device px');
    scale.domElement.dataset['control'] = 'scale';
    scale.onFinishChange(() => this.scaleChanged(p.scale));
    this.byKey.set('scale', scale);
    this.greyOut();
  }

  /** Wires a control: `patch` is what it sends, while it moves (`live`) and when it settles. */
  private add(c: Controller, key: string, patch: () => StatePatch, live = true): Controller {
    c.domElement.dataset['control'] = key;
    if (live) c.onChange(() => this.send(patch(), true));
    c.onFinishChange(() => this.send(patch(), false));
    c.enable(this.enabled);
    this.controllers.push(c);
    this.byKey.set(key, c);
    return c;
  }

  /** The server's maxima from `hello`. */
  setLimits(limits: Limits): void {
    this.slices.max(limits.max_slices);
    this.resolution.max(limits.max_light_resolution);
  }

  /**
   * The server's ranges from `hello`: a control for each numeric setting, spanning its range (a
   * later hello's ranges update them; a setting it no longer announces is hidden).
   */
  setRanges(ranges: SettingRanges): void {
    for (const control of this.ranged.values()) control.announced = false;
    for (const setting of methodControls(ranges)) {
      const known = this.ranged.get(setting.path);
      if (known) {
        known.announced = true;
        known.setting = setting;
        if (setting.kind === 'slider') known.controller.min(setting.min).max(setting.max);
        known.controller.domElement.title = setting.hint;
        continue;
      }
      const controller = this.addSetting(setting);
      this.ranged.set(setting.path, { setting, controller, announced: true });
    }
    for (const key of ['jpeg_quality', 'h264_quality'] as const) {
      const quality = ranges[`output/${key}`];
      if (quality) this.byKey.get(key)?.min(quality.min).max(quality.max);
    }
    this.showSettings();
    this.greyOut();
  }

  private addSetting(setting: SettingControl): Controller {
    const folder = this.folderOf(setting.part);
    const held = this.state ? settingValue(this.state.settings, setting.members) : undefined;
    this.values[setting.path] = held ?? setting.min;
    const value = () => settingPatch(setting.members, this.values[setting.path]!);
    const step = setting.integer ? 1 : undefined;
    const c =
      setting.kind === 'slider'
        ? folder.add(this.values, setting.path, setting.min, setting.max, step)
        : folder.add(this.values, setting.path).decimals(setting.decimals);
    c.name(setting.label);
    c.domElement.title = setting.hint;
    c.domElement.dataset['setting'] = setting.path;
    // A number field sends what was typed once it is complete; a slider while it moves.
    const name = setting.members[setting.members.length - 1]!;
    return this.add(c, name, value, setting.kind === 'slider');
  }

  private folderOf(part: string): GUI {
    let folder = this.parts.get(part);
    if (folder === undefined) {
      folder = this.folder.addFolder(labelOf(part));
      this.parts.set(part, folder);
    }
    return folder;
  }

  private addToggle(toggle: ToggleControl): void {
    const held = valueIn(this.state?.settings, toggle.members);
    this.toggles[toggle.path] = held ?? (toggle.choices ? toggle.choices[0]! : false);
    const folder = this.folderOf(toggle.part);
    const c = toggle.choices
      ? folder.add(this.toggles, toggle.path, [...toggle.choices])
      : folder.add(this.toggles, toggle.path);
    c.name(toggle.label);
    c.domElement.title = toggle.hint;
    c.domElement.dataset['setting'] = toggle.path;
    const name = toggle.members[toggle.members.length - 1]!;
    this.add(c, name, () => settingPatch(toggle.members, this.toggles[toggle.path]!), false);
  }

  /** The modes this server offers, with what each computes (its hello). */
  setModes(modes: ModeCapabilities[]): void {
    this.modes = new Map(modes.map((m) => [m.name, m]));
    if (modes.length > 0) {
      this.mode.options(modes.map((m) => m.name));
    }
    this.greyOut();
  }

  /** Shows the session's state. */
  update(state: State): void {
    const p = this.params;
    const s = state.settings;
    this.state = state;
    p.mode = s.mode;
    p.compositing = s.compositing;
    p.reconstruction = s.reconstruction ?? DEFAULT_SETTINGS.reconstruction;
    p.stage = s.stage;
    p.slices = s.light_buffer.slices;
    p.resolution = s.light_buffer.resolution;
    p.builder = s.light_buffer.builder;
    p.lookup = s.light_buffer.lookup;
    // A server older than these settings renders as a new session of this one starts.
    p.jitter = s.jitter ?? DEFAULT_SETTINGS.jitter;
    p.preintegration = s.preintegration ?? DEFAULT_SETTINGS.preintegration;
    p.empty_space_skipping = s.empty_space_skipping ?? DEFAULT_SETTINGS.empty_space_skipping;
    p.phong = s.phong;
    p.background = [...s.background];
    p.encoding = state.output.encoding;
    p.jpeg_quality = state.output.jpeg_quality;
    // A server older than H.264 frames has no rate factor: the default stays.
    p.h264_quality = state.output.h264_quality ?? DEFAULT_OUTPUT.h264_quality;
    for (const { setting } of this.ranged.values()) {
      const value = settingValue(s, setting.members);
      if (value !== undefined) this.values[setting.path] = value;
    }
    for (const toggle of this.toggled) {
      const value = valueIn(s, toggle.members);
      if (value !== undefined) this.toggles[toggle.path] = value;
    }
    this.showSettings();
    for (const c of this.controllers) c.updateDisplay();
    this.greyOut();
  }

  /**
   * A setting is shown where hello announces it and the session's state holds it (older servers
   * lack some).
   */
  private showSettings(): void {
    for (const { setting, controller, announced } of this.ranged.values()) {
      const held =
        this.state === null || settingValue(this.state.settings, setting.members) !== undefined;
      controller.show(announced && held);
    }
  }

  private greyOut(): void {
    const mode = this.modes.get(this.params.mode);
    this.mode.domElement.title = mode?.summary ?? '';
    const dim = (c: Controller | undefined, used: boolean): void => {
      c?.domElement.classList.toggle('unused', !used);
    };
    const phong = this.params.phong;
    for (const key of ['resolution', 'builder', 'lookup']) {
      dim(this.byKey.get(key), settingUsed(mode, 'light_buffer', key, phong));
    }
    // Half-angle slicing slices the volume without a light buffer.
    const slicing = mode?.technique === 'half_angle_slicing';
    dim(this.slices, settingUsed(mode, 'light_buffer', 'slices', phong) || slicing);
    dim(this.byKey.get('phong'), mode === undefined || mode.gradients === 'with_phong');
    for (const { setting, controller } of this.ranged.values()) {
      const name = setting.members[setting.members.length - 1]!;
      dim(controller, settingUsed(mode, setting.part, name, phong));
    }
    dim(this.byKey.get('jpeg_quality'), this.params.encoding === 'jpeg');
    dim(this.byKey.get('h264_quality'), this.params.encoding === 'h264');
  }

  setEnabled(enabled: boolean): void {
    this.enabled = enabled;
    for (const c of this.controllers) c.enable(enabled);
  }
}
