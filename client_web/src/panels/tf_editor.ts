// Transfer-function editor: the volume's histogram behind the opacity curve, whose control points
// are dragged (click on empty space adds one, double-click or right-click removes one, Delete
// removes the selected one), and a colour bar whose stops are dragged likewise (double-click a
// stop to pick its colour). The presets are the server's (its hello, through the model), the
// colour maps tf_model.ts's and the presets' own. Applied live:
// interactive frames while dragging, a still frame on release.

import type GUI from 'lil-gui';
import type { Controller } from 'lil-gui';
import { histogramCurve, TfModel } from './tf_model';
import {
  HOUNSFIELD,
  type Preset,
  type Rgb,
  type TransferFunctionPoints,
} from '../protocol/messages';

/**
 * The names the preset list offers, in the server's order; for a volume in Hounsfield units those
 * in Hounsfield units (the CT presets) first.
 */
export function presetsFor(
  presets: readonly TransferFunctionPoints[],
  hounsfield: boolean,
): Preset[] {
  const names = presets.map((p) => p.name);
  if (!hounsfield) return names;
  const inHu = presets.filter((p) => p.space === HOUNSFIELD).map((p) => p.name);
  return [...inHu, ...names.filter((name) => !inHu.includes(name))];
}

const HEIGHT = 120; // CSS pixels
const BAR_HEIGHT = 20;
const PICK_PX = 9;

function hex(rgb: Rgb): string {
  return `#${rgb
    .map((c) =>
      Math.round(c * 255)
        .toString(16)
        .padStart(2, '0'),
    )
    .join('')}`;
}

function fromHex(text: string): Rgb {
  const n = parseInt(text.slice(1), 16);
  return [((n >> 16) & 255) / 255, ((n >> 8) & 255) / 255, (n & 255) / 255];
}

function css(rgb: Rgb, alpha = 1): string {
  const [r, g, b] = rgb.map((c) => Math.round(c * 255));
  return `rgba(${r},${g},${b},${alpha})`;
}

export class TfEditor {
  private readonly curve: HTMLCanvasElement;
  private readonly bar: HTMLCanvasElement;
  private readonly picker: HTMLInputElement;
  private histogram: number[] = [];
  private enabled = true;
  private selected: { kind: 'opacity' | 'color'; index: number } | null = null;
  private readonly params = { preset: 'custom', colormap: '(keep)' };
  private readonly controllers: Controller[] = [];
  private presetList!: Controller;
  private hounsfield = false;

  constructor(
    private readonly folder: GUI,
    readonly model: TfModel,
    private readonly send: (interactive: boolean) => void,
  ) {
    const root = document.createElement('div');
    root.className = 'tf-editor';
    this.curve = document.createElement('canvas');
    this.curve.className = 'tf-curve';
    this.curve.tabIndex = 0;
    this.curve.dataset['control'] = 'tf-curve';
    this.curve.title = 'opacity: drag points; click to add; double-click or right-click to remove';
    this.bar = document.createElement('canvas');
    this.bar.className = 'tf-bar';
    this.bar.dataset['control'] = 'tf-bar';
    this.bar.title =
      'colour: drag stops; click to add; double-click to pick a colour; right-click to remove';
    this.picker = document.createElement('input');
    this.picker.type = 'color';
    this.picker.className = 'tf-picker';
    const hint = document.createElement('div');
    hint.className = 'hint';
    hint.textContent = 'histogram (log) · opacity points · colour stops';
    root.append(this.curve, this.bar, this.picker, hint);
    folder.$children.appendChild(root);

    this.buildLists(folder, false);

    this.model.onChange(() => {
      const name = this.presetName();
      if (this.params.preset !== name) {
        this.params.preset = name;
        this.presetList.updateDisplay();
      }
      this.draw();
    });
    this.attachCurve();
    this.attachBar();
    new ResizeObserver(() => this.draw()).observe(root);
  }

  /**
   * The preset and colour-map lists, in that order; the presets offered depend on the volume (the
   * CT presets, in Hounsfield units, first for a volume whose values are HU).
   */
  private buildLists(folder: GUI, hounsfield: boolean): void {
    for (const c of this.controllers) c.destroy();
    this.controllers.length = 0;
    this.hounsfield = hounsfield;
    const preset = folder
      .add(this.params, 'preset', presetsFor(this.model.terms.presets, hounsfield))
      .name('preset');
    preset.domElement.dataset['control'] = 'tf-preset';
    preset.onChange((name: string) => {
      this.model.loadPreset(name as Preset);
      this.send(false);
    });
    const colormap = folder.add(this.params, 'colormap', [
      '(keep)',
      ...Object.keys(this.model.colorMaps),
    ]);
    colormap.name('colour map');
    colormap.domElement.dataset['control'] = 'tf-colormap';
    colormap.onChange((name: string) => {
      if (name === '(keep)') return;
      this.model.applyColorMap(name);
      this.send(false);
    });
    this.presetList = preset;
    this.controllers.push(preset, colormap);
    for (const c of this.controllers) c.enable(this.enabled);
  }

