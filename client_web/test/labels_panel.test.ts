import { afterEach, describe, expect, it, vi } from 'vitest';
import type GUI from 'lil-gui';
import {
  allPatch,
  alonePatch,
  blendPatch,
  cssColor,
  filterLabels,
  formatCount,
  labelMapChoices,
  labelRows,
  LabelsPanel,
  matchesSearch,
  onlyPatch,
  opacityPatch,
  visibilityPatch,
} from '../src/panels/labels_panel';
import {
  parseServerMessage,
  type LabelsMessage,
  type LabelsState,
  type StatePatch,
  type VolumeSummary,
} from '../src/protocol/messages';
import { checkClientMessage } from './client_checks';
import { FakeElement, useFakeDom } from './fake_dom';
import { applyLabelsPatch } from './labels_server';
import { recordedLabelMessages, recordedTerms } from './recorded';

const added = parseServerMessage(recordedLabelMessages[0]!) as LabelsMessage;
const drawn = { volume: added.volume, labels: added.labels };
const styles = added.state.labels!;
const rows = labelRows(styles, drawn);

/** The labels' styles after the server applied the patch's labels. */
function applied(patch: StatePatch, to: LabelsState = styles): LabelsState {
  expect(checkClientMessage({ v: 1, type: 'set', ...patch }, recordedTerms)).toBeNull();
  return applyLabelsPatch(to, patch.labels!);
}

describe('the labels listed', () => {
  it("are the map's, in its order, each with the state's style", () => {
    expect(rows).toHaveLength(116);
    expect(rows.slice(0, 2).map((r) => [r.id, r.name, r.voxels])).toEqual([
      [1, 'Precentral_L', 28174],
      [2, 'Precentral_R', 27058],
    ]);
    expect(rows.every((r) => r.named && r.visible && r.opacity === 1)).toBe(true);
    // The colour is the state's (0..1), which a set may change, not the file's.
    expect(rows[2]!.color).toEqual(styles.styles['3']!.color);
  });

  it('none while the state styles no labels', () => {
    expect(labelRows(undefined, drawn)).toEqual([]);
  });

  it('by id alone, in order, where the names are not known (an older server told a viewer them only at its join)', () => {
    const some: LabelsState = {
      blend: 0.5,
      styles: {
        '12': { color: [1, 0, 0], opacity: 1, visible: true },
        '3': { color: [0, 1, 0], opacity: 0.5, visible: false },
      },
    };
    expect(labelRows(some).map((r) => [r.id, r.name, r.named, r.voxels])).toEqual([
      [3, 'label 3', false, null],
      [12, 'label 12', false, null],
    ]);
    // A list of another map's labels names none of these.
    expect(labelRows(some, drawn).every((r) => !r.named)).toBe(true);
  });
});

describe('the search', () => {
  const names = (query: string) => filterLabels(rows, query).map((r) => r.name);

  it('finds names holding the words, underscores read as spaces, in any case', () => {
    expect(names('Cuneus')).toEqual(['Cuneus_L', 'Cuneus_R', 'Precuneus_L', 'Precuneus_R']);
    expect(names('cuneus l')).toEqual(['Cuneus_L', 'Precuneus_L']);
    expect(names('  CUNEUS_R ')).toEqual(['Cuneus_R', 'Precuneus_R']);
    expect(names('nothing like it')).toEqual([]);
  });

  it('finds a label by its id, and names holding the number', () => {
    expect(names('45')).toEqual(['Cuneus_L']);
    expect(names('#46')).toEqual(['Cuneus_R']);
    expect(names('10')).toEqual([
      'Frontal_Mid_Orb_R',
      'Cerebelum_10_L',
      'Cerebelum_10_R',
      'Vermis_10',
    ]);
  });

  it('finds every label when empty', () => {
    expect(filterLabels(rows, '')).toHaveLength(116);
    expect(matchesSearch(rows[0]!, '   ')).toBe(true);
  });
});

describe("the panel's patches", () => {
  it('hide or show one label', () => {
    const hidden = applied(visibilityPatch(45, false));
    expect(hidden.styles['45']!.visible).toBe(false);
    expect(Object.values(hidden.styles).filter((s) => !s.visible)).toHaveLength(1);
  });

  it("set one label's opacity", () => {
    expect(applied(opacityPatch(46, 0.25)).styles['46']).toMatchObject({
      opacity: 0.25,
      visible: true,
    });
  });

  it('show one label, or the labels found, alone', () => {
    const one = applied(onlyPatch([45]));
    expect(Object.entries(one.styles).filter(([, s]) => s.visible)).toEqual([
      ['45', expect.objectContaining({ visible: true })],
    ]);
    const found = filterLabels(rows, 'cuneus').map((r) => r.id);
    const four = applied(onlyPatch(found));
    expect(
      Object.keys(four.styles)
        .filter((id) => four.styles[id]!.visible)
        .map(Number)
        .sort((a, b) => a - b),
    ).toEqual([45, 46, 67, 68]);
  });

  it('show or hide every label, and blend their colours', () => {
    const none = applied(allPatch({ visible: false }));
    expect(Object.values(none.styles).some((s) => s.visible)).toBe(false);
    const all = applied(allPatch({ visible: true }), none);
    expect(Object.values(all.styles).every((s) => s.visible)).toBe(true);
    expect(applied(blendPatch(0.3)).blend).toBe(0.3);
  });

  it('draw the map alone, as surfaces, and inside the scan again', () => {
    expect(styles.alone).toBe(false);
    const alone = applied(alonePatch(true));
    expect(alone.alone).toBe(true);
    expect(alone.styles).toEqual(styles.styles);
    expect(applied(alonePatch(false), alone).alone).toBe(false);
  });
});

