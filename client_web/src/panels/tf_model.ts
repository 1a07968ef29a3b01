// The transfer-function editor's model: opacity and colour control points over normalised value
// positions [0, 1], the server's presets (from its hello), colour maps and the histogram curve. No DOM: the editor
// (tf_editor.ts) draws it and turns pointer events into these operations; tests drive it directly.

import { UNNAMED_TRANSFER_FUNCTION } from '../protocol/generated/server_tables';
import {
  HOUNSFIELD,
  NORMALIZED,
  type ColorPoint,
  type HelloMessage,
  type OpacityPoint,
  type PositionSpace,
  type Preset,
  type Rgb,
  type TransferFunctionPatch,
  type TransferFunctionPoints,
} from '../protocol/messages';

/**
 * What the server says about transfer functions (its hello): its presets, with the points each
 * sets, in the shape a state holds them (the CT presets in Hounsfield units); the range over which
 * Hounsfield positions are read on a volume whose values are not marked HU; and how many points a
 * list may hold. The client keeps no copy of its own.
 */
export interface TfTerms {
  presets: readonly TransferFunctionPoints[];
  nominalCtRange: readonly [number, number];
  maxPoints: number;
}

export function tfTerms(hello: HelloMessage): TfTerms {
  return {
    presets: hello.presets,
    nominalCtRange: hello.nominal_ct_range,
    maxPoints: hello.limits.max_transfer_function_points,
  };
}

/** Until a server's hello arrives: no presets, and no points may be added. */
const NO_TERMS: TfTerms = { presets: [], nominalCtRange: [0, 1], maxPoints: 0 };

/** Colour maps that replace only the colour points. */
export const COLOR_MAPS: Record<string, ColorPoint[]> = {
  grey: [
    { x: 0, rgb: [0, 0, 0] },
    { x: 1, rgb: [1, 1, 1] },
  ],
  bone: [
    { x: 0, rgb: [0.5, 0.3, 0.2] },
    { x: 0.3, rgb: [0.9, 0.8, 0.65] },
    { x: 0.5, rgb: [1, 0.98, 0.92] },
    { x: 1, rgb: [1, 1, 1] },
  ],
  hot: [
    { x: 0, rgb: [0.05, 0, 0] },
    { x: 0.35, rgb: [0.9, 0.1, 0] },
    { x: 0.7, rgb: [1, 0.85, 0] },
    { x: 1, rgb: [1, 1, 1] },
  ],
  cool_warm: [
    { x: 0, rgb: [0.23, 0.3, 0.75] },
    { x: 0.5, rgb: [0.87, 0.87, 0.87] },
    { x: 1, rgb: [0.71, 0.02, 0.15] },
  ],
  viridis: [
    { x: 0, rgb: [0.267, 0.005, 0.329] },
    { x: 0.25, rgb: [0.229, 0.322, 0.546] },
    { x: 0.5, rgb: [0.128, 0.567, 0.551] },
    { x: 0.75, rgb: [0.369, 0.789, 0.383] },
    { x: 1, rgb: [0.993, 0.906, 0.144] },
  ],
};

/**
 * The colour maps the editor offers: the client's own and the colours of each of the server's
 * presets whose positions are normalised (`mri_skin`'s skin tones), under the preset's name.
 */
export function colorMaps(
  presets: readonly TransferFunctionPoints[],
): Record<string, ColorPoint[]> {
  const maps: Record<string, ColorPoint[]> = { ...COLOR_MAPS };
  for (const preset of presets) {
    if (preset.space === NORMALIZED && !(preset.name in maps)) maps[preset.name] = preset.colors;
  }
  return maps;
}

function clamp(v: number, lo: number, hi: number): number {
  return Math.min(hi, Math.max(lo, v));
}

function lerp(a: number, b: number, t: number): number {
  return a + (b - a) * t;
}

/** Piecewise-linear value at x over points sorted by x; constant beyond the ends, as the server. */
function interpolate<P extends { x: number }>(
  points: readonly P[],
  x: number,
  get: (p: P) => number,
  empty: number,
): number {
  const first = points[0];
  const last = points[points.length - 1];
  if (!first || !last) return empty;
  if (x <= first.x) return get(first);
  if (x >= last.x) return get(last);
  for (let i = 1; i < points.length; ++i) {
    const b = points[i]!;
    const a = points[i - 1]!;
    if (x <= b.x) {
      const span = b.x - a.x;
      return span > 0 ? lerp(get(a), get(b), (x - a.x) / span) : get(b);
    }
  }
  return get(last);
}

