// Labels: the label map (a segmentation, an atlas) the session draws inside its volume. A choice
// of the listed label maps adds one (or replaces the one drawn), Remove takes it away; the list of
// its labels (swatch, name, id, voxels) filters by a search, and each label is shown or hidden,
// shown alone, or (selected) made more or less opaque; show all, hide all, the blend of the labels'
// colours, and the map drawn by itself (its visible labels as lit surfaces, the scan not drawn). Plain DOM rows, built once per map: an atlas has hundreds of labels. The rows show the
// state the server answers with; a viewer sees them read-only.

import type GUI from 'lil-gui';
import { namesTheLabels, type DrawnLabels } from '../protocol/connection';
import type {
  LabelsState,
  LabelStyle,
  Rgb,
  State,
  StatePatch,
  VolumeSummary,
} from '../protocol/messages';

/** One label as the panel lists it. */
export interface LabelRow {
  id: number;
  name: string;
  /** Whether the name is the map's own, not its id alone (the names not known: an older server). */
  named: boolean;
  color: Rgb;
  opacity: number;
  visible: boolean;
  /** How many voxels the map gives it; null when its list is not known. */
  voxels: number | null;
}

/**
 * The labels a state styles, in the order the map lists them, each with its name and voxels; by
 * id where `drawn` is not the list of the same labels (another map's).
 */
export function labelRows(labels: LabelsState | undefined, drawn?: DrawnLabels): LabelRow[] {
  if (!labels) return [];
  const named = drawn !== undefined && namesTheLabels(drawn.labels, labels.styles);
  const row = (id: number, style: LabelStyle): LabelRow => ({
    id,
    name: `label ${id}`,
    named: false,
    color: style.color,
    opacity: style.opacity,
    visible: style.visible,
    voxels: null,
  });
  const rows: LabelRow[] = [];
  const listed = new Set<number>();
  for (const label of named ? drawn.labels : []) {
    const style = labels.styles[String(label.id)]!;
    listed.add(label.id);
    rows.push({ ...row(label.id, style), name: label.name, named: true, voxels: label.voxels });
  }
  const rest = Object.keys(labels.styles)
    .map(Number)
    .filter((id) => !listed.has(id))
    .sort((a, b) => a - b);
  for (const id of rest) rows.push(row(id, labels.styles[String(id)]!));
  return rows;
}

function words(text: string): string {
  return text
    .toLowerCase()
    .replace(/[_\s-]+/g, ' ')
    .trim();
}

/**
 * Whether a label answers a search: an id (`45`, `#45`) finds that label and names holding the
 * number; words find names holding every one of them, underscores read as spaces, a single letter
 * (L, R) only as a word of its own ("cuneus l" finds Cuneus_L and Precuneus_L).
 */
