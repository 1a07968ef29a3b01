import type GUI from 'lil-gui';
import { beforeEach, describe, expect, it } from 'vitest';
import {
  ExportPanel,
  type ExportRequest,
  exportSize,
  exportText,
  movieSize,
} from '../src/panels/export_panel';
import type { ExportStatusMessage } from '../src/protocol/messages';
import { FakeElement, useFakeDom } from './fake_dom';

const running: ExportStatusMessage = {
  v: 1,
  type: 'export_status',
  id: 4,
  export: '5f0c2a9e41d37b88c6e2f01a9b4d7e63',
  state: 'running',
  progress: 0.25,
  width: 4096,
  height: 2731,
  tiles: 6,
};

beforeEach(() => useFakeDom());

function find(root: FakeElement, className: string): FakeElement {
  const all = [root];
  while (all.length > 0) {
    const element = all.shift() as FakeElement;
    if (element.className === className) return element;
    all.push(...element.children);
  }
  throw new Error(`no .${className}`);
}

describe('export size', () => {
  it("keeps the view's aspect with the long side asked for, within the server's limit", () => {
    expect(exportSize(1200, 800, 4096, 4096)).toEqual({ width: 4096, height: 2731 });
    expect(exportSize(768, 1024, 2048, 4096)).toEqual({ width: 1536, height: 2048 });
    expect(exportSize(1000, 1000, 8192, 3000)).toEqual({ width: 3000, height: 3000 });
  });

  it("gives a movie even sides in the view's aspect", () => {
    expect(movieSize(1200, 800, 1024, 1920)).toEqual({ width: 1024, height: 682 });
    expect(movieSize(1000, 333, 1024, 1920)).toEqual({ width: 1024, height: 340 });
    expect(movieSize(777, 1000, 4096, 1921)).toEqual({ width: 1492, height: 1920 });
    expect(movieSize(1, 1000, 512, 512)).toEqual({ width: 2, height: 512 });
  });
});

const limits = { max_export_side: 2048, max_movie_side: 1920, max_movie_frames: 720 };