export type Listener = () => void;

/** The values a table is read over: the volume's range, and whether they are Hounsfield units. */
export interface ValueDomain {
  min: number;
  max: number;
  hounsfield: boolean;
}

/**
 * A position in `space` as a fraction of the volume's range, as the server's bake reads it: a
 * Hounsfield position over the volume's range when its values are HU, else over
 * `nominalCtRange` (the server's, from hello).
 */
export function normalizedPosition(
  x: number,
  space: PositionSpace | undefined,
  domain: ValueDomain,
  nominalCtRange: readonly [number, number],
): number {
  if (space !== HOUNSFIELD) return x;
  const [min, max] = domain.hounsfield ? [domain.min, domain.max] : nominalCtRange;
  const width = max - min;
  return width > 0 ? (x - min) / width : 0;
}

/**
 * Opacity and colour control points; every operation keeps positions within [0, 1] and
 * non-decreasing (a moved point stays between its neighbours), and the values within [0, 1].
 */
export class TfModel {
  name = UNNAMED_TRANSFER_FUNCTION;
  colors: ColorPoint[] = [];
  opacities: OpacityPoint[] = [];
  /** The open volume's values, for points given in Hounsfield units. */
  domain: ValueDomain = { min: 0, max: 1, hounsfield: false };
  /** The server's presets, nominal CT range and point limit (setTerms, from its hello). */
  terms: TfTerms = NO_TERMS;
  private listeners: Listener[] = [];

  constructor(
    terms?: TfTerms,
    points?: { name?: string; colors: ColorPoint[]; opacities: OpacityPoint[] },
  ) {
    if (terms) this.terms = terms;
    if (points) this.load(points, false);
  }

  /** The colour maps offered with the server's presets (colorMaps). */
  get colorMaps(): Record<string, ColorPoint[]> {
    return colorMaps(this.terms.presets);
  }

  /** The server's preset of that name, as a state holds it; undefined when it has none. */
  preset(name: string): TransferFunctionPoints | undefined {
    const found = this.terms.presets.find((p) => p.name === name);
    return found ? structuredClone(found) : undefined;
  }

  onChange(listener: Listener): void {
    this.listeners.push(listener);
  }

  private changed(): void {
    for (const l of this.listeners) l();
  }

  /**
   * Replaces every point (from the server's state or a preset, within its point limit); sorted
   * and clamped. Points in Hounsfield units are placed on the open volume's range (`domain`).
   */
  load(
    points: {
      name?: string;
      space?: PositionSpace;
      colors: ColorPoint[];
      opacities: OpacityPoint[];
    },
    notify = true,
  ): void {
    const at = (x: number) =>
      clamp(normalizedPosition(x, points.space, this.domain, this.terms.nominalCtRange), 0, 1);
    this.name = points.name ?? UNNAMED_TRANSFER_FUNCTION;
    this.colors = points.colors
      .map((p) => ({ x: at(p.x), rgb: p.rgb.map((c) => clamp(c, 0, 1)) as Rgb }))
      .sort((a, b) => a.x - b.x);
    this.opacities = points.opacities
      .map((p) => ({ x: at(p.x), alpha: clamp(p.alpha, 0, 1) }))
      .sort((a, b) => a.x - b.x);
    if (notify) this.changed();
  }

  /** Loads the server's preset of that name (hello's presets). */
  loadPreset(name: Preset): void {
    const preset = this.preset(name);
    if (!preset) throw new Error(`the server has no preset "${name}"`);
    this.load(preset);
  }

  /** Replaces the colours by a colour map, keeping the opacities. */
  applyColorMap(name: string): void {
    const map = this.colorMaps[name];
    if (!map) throw new Error(`unknown colour map "${name}"`);
    this.colors = structuredClone(map);
    this.name = UNNAMED_TRANSFER_FUNCTION;
    this.changed();
  }

  /** Inserts an opacity point in order; returns its index, or -1 when the list is full. */
  addOpacity(x: number, alpha: number): number {
    if (this.opacities.length >= this.terms.maxPoints) return -1;
    const point = { x: clamp(x, 0, 1), alpha: clamp(alpha, 0, 1) };
    let i = this.opacities.findIndex((p) => p.x > point.x);
    if (i < 0) i = this.opacities.length;
    this.opacities.splice(i, 0, point);
    this.name = UNNAMED_TRANSFER_FUNCTION;
    this.changed();
    return i;
  }

