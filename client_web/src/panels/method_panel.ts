// Method and quality: the rendering mode (those the server's hello offers, with what each reads), light-buffer slices and
// resolution, builder, sample distance, compositing, compensation n, shell/cone parameters,
// shading, empty-space skipping, and the output encoding (JPEG quality or PNG). The sliders span
// the ranges the server's hello announces; the free-number fields take any number, and a bad one
// comes back as the server's error.

import type GUI from 'lil-gui';
import type { Controller } from 'lil-gui';
import {
  BUILDERS,
  LIGHT_LOOKUPS,
  COMPOSITINGS,
  DEFAULT_LIMITS,
  ENCODINGS,
  STAGES,
  type Limits,
  type ModeCapabilities,
  type SettingRanges,
  type State,
  type StatePatch,
} from '../protocol/messages';

export type PatchSink = (patch: StatePatch, interactive: boolean) => void;

/**
 * Which parameters matter for a mode, from what the server's hello says it computes (the others
 * are greyed out, still settable). Before hello, or for a mode hello did not list, all matter.
 */
const USES: Record<string, (mode: ModeCapabilities | undefined) => boolean> = {
  light_buffer: (m) => m === undefined || m.shadows === 'light_buffer',
  slices: (m) => m === undefined || m.shadows === 'light_buffer' || m.technique === 'half_angle_slicing',
  shell: (m) => m === undefined || m.scattering === 'shell',
  cone: (m) => m === undefined || m.scattering === 'cone',
  phong: (m) => m === undefined || m.gradients === 'with_phong',
};

/** The sliders whose ends are the server's ranges (hello.ranges), by control and setting path. */
const SLIDER_RANGES: Record<string, string> = {
  slab_samples: 'settings/light_buffer/slab_samples',
  early_termination: 'settings/early_termination',
  refinement_steps: 'settings/refinement_steps',
  shell_radius: 'settings/scattering/shell_radius',
  shell_rings: 'settings/scattering/shell_rings',
  shell_center_weight: 'settings/scattering/shell_center_weight',
  cone_angle: 'settings/scattering/cone_angle',
  cone_center_weight: 'settings/scattering/cone_center_weight',
  diffuse: 'settings/shading/diffuse',
  specular: 'settings/shading/specular',
  shininess: 'settings/shading/shininess',
};

export class MethodPanel {
  readonly params = {
    mode: 'sbrc' as string,
    compositing: 'alpha',
    stage: 'compute',
    slices: 128,
    resolution: 256,
    builder: 'multi_slice',
    compensation: 0,
    lookup: 'local',
    slab_samples: 0,
    sample_distance: 1 / 256,
    opacity_unit_distance: 1 / 256,
    early_termination: 0.99,
    phong: true,
    diffuse: 0.75,
    specular: 0.3,
    shininess: 32,
    shell_radius: 1 / 128,
    shell_rings: 1,
    shell_center_weight: 0.4,
    cone_angle: 30,
    cone_center_weight: 0.2,
    background: [0, 0, 0] as number[],
    encoding: 'jpeg',
    jpeg_quality: 85,
    frame_budget_ms: 0,
    jitter: false,
    refinement_steps: 8,
    empty_space_skipping: true,
    /** Client side: rendered pixels per device pixel. */
    scale: 1,
  };
  private readonly controllers: Controller[] = [];
  private readonly byKey = new Map<string, Controller>();
  private readonly mode: Controller;
  private modes = new Map<string, ModeCapabilities>();
  private readonly slices: Controller;
  private readonly resolution: Controller;
  private readonly budget: Controller;