export function matchesSearch(row: LabelRow, query: string): boolean {
  const q = words(query).replace(/^#/, '');
  if (q === '') return true;
  const name = words(row.name);
  if (/^-?\d+$/.test(q) && String(row.id) === q) return true;
  const nameWords = name.split(' ');
  return q
    .split(' ')
    .every((word) => (word.length === 1 ? nameWords.includes(word) : name.includes(word)));
}

export function filterLabels(rows: LabelRow[], query: string): LabelRow[] {
  return rows.filter((row) => matchesSearch(row, query));
}

export function visibilityPatch(id: number, visible: boolean): StatePatch {
  return { labels: { styles: { [String(id)]: { visible } } } };
}

export function opacityPatch(id: number, opacity: number): StatePatch {
  return { labels: { styles: { [String(id)]: { opacity } } } };
}

/** These labels shown, every other one hidden. */
export function onlyPatch(ids: number[]): StatePatch {
  return { labels: { only: [...ids] } };
}

export function allPatch(all: { visible?: boolean; opacity?: number }): StatePatch {
  return { labels: { all: { ...all } } };
}

export function blendPatch(blend: number): StatePatch {
  return { labels: { blend } };
}

/** The label map drawn alone, as surfaces (true), or inside the scan (false). */
export function alonePatch(alone: boolean): StatePatch {
  return { labels: { alone } };
}

/**
 * The volumes to offer as label maps: those the server says it would draw as one. A server that
 * does not say (older than `label_map`) has each offered, and refuses what is not one.
 */
export function labelMapChoices(volumes: VolumeSummary[], current: string): VolumeSummary[] {
  const told = volumes.some((v) => v.label_map !== undefined);
  return volumes.filter((v) => v.id !== current && (told ? v.label_map === true : true));
}

/** "28,174"; thousands grouped, as the voxel counts are compared at a glance. */
export function formatCount(n: number): string {
  return Math.round(n)
    .toString()
    .replace(/\B(?=(\d{3})+(?!\d))/g, ',');
}

export function cssColor(rgb: Rgb, alpha = 1): string {
  const [r, g, b] = rgb.map((c) => Math.round(Math.min(1, Math.max(0, c)) * 255));
  return alpha >= 1 ? `rgb(${r},${g},${b})` : `rgba(${r},${g},${b},${alpha})`;
}

export interface LabelsPanelActions {
  /** A labels patch to send, as the other panels' changes go (interactive while a slider moves). */
  change: (patch: StatePatch, interactive: boolean) => void;
  /** Draw this volume as the label map. */
  add: (volume: string) => void;
  remove: () => void;
}

/** One row's elements, kept so that a new state updates them in place. */
interface RowElements {
  root: HTMLElement;
  visible: HTMLInputElement;
  swatch: HTMLElement;
  only: HTMLButtonElement;
}

export class LabelsPanel {
  private readonly root: HTMLElement;
  private readonly choice: HTMLSelectElement;
  private readonly status: HTMLElement;
  private readonly drawnPart: HTMLElement;
  private readonly mapName: HTMLElement;
  private readonly shownCount: HTMLElement;
  private readonly unnamed: HTMLElement;
  private readonly removeButton: HTMLButtonElement;
  private readonly alone: HTMLInputElement;
  private readonly blendRow: HTMLElement;
  private readonly blend: HTMLInputElement;
  private readonly blendValue: HTMLOutputElement;
  private readonly search: HTMLInputElement;
  private readonly showAll: HTMLButtonElement;
  private readonly hideAll: HTMLButtonElement;
  private readonly onlyFound: HTMLButtonElement;
  private readonly list: HTMLElement;
  private readonly selectedPart: HTMLElement;
  private readonly selectedName: HTMLElement;
  private readonly selectedOpacity: HTMLInputElement;
  private readonly selectedOpacityValue: HTMLOutputElement;
  private readonly selectedOnly: HTMLButtonElement;

  private rows: LabelRow[] = [];
  private readonly elements = new Map<number, RowElements>();
  private found: LabelRow[] = [];
  private selected: number | null = null;
  private enabled = true;
  private drawnVolume = '';
  private choices: VolumeSummary[] = [];
  private listed = false;
  private busy: string | null = null;
  /** The slider the user is moving: a state that arrives meanwhile leaves it where the finger is. */
  private moving: HTMLInputElement | null = null;

  constructor(
    private readonly folder: GUI,
    private readonly actions: LabelsPanelActions,
  ) {
    this.root = element('div', 'labels-panel');

    this.choice = element('select', 'labels-add');
    this.choice.dataset['control'] = 'labels-add';
    this.choice.setAttribute('aria-label', 'add a label map');
    this.choice.addEventListener('change', () => {
      const id = this.choice.value;
      this.choice.value = '';
      if (id && this.enabled && this.busy === null) this.actions.add(id);
    });
    this.status = element('div', 'hint labels-status');

    this.drawnPart = element('div', 'labels-drawn');
    const head = element('div', 'labels-head');
    this.mapName = element('span', 'labels-map');
    this.shownCount = element('span', 'labels-count');
    this.shownCount.dataset['control'] = 'labels-count';
    this.unnamed = element('div', 'hint');
    this.unnamed.textContent =
      "This map's names are not known (an older server tells a viewer them only as it joins): its labels are listed by id.";
    this.removeButton = button('Remove', 'labels-remove', 'draw no label map');
    this.removeButton.addEventListener(
      'click',
      () => this.enabled && this.busy === null && this.actions.remove(),
    );
    head.append(this.mapName, this.removeButton);

    const aloneRow = element('label', 'labels-alone');
    aloneRow.title =
      'draw the label map by itself: each visible label a smooth lit surface in its colour, the scan not drawn';
    this.alone = element('input', '');
    this.alone.type = 'checkbox';
    this.alone.dataset['control'] = 'labels-alone';
    this.alone.addEventListener('change', () => this.send(alonePatch(this.alone.checked)));
    aloneRow.append(this.alone, text('span', 'labels only (surfaces, no scan)'));

    const blendRow = element('label', 'labels-slider');
    this.blendRow = blendRow;
    blendRow.dataset['control'] = 'labels-blend-row';
    blendRow.title = "how much a label's colour replaces the transfer function's";
    this.blend = slider('labels-blend');
    this.blendValue = element('output', '');
    blendRow.append(text('span', 'colour blend'), this.blend, this.blendValue);
    this.wireSlider(this.blend, this.blendValue, (value, interactive) =>
      this.actions.change(blendPatch(value), interactive),
    );

    this.search = element('input', 'labels-search');
    this.search.type = 'search';
    this.search.placeholder = 'search name or id';
    this.search.dataset['control'] = 'labels-search';
    this.search.setAttribute('aria-label', 'search the labels by name or id');
    this.search.addEventListener('input', () => this.applySearch());

    const bulk = element('div', 'labels-actions');
    this.showAll = button('Show all', 'labels-show-all', 'show every label');
    this.showAll.addEventListener('click', () => this.send(allPatch({ visible: true })));
    this.hideAll = button('Hide all', 'labels-hide-all', 'hide every label');
    this.hideAll.addEventListener('click', () => this.send(allPatch({ visible: false })));
    this.onlyFound = button('Only these', 'labels-only-found', 'show only the labels found');
    this.onlyFound.addEventListener('click', () =>
      this.send(onlyPatch(this.found.map((r) => r.id))),
    );
    bulk.append(this.showAll, this.hideAll, this.onlyFound);

    this.list = element('div', 'labels-list');
    this.list.dataset['control'] = 'labels-list';
    this.list.setAttribute('role', 'listbox');
    this.list.setAttribute('aria-label', 'labels');
    this.list.addEventListener('click', (e) => this.listClicked(e));
    this.list.addEventListener('change', (e) => this.listChanged(e));

    this.selectedPart = element('div', 'labels-selected');
    this.selectedPart.dataset['control'] = 'labels-selected';
    this.selectedName = element('div', 'labels-selected-name');
    const opacityRow = element('label', 'labels-slider');
    this.selectedOpacity = slider('labels-opacity');
    this.selectedOpacityValue = element('output', '');
    opacityRow.append(text('span', 'opacity'), this.selectedOpacity, this.selectedOpacityValue);
    this.wireSlider(this.selectedOpacity, this.selectedOpacityValue, (value, interactive) => {
      if (this.selected !== null)
        this.actions.change(opacityPatch(this.selected, value), interactive);
    });
    this.selectedOnly = button('Show only this', 'labels-selected-only', '');
    this.selectedOnly.addEventListener('click', () => {
      if (this.selected !== null) this.send(onlyPatch([this.selected]));
    });
    this.selectedPart.append(this.selectedName, opacityRow, this.selectedOnly);

    this.drawnPart.append(
      head,
      this.shownCount,
      this.unnamed,
      aloneRow,
      blendRow,
      this.search,
      bulk,
      this.list,
      this.selectedPart,
    );
    this.root.append(this.choice, this.status, this.drawnPart);
    folder.$children.appendChild(this.root);
    this.refreshChoices();
    this.show();
  }

  /** The volumes listed; those the server draws as label maps are offered. */
  setVolumes(volumes: VolumeSummary[], current: string): void {
    this.choices = labelMapChoices(volumes, current);
    this.listed = true;
    this.refreshChoices();
  }

  /**
   * A label map being loaded or removed (its text), or null once the server answered. Meanwhile
   * neither another map nor Remove may be chosen: one change of the map at a time, so the text
   * stays until the server answered it.
   */
  setBusy(busy: string | null): void {
    this.busy = busy;
    this.refreshChoices();
  }

  /** Whether the user may change the labels (the session's owner). */
  setEnabled(enabled: boolean): void {
    this.enabled = enabled;
    for (const control of [
      this.alone,
      this.blend,
      this.showAll,
      this.hideAll,
      this.onlyFound,
      this.selectedOpacity,
      this.selectedOnly,
    ]) {
      control.disabled = !enabled;
    }
    for (const row of this.elements.values()) {
      row.visible.disabled = !enabled;
      row.only.disabled = !enabled;
    }
    this.root.classList.toggle('read-only', !enabled);
    this.refreshChoices();
    this.show();
  }

  /** Shows the session's labels as the server's state styles them; `drawn` names them. */
  update(state: State | undefined, drawn?: DrawnLabels): void {
    const labels = state?.labels;
    const rows = labelRows(labels, drawn);
    this.drawnVolume = labels ? (drawn?.volume ?? '') : '';
    const sameLabels =
      rows.length === this.rows.length &&
      rows.every((r, i) => r.id === this.rows[i]!.id && r.name === this.rows[i]!.name);
    this.rows = rows;
    if (!sameLabels) this.build();
    for (const row of rows) this.showRow(row);
    if (labels && this.moving !== this.blend) setSlider(this.blend, this.blendValue, labels.blend);
    this.alone.checked = labels?.alone ?? false;
    // Drawn alone, the labels' colours are whole: the blend has nothing to blend.
    this.blendRow.hidden = this.alone.checked;
    if (this.selected !== null && !rows.some((r) => r.id === this.selected)) this.selected = null;
    this.mapName.textContent = this.drawnVolume || 'label map';
    this.mapName.title = this.drawnVolume;
    this.unnamed.hidden = rows.length === 0 || rows.some((r) => r.named);
    this.applySearch();
    this.showSelected();
    this.refreshChoices();
    this.show();
  }

  /** Selects a label (a row tapped, or a pick that found it) and scrolls the list to it. */
  select(id: number): void {
    if (!this.rows.some((r) => r.id === id)) return;
    this.selected = id;
    this.showSelected();
    const row = this.elements.get(id)?.root;
    if (row && !row.hidden) {
      this.list.scrollTop = row.offsetTop - (this.list.clientHeight - row.offsetHeight) / 2;
    }
  }

  /** The label's style as the state has it: the colour a pick shows it with. */
  row(id: number): LabelRow | undefined {
    return this.rows.find((r) => r.id === id);
  }

  private send(patch: StatePatch): void {
    if (this.enabled) this.actions.change(patch, false);
  }

  /** A slider sends interactive changes while it moves and a still one when let go. */
  private wireSlider(
    input: HTMLInputElement,
    output: HTMLOutputElement,
    send: (value: number, interactive: boolean) => void,
  ): void {
    input.addEventListener('input', () => {
      this.moving = input;
      output.value = Number(input.value).toFixed(2);
      if (this.enabled) send(Number(input.value), true);
    });
    input.addEventListener('change', () => {
      this.moving = null;
      if (this.enabled) send(Number(input.value), false);
    });
  }

  private build(): void {
    this.elements.clear();
    const fragment = document.createDocumentFragment();
    for (const row of this.rows) {
      const root = element('div', 'label-row');
      root.dataset['label'] = String(row.id);
      root.setAttribute('role', 'option');
      const visible = element('input', 'label-visible');
      visible.type = 'checkbox';
      visible.title = 'shown';
      visible.setAttribute('aria-label', `show ${row.name}`);
      visible.disabled = !this.enabled;
      const swatch = element('span', 'label-swatch');
      const name = text('span', row.name, 'label-name');
      name.title = row.named ? row.name : 'name not known';
      const id = text('span', String(row.id), 'label-id');
      const voxels = text(
        'span',
        row.voxels === null ? '' : formatCount(row.voxels),
        'label-voxels',
      );
      if (row.voxels !== null) voxels.title = `${formatCount(row.voxels)} voxels`;
      const only = button('only', '', `show only ${row.name}`);
      only.className = 'label-only';
      only.disabled = !this.enabled;
      root.append(visible, swatch, name, id, voxels, only);
      fragment.append(root);
      this.elements.set(row.id, { root, visible, swatch, only });
    }
    this.list.replaceChildren(fragment);
  }

  private showRow(row: LabelRow): void {
    const e = this.elements.get(row.id);
    if (!e) return;
    e.visible.checked = row.visible;
    e.swatch.style.background = cssColor(row.color, 0.25 + 0.75 * row.opacity);
    e.root.classList.toggle('hidden-label', !row.visible);
    e.root.classList.toggle('selected', row.id === this.selected);
    e.root.setAttribute('aria-selected', String(row.id === this.selected));
  }

  private rowOf(target: EventTarget | null): LabelRow | undefined {
    const root = (target as HTMLElement | null)?.closest?.('.label-row') as HTMLElement | null;
    const id = root ? Number(root.dataset['label']) : NaN;
    return this.rows.find((r) => r.id === id);
  }

  private listClicked(e: Event): void {
    const row = this.rowOf(e.target);
    if (!row) return;
    const target = e.target as HTMLElement;
    if (target.classList.contains('label-only')) {
      this.send(onlyPatch([row.id]));
    } else if (!target.classList.contains('label-visible')) {
      this.select(row.id);
    }
  }

  private listChanged(e: Event): void {
    const row = this.rowOf(e.target);
    const target = e.target as HTMLInputElement;
    if (!row || !target.classList.contains('label-visible')) return;
    if (!this.enabled) {
      target.checked = row.visible;
      return;
    }
    this.send(visibilityPatch(row.id, target.checked));
  }

  /** Rows that do not answer the search are hidden, not rebuilt. */
  private applySearch(): void {
    const query = this.search.value;
    this.found = filterLabels(this.rows, query);
    const found = new Set(this.found.map((r) => r.id));
    for (const [id, e] of this.elements) e.root.hidden = !found.has(id);
    const shown = this.rows.filter((r) => r.visible).length;
    const searching = words(query) !== '';
    this.shownCount.textContent = searching
      ? `${this.found.length} found · ${shown} of ${this.rows.length} shown`
      : `${shown} of ${this.rows.length} shown`;
    this.onlyFound.hidden = !searching;
    this.onlyFound.textContent = `Only the ${this.found.length} found`;
    this.onlyFound.disabled = !this.enabled || this.found.length === 0;
    for (const row of this.rows) {
      const e = this.elements.get(row.id);
      e?.root.classList.toggle('selected', row.id === this.selected);
    }
  }

  private showSelected(): void {
    const row = this.selected === null ? undefined : this.rows.find((r) => r.id === this.selected);
    this.selectedPart.hidden = !row;
    for (const [id, e] of this.elements) {
      e.root.classList.toggle('selected', id === this.selected);
      e.root.setAttribute('aria-selected', String(id === this.selected));
    }
    if (!row) return;
    this.selectedName.replaceChildren(
      swatchOf(row),
      text('strong', row.name),
      text('span', ` ${row.id}`, 'label-id'),
    );
    if (this.moving !== this.selectedOpacity)
      setSlider(this.selectedOpacity, this.selectedOpacityValue, row.opacity);
    this.selectedOnly.textContent = `Show only ${row.name}`;
  }

  private refreshChoices(): void {
    const options = [
      new Option(this.rows.length > 0 ? 'Replace with another label map…' : 'Add label map…', ''),
      ...this.choices.filter((v) => v.id !== this.drawnVolume).map((v) => new Option(v.name, v.id)),
    ];
    options[0]!.disabled = true;
    this.choice.replaceChildren(...options);
    this.choice.value = '';
    this.choice.hidden = this.listed && options.length === 1;
    this.choice.disabled = !this.enabled || this.busy !== null;
    this.removeButton.disabled = !this.enabled || this.busy !== null;
    this.status.textContent = this.busy
      ? this.busy
      : this.enabled && this.listed && this.choices.length === 0
        ? 'The server lists no label maps (segmentations or atlases) in its data folder.'
        : '';
    this.status.hidden = this.status.textContent === '';
  }

  /** The folder shows while a map is drawn, and to the owner, who may add one. */
  private show(): void {
    const drawn = this.rows.length > 0;
    this.drawnPart.hidden = !drawn;
    this.folder.show(drawn || this.enabled);
  }
}

function element<K extends keyof HTMLElementTagNameMap>(
  tag: K,
  className: string,
): HTMLElementTagNameMap[K] {
  const e = document.createElement(tag);
  if (className) e.className = className;
  return e;
}

function text(tag: 'span' | 'strong', content: string, className = ''): HTMLElement {
  const e = element(tag, className);
  e.textContent = content;
  return e;
}

function button(label: string, control: string, title: string): HTMLButtonElement {
  const b = element('button', 'labels-button');
  b.type = 'button';
  b.textContent = label;
  if (control) b.dataset['control'] = control;
  if (title) b.title = title;
  return b;
}

function slider(control: string): HTMLInputElement {
  const s = element('input', '');
  s.type = 'range';
  s.min = '0';
  s.max = '1';
  s.step = '0.01';
  s.dataset['control'] = control;
  return s;
}

function setSlider(input: HTMLInputElement, output: HTMLOutputElement, value: number): void {
  input.value = String(value);
  output.value = value.toFixed(2);
}

function swatchOf(row: LabelRow): HTMLElement {
  const swatch = element('span', 'label-swatch');
  swatch.style.background = cssColor(row.color);
  return swatch;
}