describe('the label maps offered', () => {
  const volume = (id: string, label_map?: boolean): VolumeSummary => ({
    id,
    name: id,
    dims: [0, 0, 0],
    spacing: [1, 1, 1],
    voxel_type: '',
    range: [0, 0],
    hounsfield: false,
    loaded: false,
    ...(label_map === undefined ? {} : { label_map }),
  });

  it('are those the server says it draws as label maps', () => {
    const listed = [
      volume('ch2.nii.gz', false),
      volume('aal.nii.gz', true),
      volume('x.nii', false),
    ];
    expect(labelMapChoices(listed, 'ch2.nii.gz').map((v) => v.id)).toEqual(['aal.nii.gz']);
    expect(labelMapChoices([volume('ch2.nii.gz', false)], 'ch2.nii.gz')).toEqual([]);
  });

  it('are every other volume from a server that does not say', () => {
    const listed = [volume('ch2.nii.gz'), volume('aal.nii.gz'), volume('brodmann.nii.gz')];
    expect(labelMapChoices(listed, 'ch2.nii.gz').map((v) => v.id)).toEqual([
      'aal.nii.gz',
      'brodmann.nii.gz',
    ]);
  });
});

describe('a change of the label map', () => {
  afterEach(() => vi.unstubAllGlobals());

  function find(e: FakeElement, control: string): FakeElement | undefined {
    if (e.dataset['control'] === control) return e;
    for (const child of e.children) {
      const found = find(child, control);
      if (found) return found;
    }
    return undefined;
  }

  it('is one at a time: while a map loads, neither another nor Remove may be chosen', () => {
    useFakeDom();
    const children = new FakeElement('div');
    const folder = { $children: children, show: () => folder } as unknown as GUI;
    const asked: string[] = [];
    const panel = new LabelsPanel(folder, {
      change: () => {},
      add: (volume) => asked.push(`add ${volume}`),
      remove: () => asked.push('remove'),
    });
    panel.setEnabled(true);
    const volume = (id: string, label_map: boolean): VolumeSummary => ({
      id,
      name: id,
      dims: [0, 0, 0],
      spacing: [1, 1, 1],
      voxel_type: '',
      range: [0, 0],
      hounsfield: false,
      loaded: false,
      label_map,
    });
    const volumes = [
      volume('ch2.nii.gz', false),
      volume('aal.nii.gz', true),
      volume('b.nii', true),
    ];
    panel.setVolumes(volumes, 'ch2.nii.gz');
    panel.update(added.state, drawn);
    const choice = find(children, 'labels-add')!;
    const remove = find(children, 'labels-remove')!;
    const choose = (id: string) => {
      choice.value = id;
      choice.dispatchEvent(new Event('change'));
    };

    choose('b.nii');
    panel.setBusy('Loading b.nii…');
    expect([choice.disabled, remove.disabled]).toEqual([true, true]);
    panel.setEnabled(true); // the session's role told again meanwhile
    expect([choice.disabled, remove.disabled]).toEqual([true, true]);
    choose('aal.nii.gz');
    remove.dispatchEvent(new Event('click'));
    expect(asked).toEqual(['add b.nii']);

    panel.setBusy(null);
    expect([choice.disabled, remove.disabled]).toEqual([false, false]);
    remove.dispatchEvent(new Event('click'));
    expect(asked).toEqual(['add b.nii', 'remove']);
  });

  it('draws the map alone when asked, and shows it so once the state says it (no blend then)', () => {
    useFakeDom();
    const children = new FakeElement('div');
    const folder = { $children: children, show: () => folder } as unknown as GUI;
    const sent: StatePatch[] = [];
    const panel = new LabelsPanel(folder, {
      change: (patch) => sent.push(patch),
      add: () => {},
      remove: () => {},
    });
    panel.setEnabled(true);
    panel.update(added.state, drawn);
    const alone = find(children, 'labels-alone')!;
    const blend = find(children, 'labels-blend-row')!;
    expect(alone.checked).toBe(false);
    alone.checked = true;
    alone.dispatchEvent(new Event('change'));
    expect(sent).toEqual([alonePatch(true)]);
    const state = { ...added.state, labels: applied(alonePatch(true)) };
    panel.update(state, drawn);
    expect(alone.checked).toBe(true);
    expect(blend.hidden).toBe(true);
    panel.update(added.state, drawn);
    expect(blend.hidden).toBe(false);
    panel.setEnabled(false);
    expect(alone.disabled).toBe(true);
  });
});

describe('what the rows show', () => {
  it('voxel counts grouped by thousands', () => {
    expect([0, 999, 28174, 1234567].map(formatCount)).toEqual(['0', '999', '28,174', '1,234,567']);
  });

  it("a style's colour as CSS", () => {
    expect(cssColor([0.8, 0.8, 0.8])).toBe('rgb(204,204,204)');
    expect(cssColor([1, 0, 0.5], 0.5)).toBe('rgba(255,0,128,0.5)');
  });
});
