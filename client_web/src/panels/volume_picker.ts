// Volume picker: the volumes from `list_volumes` in a drop-down; picking one opens it.

import type GUI from 'lil-gui';
import type { Controller } from 'lil-gui';
import type { Listing, VolumeSummary } from '../protocol/messages';

export function volumeLabel(v: VolumeSummary): string {
  const dims = v.dims.every((d) => d > 0) ? ` (${v.dims.join('×')} ${v.voxel_type})` : '';
  return `${v.name}${dims}`;
}

/** What the picker says of a listing that is not yet, or not, the whole data folder. */
export function listingNote(listing: Listing, count: number): string {
  switch (listing) {
    case 'scanning':
      return `scanning… ${count} found`;
    case 'cut_short':
      return 'partial list';
    case 'complete':
      return '';
  }
}

export class VolumePicker {
  private readonly params = { volume: '', listing: '' };
  private readonly controller: Controller;
  private readonly listingLine: Controller;
  private volumes: VolumeSummary[] = [];

  constructor(
    private readonly folder: GUI,
    private readonly pick: (id: string) => void,
    refresh: () => void,
  ) {
    this.controller = folder.add(this.params, 'volume', []).name('volume');
    this.controller.onChange((id: string) => this.pick(id));
    this.controller.domElement.dataset['control'] = 'volume';
    folder.add({ refresh }, 'refresh').name('refresh list');
    this.listingLine = folder.add(this.params, 'listing').name('data folder').disable().hide();
    this.listingLine.domElement.dataset['control'] = 'listing';
  }

  /** Says whether the list is the whole data folder (hidden when it is). */
  setListing(listing: Listing): void {
    this.params.listing = listingNote(listing, this.volumes.length);
    this.listingLine.updateDisplay();
    this.listingLine.domElement.title =
      listing === 'cut_short'
        ? "The server's scan of its data folder stopped at its budget: some volumes may be missing."
        : '';
    this.listingLine.show(listing !== 'complete');
  }

  /** Whether the volume defaultVolume(wanted) would pick from the whole folder is listed yet. */
  listsPreferred(wanted: string | null): boolean {
    const ids = this.volumes.map((v) => v.id);
    return wanted ? ids.includes(wanted) : ids.some((id) => /^ch2\./.test(id));
  }

  /** The list to offer; `current` is selected without opening it again. */
  setVolumes(volumes: VolumeSummary[], current: string): void {
    this.volumes = volumes;
    const options: Record<string, string> = {};
    for (const v of volumes) options[volumeLabel(v)] = v.id;
    this.controller.options(options);
    this.select(current);
  }

  /** Shows what the server said about a volume once it was opened (dims, type). */
  updateVolume(volume: VolumeSummary): void {
    const i = this.volumes.findIndex((v) => v.id === volume.id);
    if (i < 0) return;
    this.volumes[i] = volume;
    this.setVolumes(this.volumes, volume.id);
  }

  select(id: string): void {
    this.params.volume = id;
    this.controller.updateDisplay();
  }

  /** The volume to open first: `wanted` when offered, else a head (ch2), else the first. */
  defaultVolume(wanted: string | null): string | undefined {
    const ids = this.volumes.map((v) => v.id);
    if (wanted && ids.includes(wanted)) return wanted;
    return ids.find((id) => /^ch2\./.test(id)) ?? ids[0];
  }

  setEnabled(enabled: boolean): void {
    this.controller.enable(enabled);
  }
}
