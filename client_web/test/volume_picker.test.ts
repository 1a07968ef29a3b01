import { describe, expect, it } from 'vitest';
import { listingNote } from '../src/panels/volume_picker';

describe('listingNote', () => {
  it('says while the first scan runs how many volumes it has found, and when a scan was cut short', () => {
    expect(listingNote('scanning', 3)).toBe('scanning… 3 found so far');
    expect(listingNote('cut_short', 40)).toMatch(/cut short.*missing/);
    expect(listingNote('complete', 40)).toBe('');
  });
});