  constructor(
    folder: GUI,
    private readonly send: PatchSink,
    private readonly scaleChanged: (scale: number) => void,
  ) {
    const p = this.params;
    const add = (c: Controller, key: string, patch: () => StatePatch, live = true): Controller => {
      c.domElement.dataset['control'] = key;
      if (live) c.onChange(() => this.send(patch(), true));
      c.onFinishChange(() => this.send(patch(), false));
      this.controllers.push(c);
      this.byKey.set(key, c);
      return c;
    };
    const settings = (s: StatePatch['settings']): StatePatch => ({ settings: s });

    // The server's modes arrive with its hello (setModes).
    this.mode = add(folder.add(p, 'mode', [p.mode]), 'mode', () => settings({ mode: p.mode }), false);
    this.mode.onChange(() => this.greyOut());
    add(folder.add(p, 'compositing', [...COMPOSITINGS]), 'compositing', () =>
      settings({ compositing: p.compositing as 'alpha' }), false);
    add(folder.add(p, 'stage', [...STAGES]).name('ray caster stage'), 'stage', () =>
      settings({ stage: p.stage as 'compute' }), false);

    const lb = folder.addFolder('Light buffer & slices');
    this.slices = add(lb.add(p, 'slices', 1, DEFAULT_LIMITS.max_slices, 1), 'slices', () =>
      settings({ light_buffer: { slices: p.slices } }));
    this.resolution = add(lb.add(p, 'resolution', 1, DEFAULT_LIMITS.max_light_resolution, 1).name('resolution R'),
      'resolution', () => settings({ light_buffer: { resolution: p.resolution } }));
    add(lb.add(p, 'builder', [...BUILDERS]), 'builder', () =>
      settings({ light_buffer: { builder: p.builder as 'per_slice' } }), false);
    // A free number field: the server checks the range (0..1000).
    add(lb.add(p, 'compensation').name('compensation n'), 'compensation', () =>
      settings({ light_buffer: { compensation: p.compensation } }), false);
    add(lb.add(p, 'lookup', [...LIGHT_LOOKUPS]).name('light lookup'), 'lookup', () =>
      settings({ light_buffer: { lookup: p.lookup as 'local' } }), false);
    add(lb.add(p, 'slab_samples').step(1).name('slab samples (0 = per voxel)'), 'slab_samples', () =>
      settings({ light_buffer: { slab_samples: p.slab_samples } }));

    const sampling = folder.addFolder('Sampling');
    // Free number fields: the server checks the ranges and says what is wrong.
    add(sampling.add(p, 'sample_distance').name('sample distance').decimals(6), 'sample_distance',
      () => settings({ sample_distance: p.sample_distance }), false);
    add(sampling.add(p, 'opacity_unit_distance').name('opacity unit dist.').decimals(6),
      'opacity_unit_distance', () => settings({ opacity_unit_distance: p.opacity_unit_distance }), false);
    add(sampling.add(p, 'early_termination').step(0.01).name('early termination'),
      'early_termination', () => settings({ early_termination: p.early_termination }));
    add(sampling.add(p, 'jitter').name('jittered samples'), 'jitter', () =>
      settings({ jitter: p.jitter }), false);
    // Progressive stills: the server refines a still frame this many times (0: off).
    add(sampling.add(p, 'refinement_steps').step(1).name('refinement steps (0 off)'), 'refinement_steps',
      () => settings({ refinement_steps: p.refinement_steps }), false);
    // Skips the volume's empty bricks while marching: faster, the same image.
    add(sampling.add(p, 'empty_space_skipping').name('empty-space skipping'), 'empty_space_skipping', () =>
      settings({ empty_space_skipping: p.empty_space_skipping }), false);
    // The server picks mode and quality to fit this frame time (0: as set); newer servers only.
    this.budget = add(sampling.add(p, 'frame_budget_ms').name('frame budget ms (0 off)'),
      'frame_budget_ms', () => settings({ frame_budget_ms: p.frame_budget_ms }), false);

    const scattering = folder.addFolder('Shell & cone (sbrc_shell, sbrc_cone)');
    scattering.close();
    add(scattering.add(p, 'shell_radius').step(0.0001).name('shell radius'), 'shell_radius',
      () => settings({ scattering: { shell_radius: p.shell_radius } }));
    add(scattering.add(p, 'shell_rings').step(1).name('shell rings'), 'shell_rings', () =>
      settings({ scattering: { shell_rings: p.shell_rings } }));
    add(scattering.add(p, 'shell_center_weight').step(0.01).name('shell centre weight'),
      'shell_center_weight', () => settings({ scattering: { shell_center_weight: p.shell_center_weight } }));
    add(scattering.add(p, 'cone_angle').step(0.1).name('cone angle °'), 'cone_angle', () =>
      settings({ scattering: { cone_angle: p.cone_angle } }));
    add(scattering.add(p, 'cone_center_weight').step(0.01).name('cone centre weight'),
      'cone_center_weight', () => settings({ scattering: { cone_center_weight: p.cone_center_weight } }));

    const shading = folder.addFolder('Shading');
    shading.close();
    add(shading.add(p, 'phong').name('Blinn-Phong'), 'phong', () => settings({ phong: p.phong }), false);
    add(shading.add(p, 'diffuse').step(0.01), 'diffuse', () => settings({ shading: { diffuse: p.diffuse } }));
    add(shading.add(p, 'specular').step(0.01), 'specular', () =>
      settings({ shading: { specular: p.specular } }));
    add(shading.add(p, 'shininess').step(1), 'shininess', () =>
      settings({ shading: { shininess: p.shininess } }));
    add(shading.addColor(p, 'background', 1), 'background', () =>
      settings({ background: [p.background[0] ?? 0, p.background[1] ?? 0, p.background[2] ?? 0] }));

    const output = folder.addFolder('Image');
    add(output.add(p, 'encoding', [...ENCODINGS]), 'encoding', () =>
      ({ output: { encoding: p.encoding as 'jpeg' } }), false).onChange(() => this.greyOut());
    add(output.add(p, 'jpeg_quality', 1, 100, 1).name('JPEG quality'), 'jpeg_quality', () =>
      ({ output: { jpeg_quality: p.jpeg_quality } }), false);
    const scale = output.add(p, 'scale', 0.25, 2, 0.05).name('pixels per device px');
    scale.domElement.dataset['control'] = 'scale';
    scale.onFinishChange(() => this.scaleChanged(p.scale));
    this.byKey.set('scale', scale);
    this.greyOut();
  }

