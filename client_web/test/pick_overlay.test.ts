import { afterEach, describe, expect, it, vi } from 'vitest';
import {
  formatPosition,
  formatValue,
  framePoint,
  pickText,
  PickOverlay,
} from '../src/view/pick_overlay';
import { parseServerMessage, type PickedMessage } from '../src/protocol/messages';
import { FakeElement, useFakeDom } from './fake_dom';
import { recordedLabelMessages } from './recorded';

describe('the point of the frame image under a pointer', () => {
  it('is the fraction of the image, which fills a view of its own shape', () => {
    expect(framePoint(400, 180, 800, 720, 800, 720)).toEqual({ x: 0.5, y: 0.25 });
    expect(framePoint(0, 720, 800, 720, 800, 720)).toEqual({ x: 0, y: 1 });
  });

  it("is of the image, not of the view, while it is letterboxed (the view's shape changed)", () => {
    // A 400×400 image in an 800×600 view: drawn 600×600 from x 100.
    expect(framePoint(400, 300, 800, 600, 400, 400)).toEqual({ x: 0.5, y: 0.5 });
    expect(framePoint(100, 0, 800, 600, 400, 400)).toEqual({ x: 0, y: 0 });
    expect(framePoint(250, 450, 800, 600, 400, 400)).toEqual({ x: 0.25, y: 0.75 });
    // A portrait view: bands above and below.
    expect(framePoint(384, 512, 768, 1024, 800, 720)).toEqual({ x: 0.5, y: 0.5 });
  });

  it('is none on the bands beside the image, or before any frame', () => {
    expect(framePoint(50, 300, 800, 600, 400, 400)).toBeNull();
    expect(framePoint(384, 100, 768, 1024, 800, 720)).toBeNull();
    expect(framePoint(10, 10, 800, 600, 0, 0)).toBeNull();
  });
});

describe('what a pick says', () => {
  const hit = parseServerMessage(recordedLabelMessages[4]!) as PickedMessage;
  const miss = parseServerMessage(recordedLabelMessages[5]!) as PickedMessage;

  it('where in the patient, RAS to a tenth of a millimetre', () => {
    expect(formatPosition([-14.616, -0.421, 48.519])).toBe('R -14.6 · A -0.4 · S 48.5 mm');
    expect(formatPosition([-0.04, 0, 0.04])).toBe('R 0.0 · A 0.0 · S 0.0 mm');
  });

  it('the value, in Hounsfield units whole for a CT', () => {
    expect(formatValue(112.9397, false)).toBe('112.9');
    expect(formatValue(-999.6, true)).toBe('-1000 HU');
  });

  it('the label drawn there, its name and id', () => {
    expect(pickText(hit)).toEqual({
      hit: true,
      label: { id: 19, name: 'Supp_Motor_Area_L' },
      position: 'R -14.6 · A -0.4 · S 48.5 mm',
      value: 'value 112.9',
    });
    const unlabelled: PickedMessage = { ...hit, hounsfield: true, value: 40.2 };
    delete unlabelled.label;
    expect(pickText(unlabelled)).toEqual({
      hit: true,
      position: 'R -14.6 · A -0.4 · S 48.5 mm',
      value: 'value 40 HU',
    });
  });

  it('that nothing is there without a hit', () => {
    expect(pickText(miss)).toEqual({ hit: false });
  });
});

describe('the pick on screen', () => {
  const hit = parseServerMessage(recordedLabelMessages[4]!) as PickedMessage;
  afterEach(() => vi.unstubAllGlobals());

  function overlay(): PickOverlay {
    useFakeDom();
    const pick = new PickOverlay(new FakeElement('div') as unknown as HTMLElement);
    pick.setFrame({ width: 800, height: 600 });
    return pick;
  }

  it("shows its own answer, and says so (the panel then selects the answer's label)", () => {
    const pick = overlay();
    const ticket = pick.start({ x: 0.5, y: 0.5 });
    expect(pick.answer(ticket, hit)).toBe(true);
    const callout = (pick.element as unknown as FakeElement).children[1]!;
    expect(callout.dataset).toMatchObject({ state: 'hit', label: '19' });
  });

  it('shows no answer to an older pick, or to one cleared since, and says so', () => {
    const pick = overlay();
    const first = pick.start({ x: 0.2, y: 0.2 });
    const second = pick.start({ x: 0.5, y: 0.5 });
    expect(pick.answer(first, hit)).toBe(false);
    pick.clear();
    expect(pick.answer(second, hit)).toBe(false);
    expect(pick.shown).toBe(false);
  });
});