  /** The model's preset of the model's name, else 'custom'. */
  private presetName(): string {
    return this.model.preset(this.model.name) ? this.model.name : 'custom';
  }

  /** After a volume opened: whether its values are Hounsfield units. */
  setHounsfield(hounsfield: boolean): void {
    if (hounsfield !== this.hounsfield) this.buildLists(this.folder, hounsfield);
  }

  /** After the server's hello: its presets (the model's terms) fill the lists. */
  termsChanged(): void {
    this.buildLists(this.folder, this.hounsfield);
    this.refresh();
  }

  setHistogram(histogram: number[]): void {
    this.histogram = histogramCurve(histogram);
    this.draw();
  }

  /** After the model was loaded from the session's state. */
  refresh(): void {
    this.params.preset = this.presetName();
    this.params.colormap = '(keep)';
    for (const c of this.controllers) c.updateDisplay();
    this.draw();
  }

  setEnabled(enabled: boolean): void {
    this.enabled = enabled;
    for (const c of this.controllers) c.enable(enabled);
    this.curve.classList.toggle('disabled', !enabled);
    this.bar.classList.toggle('disabled', !enabled);
  }

  private position(
    canvas: HTMLCanvasElement,
    e: PointerEvent | MouseEvent,
  ): { x: number; y: number } {
    const rect = canvas.getBoundingClientRect();
    return {
      x: Math.min(1, Math.max(0, (e.clientX - rect.left) / Math.max(1, rect.width))),
      y: Math.min(1, Math.max(0, 1 - (e.clientY - rect.top) / Math.max(1, rect.height))),
    };
  }

  private attachCurve(): void {
    const c = this.curve;
    let dragging = -1;
    const pick = (e: MouseEvent): number => {
      const { x, y } = this.position(c, e);
      const rect = c.getBoundingClientRect();
      return this.model.pickOpacity(
        x,
        y,
        PICK_PX / Math.max(1, rect.width),
        rect.height / Math.max(1, rect.width),
      );
    };
    c.addEventListener('contextmenu', (e) => e.preventDefault());
    c.addEventListener('pointerdown', (e) => {
      if (!this.enabled) return;
      c.focus();
      let i = pick(e);
      if (e.button === 2) {
        if (i >= 0) {
          this.model.removeOpacity(i);
          this.selected = null;
          this.send(false);
        }
        return;
      }
      if (i < 0) {
        const { x, y } = this.position(c, e);
        i = this.model.addOpacity(x, y);
        if (i < 0) return;
        this.send(true);
      }
      dragging = i;
      this.selected = { kind: 'opacity', index: i };
      c.setPointerCapture(e.pointerId);
      this.draw();
    });
    c.addEventListener('pointermove', (e) => {
      if (dragging < 0) return;
      const { x, y } = this.position(c, e);
      this.model.moveOpacity(dragging, x, y);
      this.send(true);
    });
    const up = (): void => {
      if (dragging < 0) return;
      dragging = -1;
      this.send(false);
    };
    c.addEventListener('pointerup', up);
    c.addEventListener('pointercancel', up);
    c.addEventListener('dblclick', (e) => {
      if (!this.enabled) return;
      const i = pick(e);
      if (i >= 0) {
        this.model.removeOpacity(i);
        this.selected = null;
        this.send(false);
      }
    });
    c.addEventListener('keydown', (e) => {
      if (!this.enabled || !this.selected) return;
      if (e.key === 'Delete' || e.key === 'Backspace') {
        if (this.selected.kind === 'opacity') this.model.removeOpacity(this.selected.index);
        else this.model.removeColor(this.selected.index);
        this.selected = null;
        this.send(false);
        e.preventDefault();
      }
    });
  }