  /** The server's maxima from `hello`. */
  setLimits(limits: Limits): void {
    this.slices.max(limits.max_slices);
    this.resolution.max(limits.max_light_resolution);
  }

  /** The server's ranges from `hello`: the sliders span them (until then, number fields). */
  setRanges(ranges: SettingRanges): void {
    for (const [key, path] of Object.entries(SLIDER_RANGES)) {
      const range = ranges[path];
      if (range !== undefined) this.byKey.get(key)?.min(range.min).max(range.max);
    }
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
    p.mode = s.mode;
    p.compositing = s.compositing;
    p.stage = s.stage;
    p.slices = s.light_buffer.slices;
    p.resolution = s.light_buffer.resolution;
    p.builder = s.light_buffer.builder;
    p.compensation = s.light_buffer.compensation;
    p.lookup = s.light_buffer.lookup;
    p.slab_samples = s.light_buffer.slab_samples;
    p.sample_distance = s.sample_distance;
    p.opacity_unit_distance = s.opacity_unit_distance;
    p.early_termination = s.early_termination;
    p.frame_budget_ms = s.frame_budget_ms ?? 0;
    p.jitter = s.jitter ?? false;
    p.refinement_steps = s.refinement_steps ?? 0;
    p.empty_space_skipping = s.empty_space_skipping ?? true;
    this.budget.show(s.frame_budget_ms !== undefined);
    p.phong = s.phong;
    p.diffuse = s.shading.diffuse;
    p.specular = s.shading.specular;
    p.shininess = s.shading.shininess;
    Object.assign(p, s.scattering);
    p.background = [...s.background];
    p.encoding = state.output.encoding;
    p.jpeg_quality = state.output.jpeg_quality;
    for (const c of this.controllers) c.updateDisplay();
    this.greyOut();
  }

  private greyOut(): void {
    const mode = this.modes.get(this.params.mode);
    this.mode.domElement.title = mode?.summary ?? '';
    const dim = (key: string, used: boolean): void => {
      this.byKey.get(key)?.domElement.classList.toggle('unused', !used);
    };
    for (const key of ['resolution', 'builder', 'compensation', 'lookup', 'slab_samples']) dim(key, USES['light_buffer']!(mode));
    dim('slices', USES['slices']!(mode));
    for (const key of ['shell_radius', 'shell_rings', 'shell_center_weight']) dim(key, USES['shell']!(mode));
    for (const key of ['cone_angle', 'cone_center_weight']) dim(key, USES['cone']!(mode));
    dim('phong', USES['phong']!(mode));
    dim('jpeg_quality', this.params.encoding === 'jpeg');
  }

  setEnabled(enabled: boolean): void {
    for (const c of this.controllers) c.enable(enabled);
  }
}