  /** Moves opacity point i, kept between its neighbours' positions. */
  moveOpacity(i: number, x: number, alpha: number): void {
    const p = this.opacities[i];
    if (!p) return;
    const lo = this.opacities[i - 1]?.x ?? 0;
    const hi = this.opacities[i + 1]?.x ?? 1;
    p.x = clamp(x, lo, hi);
    p.alpha = clamp(alpha, 0, 1);
    this.name = UNNAMED_TRANSFER_FUNCTION;
    this.changed();
  }

  removeOpacity(i: number): void {
    if (i < 0 || i >= this.opacities.length) return;
    this.opacities.splice(i, 1);
    this.name = UNNAMED_TRANSFER_FUNCTION;
    this.changed();
  }

  addColor(x: number, rgb?: Rgb): number {
    if (this.colors.length >= this.terms.maxPoints) return -1;
    const at = clamp(x, 0, 1);
    const point = { x: at, rgb: rgb ?? this.colorAt(at) };
    let i = this.colors.findIndex((p) => p.x > at);
    if (i < 0) i = this.colors.length;
    this.colors.splice(i, 0, point);
    this.name = UNNAMED_TRANSFER_FUNCTION;
    this.changed();
    return i;
  }

  moveColor(i: number, x: number): void {
    const p = this.colors[i];
    if (!p) return;
    p.x = clamp(x, this.colors[i - 1]?.x ?? 0, this.colors[i + 1]?.x ?? 1);
    this.name = UNNAMED_TRANSFER_FUNCTION;
    this.changed();
  }

  setColor(i: number, rgb: Rgb): void {
    const p = this.colors[i];
    if (!p) return;
    p.rgb = rgb.map((c) => clamp(c, 0, 1)) as Rgb;
    this.name = UNNAMED_TRANSFER_FUNCTION;
    this.changed();
  }

  removeColor(i: number): void {
    if (i < 0 || i >= this.colors.length) return;
    this.colors.splice(i, 1);
    this.name = UNNAMED_TRANSFER_FUNCTION;
    this.changed();
  }

  opacityAt(x: number): number {
    return interpolate(this.opacities, x, (p) => p.alpha, 0);
  }

  colorAt(x: number): Rgb {
    return [0, 1, 2].map((c) => interpolate(this.colors, x, (p) => p.rgb[c]!, 0)) as Rgb;
  }

  /**
   * The index of the opacity point nearest to (x, alpha) within `radius` (in the same units,
   * alpha scaled by `aspect` = height/width of the editor), or -1.
   */
  pickOpacity(x: number, alpha: number, radius: number, aspect = 1): number {
    let best = -1;
    let bestDistance = radius;
    this.opacities.forEach((p, i) => {
      const d = Math.hypot(p.x - x, (p.alpha - alpha) * aspect);
      if (d <= bestDistance) {
        best = i;
        bestDistance = d;
      }
    });
    return best;
  }

  pickColor(x: number, radius: number): number {
    let best = -1;
    let bestDistance = radius;
    this.colors.forEach((p, i) => {
      const d = Math.abs(p.x - x);
      if (d <= bestDistance) {
        best = i;
        bestDistance = d;
      }
    });
    return best;
  }

  /** What `set` sends: the whole transfer function as points. */
  toProtocol(): TransferFunctionPatch & TransferFunctionPoints {
    return {
      name: this.name,
      space: NORMALIZED,
      colors: structuredClone(this.colors),
      opacities: structuredClone(this.opacities),
    };
  }
}

/**
 * The histogram as heights in [0, 1] for drawing: log(1 + count), normalised by the largest bin
 * after skipping the `skip` largest outliers (usually the background bin dwarfs everything).
 */
export function histogramCurve(histogram: readonly number[], skip = 1): number[] {
  if (histogram.length === 0) return [];
  const logs = histogram.map((c) => Math.log1p(Math.max(0, c)));
  const sorted = [...logs].sort((a, b) => b - a);
  const top = sorted[Math.min(skip, sorted.length - 1)] ?? 0;
  return logs.map((l) => (top > 0 ? Math.min(1, l / top) : 0));
}