  private attachBar(): void {
    const b = this.bar;
    let dragging = -1;
    let editing = -1;
    const pick = (e: MouseEvent): number => {
      const rect = b.getBoundingClientRect();
      return this.model.pickColor(this.position(b, e).x, PICK_PX / Math.max(1, rect.width));
    };
    b.addEventListener('contextmenu', (e) => e.preventDefault());
    b.addEventListener('pointerdown', (e) => {
      if (!this.enabled) return;
      let i = pick(e);
      if (e.button === 2) {
        if (i >= 0 && this.model.colors.length > 1) {
          this.model.removeColor(i);
          this.send(false);
        }
        return;
      }
      if (i < 0) {
        i = this.model.addColor(this.position(b, e).x);
        if (i < 0) return;
        this.send(false);
      }
      dragging = i;
      this.selected = { kind: 'color', index: i };
      b.setPointerCapture(e.pointerId);
      this.draw();
    });
    b.addEventListener('pointermove', (e) => {
      if (dragging < 0) return;
      this.model.moveColor(dragging, this.position(b, e).x);
      this.send(true);
    });
    const up = (): void => {
      if (dragging < 0) return;
      dragging = -1;
      this.send(false);
    };
    b.addEventListener('pointerup', up);
    b.addEventListener('pointercancel', up);
    b.addEventListener('dblclick', (e) => {
      if (!this.enabled) return;
      editing = pick(e);
      const point = this.model.colors[editing];
      if (!point) return;
      this.picker.value = hex(point.rgb);
      this.picker.click();
    });
    this.picker.addEventListener('input', () => {
      if (editing < 0) return;
      this.model.setColor(editing, fromHex(this.picker.value));
      this.send(true);
    });
    this.picker.addEventListener('change', () => {
      if (editing < 0) return;
      this.model.setColor(editing, fromHex(this.picker.value));
      this.send(false);
    });
  }

  private fit(canvas: HTMLCanvasElement, cssHeight: number): CanvasRenderingContext2D | null {
    const dpr = window.devicePixelRatio || 1;
    const width = Math.max(1, Math.round((canvas.clientWidth || 240) * dpr));
    const height = Math.round(cssHeight * dpr);
    if (canvas.width !== width || canvas.height !== height) {
      canvas.width = width;
      canvas.height = height;
    }
    return canvas.getContext('2d');
  }

  draw(): void {
    const ctx = this.fit(this.curve, HEIGHT);
    const bar = this.fit(this.bar, BAR_HEIGHT);
    if (!ctx || !bar) return;
    const dpr = window.devicePixelRatio || 1;
    const { width: w, height: h } = this.curve;
    ctx.fillStyle = '#161616';
    ctx.fillRect(0, 0, w, h);
    // Histogram.
    const bins = this.histogram.length;
    if (bins > 0) {
      ctx.fillStyle = '#4a4a4a';
      for (let i = 0; i < bins; ++i) {
        const bh = (this.histogram[i] ?? 0) * h;
        const x0 = Math.floor((i / bins) * w);
        const x1 = Math.ceil(((i + 1) / bins) * w);
        ctx.fillRect(x0, h - bh, Math.max(1, x1 - x0), bh);
      }
    }
    // Opacity area coloured by the colour map.
    for (let x = 0; x < w; x += 2) {
      const t = x / Math.max(1, w - 1);
      const a = this.model.opacityAt(t);
      ctx.fillStyle = css(this.model.colorAt(t), 0.55);
      ctx.fillRect(x, h - a * h, 2, a * h);
    }
    // Opacity curve and points.
    const points = this.model.opacities;
    ctx.strokeStyle = '#f0f0f0';
    ctx.lineWidth = 1.5 * dpr;
    ctx.beginPath();
    const first = points[0];
    if (first) ctx.moveTo(0, h - first.alpha * h);
    for (const p of points) ctx.lineTo(p.x * w, h - p.alpha * h);
    const last = points[points.length - 1];
    if (last) ctx.lineTo(w, h - last.alpha * h);
    ctx.stroke();
    points.forEach((p, i) => {
      const selected = this.selected?.kind === 'opacity' && this.selected.index === i;
      ctx.fillStyle = selected ? '#ffcc33' : '#ffffff';
      ctx.strokeStyle = '#000';
      ctx.beginPath();
      ctx.arc(p.x * w, h - p.alpha * h, (selected ? 5 : 4) * dpr, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
    });
    // Colour bar with its stops.
    const bw = this.bar.width;
    const bh = this.bar.height;
    const gradient = bar.createLinearGradient(0, 0, bw, 0);
    const colors = this.model.colors;
    if (colors.length === 0) gradient.addColorStop(0, '#000');
    for (const c of colors) gradient.addColorStop(c.x, css(c.rgb));
    bar.fillStyle = gradient;
    bar.fillRect(0, 0, bw, bh);
    colors.forEach((c, i) => {
      const selected = this.selected?.kind === 'color' && this.selected.index === i;
      const x = c.x * bw;
      bar.fillStyle = css(c.rgb);
      bar.strokeStyle = selected ? '#ffcc33' : '#000';
      bar.lineWidth = 2 * dpr;
      bar.beginPath();
      bar.moveTo(x, bh * 0.35);
      bar.lineTo(x - 5 * dpr, bh);
      bar.lineTo(x + 5 * dpr, bh);
      bar.closePath();
      bar.fill();
      bar.stroke();
    });
  }
}
