import { describe, expect, it } from 'vitest';
import { refinementStatus, refinementText } from '../src/view/refinement_badge';
import { stillHeader } from './frame_headers';

const still = stillHeader;

describe('refinement badge', () => {
  it('says a still is refining from its first frame until the last step', () => {
    expect(refinementStatus({ ...still, refining: true })).toEqual({ kind: 'refining', step: 0 });
    expect(refinementText(refinementStatus({ ...still, refinement: 4, refining: true }))).toBe(
      'refining… step 4',
    );
  });

  it('says the still is done, and after how many steps, on the last one', () => {
    const last = refinementStatus({ ...still, refinement: 7, refining: false });
    expect(last).toEqual({ kind: 'done', steps: 7 });
    expect(refinementText(last)).toBe('still done · 7 steps');
    expect(refinementText({ kind: 'done', steps: 1 })).toBe('still done · 1 step');
  });

  it('says that a preview stands for the still until the still comes', () => {
    const preview = refinementStatus({
      ...still,
      width: 32,
      height: 48,
      preview: true,
      refining: true,
    });
    expect(preview).toEqual({ kind: 'preview', width: 32, height: 48 });
    expect(refinementText(preview)).toBe('preview 32×48, rendering the still…');
    expect(refinementStatus({ ...still, refining: true }).kind).toBe('refining');
  });

  it('says nothing of interactive frames and of stills that are not refined', () => {
    expect(refinementStatus({ ...still, interactive: true, refining: true }).kind).toBe('none');
    expect(refinementStatus(still).kind).toBe('none');
    expect(refinementStatus({ ...still, refinement: 0, refining: false }).kind).toBe('none');
  });
});