describe('export panel', () => {
  it('says how far an export is, then offers its download or says why it failed', () => {
    expect(exportText(running)).toBe('rendering 4096×2731… 25% (6 tiles)');
    expect(exportText({ ...running, state: 'done', progress: 1, bytes: 9_100_000 })).toBe(
      '4096×2731 PNG, 9.1 MB',
    );
    expect(
      exportText({
        ...running,
        state: 'failed',
        error: { code: 'too_much_work', message: 'a tile asks too much' },
      }),
    ).toBe('failed: a tile asks too much');
  });

  it('starts an export at the chosen size, shows its progress and a cancel, then the link', async () => {
    const root = new FakeElement('div');
    const folder = { $children: root } as unknown as GUI;
    const started: ExportRequest[] = [];
    const cancelled: string[] = [];
    const panel = new ExportPanel(folder, {
      start: (request) => {
        started.push(request);
        return Promise.resolve({ ...running, progress: 0, tiles: 0 });
      },
      cancel: (id) => cancelled.push(id),
      viewSize: () => [1200, 800],
      downloadUrl: (status) => `http://server/exports/${status.export}?volume=ch2.nii.gz`,
    });
    panel.setLimits(limits);
    const sides = find(root, 'export-sides');
    expect(sides.children.map((o) => o.value)).toEqual(['1024', '2048']);
    expect(find(root, 'export-frames').hidden).toBe(true);
    sides.value = '2048';
    find(root, 'export-start').dispatchEvent(new Event('click'));
    await Promise.resolve();
    await Promise.resolve();
    expect(started).toEqual([{ kind: 'still', width: 2048, height: 1365 }]);
    expect(find(root, 'export-start').disabled).toBe(true);
    expect(find(root, 'export-cancel').hidden).toBe(false);

    panel.show(running);
    expect(find(root, 'export-status').textContent).toBe('rendering 4096×2731… 25% (6 tiles)');
    find(root, 'export-cancel').dispatchEvent(new Event('click'));
    expect(cancelled).toEqual([running.export]);

    panel.show({ ...running, state: 'done', progress: 1, url: '/exports/x', bytes: 5e6 });
    const link = find(root, 'export-link') as unknown as { hidden: boolean; href: string };
    expect(link.hidden).toBe(false);
    expect(link.href).toBe(`http://server/exports/${running.export}?volume=ch2.nii.gz`);
    expect(find(root, 'export-start').disabled).toBe(false);
    expect(find(root, 'export-cancel').hidden).toBe(true);
  });

  it('offers movies, a whole turn or rocking, at even sizes and lengths within the limits', async () => {
    const root = new FakeElement('div');
    const started: ExportRequest[] = [];
    const panel = new ExportPanel({ $children: root } as unknown as GUI, {
      start: (request) => {
        started.push(request);
        return Promise.resolve({ ...running, frames: 60, tiles: 1, progress: 0 });
      },
      cancel: () => {},
      viewSize: () => [1000, 333],
      downloadUrl: () => 'http://server/x',
    });
    panel.setLimits({ ...limits, max_movie_side: 1024, max_movie_frames: 100 });
    const kind = find(root, 'export-kind');
    expect(kind.children.map((o) => o.value)).toEqual(['still', 'turntable', 'rocking']);
    kind.value = 'rocking';
    kind.dispatchEvent(new Event('change'));
    expect(find(root, 'export-sides').children.map((o) => o.value)).toEqual(['512', '1024']);
    expect(find(root, 'export-sides').value).toBe('1024');
    const frames = find(root, 'export-frames');
    expect(frames.hidden).toBe(false);
    expect(frames.children.map((o) => o.value)).toEqual(['60']);
    // An earlier export's end is not what the panel says once the next starts.
    const earlier = { ...running, export: 'cd'.repeat(16) };
    panel.show({ ...earlier, state: 'done', progress: 1, url: '/exports/x', bytes: 5e6 });
    find(root, 'export-start').dispatchEvent(new Event('click'));
    expect(find(root, 'export-status').dataset['state']).toBe('starting');
    expect(find(root, 'export-link').hidden).toBe(true);
    await Promise.resolve();
    await Promise.resolve();
    expect(started).toEqual([{ kind: 'movie', width: 1024, height: 340, frames: 60, rock: 30 }]);
    panel.show({ ...running, frames: 60, progress: 0.5 });
    expect(find(root, 'export-status').textContent).toBe(
      'rendering 4096×2731… 50% (frame 31 of 60)',
    );
    panel.show({ ...running, frames: 60, state: 'done', progress: 1, bytes: 3_100_000 });
    expect(find(root, 'export-status').textContent).toBe('4096×2731 MP4, 60 frames, 3.1 MB');
    expect(exportText({ ...running, frames: 8, state: 'done', progress: 1, bytes: 41_200 })).toBe(
      '4096×2731 MP4, 8 frames, 41 kB',
    );
    panel.setLimits({ ...limits, max_movie_frames: 8 });
    expect(frames.children.map((o) => o.textContent)).toEqual(['8 frames (0.3 s)']);

    // A server that writes no movies offers none.
    panel.setLimits({ ...limits, max_movie_frames: 0 });
    expect(kind.children.map((o) => o.value)).toEqual(['still']);
    expect(kind.value).toBe('still');
    expect(find(root, 'export-frames').hidden).toBe(true);
  });

  it('lets the user start again once the connection is lost, and ignores a late status', () => {
    const root = new FakeElement('div');
    const panel = new ExportPanel({ $children: root } as unknown as GUI, {
      start: () => Promise.resolve(running),
      cancel: () => {},
      viewSize: () => [100, 100],
      downloadUrl: () => 'http://server/x',
    });
    panel.show(running);
    expect(find(root, 'export-start').disabled).toBe(true);
    panel.connectionEnded();
    expect(find(root, 'export-start').disabled).toBe(false);
    expect(find(root, 'export-cancel').hidden).toBe(true);
    expect(find(root, 'export-status').textContent).toBe(
      'stopped: the connection to the server was lost',
    );
    panel.show({ ...running, progress: 0.5 });
    expect(find(root, 'export-start').disabled).toBe(false);
    // An export that failed at once: its first status, come late, does not bring it back.
    const other = { ...running, export: 'ab'.repeat(16) };
    panel.show({ ...other, state: 'failed', error: { code: 'render_failed', message: 'gone' } });
    panel.show(other);
    expect(find(root, 'export-status').textContent).toBe('failed: gone');
  });

  it('says why the server refused to start one, and lets the user try again', async () => {
    const root = new FakeElement('div');
    const panel = new ExportPanel({ $children: root } as unknown as GUI, {
      start: () => Promise.reject(new Error('this client already has its 1 export(s) running')),
      cancel: () => {},
      viewSize: () => [100, 100],
      downloadUrl: () => undefined,
    });
    expect(panel).toBeDefined();
    find(root, 'export-start').dispatchEvent(new Event('click'));
    await new Promise((resolve) => setTimeout(resolve, 0));
    expect(find(root, 'export-status').textContent).toBe(
      'not started: this client already has its 1 export(s) running',
    );
    expect(find(root, 'export-start').disabled).toBe(false);
  });
});
