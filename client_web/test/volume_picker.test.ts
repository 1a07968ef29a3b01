import { describe, expect, it } from 'vitest';
import { listingNote } from '../src/panels/volume_picker';

describe('listingNote', () => {
  it('says while the first scan runs how many volumes it has found, and that a cut-short list is partial', () => {
    expect(listingNote('scanning', 3)).toBe('scanning… 3 found');
    expect(listingNote('cut_short', 40)).toBe('partial list');
    expect(listingNote('complete', 40)).toBe('');
  });
});
