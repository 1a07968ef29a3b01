#!/usr/bin/env node
// The README's screenshot of the web client: a real `penumbra serve`, Debian's chromium driven by
// playwright-core, the ch2 head in sbrc_cone; with `cut`, the head CT of the demo folder cut open
// at the midline by dragging the crop box's left face on the image; with `plane`, cut across the view from the left by the Cut
// panel's view plane and turned to show the cut; with `labels`, the AAL atlas added to ch2 in the
// Labels panel and drawn alone ("labels only") as lit surfaces, the left temporal lobe hidden.
//   node scripts/client-screenshot.mjs build/release/server/app/penumbra docs/images/client_sbrc_cone.png
//   node scripts/client-screenshot.mjs build/release/server/app/penumbra docs/images/client_cut.png cut
import { spawn } from 'node:child_process';
import { mkdtempSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const [penumbra, out, scene = 'modes'] = process.argv.slice(2);
if (!penumbra || !out || !['modes', 'cut', 'plane', 'labels'].includes(scene)) {
  console.error('usage: client-screenshot.mjs PENUMBRA OUT.png [modes|cut|plane|labels]');
  process.exit(2);
}
const clientDir = fileURLToPath(new URL('../client_web', import.meta.url));
const { chromium } = createRequire(path.join(clientDir, 'package.json'))('playwright-core');

const data = scene === 'labels' ? ['--data', '/usr/share/mricron/templates'] : [];
const server = spawn(penumbra,
  ['serve', '--port', '0', '--web-root', path.join(clientDir, 'dist'), ...data],
  { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((resolve, reject) => {
  let text = '';
  server.stdout.on('data', (d) => {
    text += d;
    const m = /serving:\s+(http:\/\/127\.0\.0\.1:\d+\/)/.exec(text);
    if (m) resolve(m[1]);
  });
  server.on('exit', () => reject(new Error(`penumbra serve exited:\n${text}`)));
});
/** Waits for the still that follows an interaction (its interactive frames come first). */
async function stillShown(page) {
  await page.waitForTimeout(500);
  await page.waitForFunction(
    () => /still/.test(document.querySelector('[data-stat="mode"]')?.textContent ?? ''), null,
    { timeout: 120000 });
}

const browser = await chromium.launchPersistentContext(
  mkdtempSync(path.join(tmpdir(), 'penumbra-shot-')), {
    executablePath: '/usr/bin/chromium',
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--disable-quic'],
    viewport: { width: 1100, height: 640 },
    deviceScaleFactor: 1,
  });
try {
  const page = browser.pages()[0] ?? (await browser.newPage());
  page.on('pageerror', (e) => console.error('page error:', String(e)));
  const volume = { modes: 'ch2.nii.gz', labels: 'ch2.nii.gz' }[scene] ?? 'cranium_ct.nrrd';
  await page.goto(`${url}?volume=${volume}`);
  await page.waitForFunction(() => document.querySelector('canvas.frame-canvas')?.dataset.frame !== undefined,
    null, { timeout: 120000 });
  if (scene === 'cut') {
    // From the left and a little in front and above, the crop box turned on and its left face
    // dragged by its handle on the image to the midline: the left half is cut away.
    await page.locator('.view-buttons button', { hasText: 'L' }).first().click();
    const canvas = await page.locator('canvas.frame-canvas').boundingBox();
    const cx = canvas.x + canvas.width / 2;
    const cy = canvas.y + canvas.height / 2;
    await page.mouse.move(cx, cy);
    await page.mouse.down();
    for (let i = 1; i <= 10; ++i) await page.mouse.move(cx + 8 * i, cy + 4 * i);
    await page.mouse.up();
    await stillShown(page);
    // Folders start open: close those above the Cut panel so that it shows.
    for (const title of ['Volume', 'Shared viewing', 'Transfer function', 'Light']) {
      await page.locator('.lil-gui .lil-title', { hasText: title }).first().click();
    }
    await page.locator('[data-control="crop"] input').check();
    const handle = async (face) => {
      const circle = page.locator(`circle.crop-box-handle[data-face="${face}"]`);
      await circle.waitFor();
      const b = await circle.boundingBox();
      return [b.x + b.width / 2, b.y + b.height / 2];
    };
    const [lx, ly] = await handle('left');
    const [rx, ry] = await handle('right');
    await page.mouse.move(lx, ly);
    await page.mouse.down();
    for (let i = 1; i <= 10; ++i) {
      await page.mouse.move(lx + (0.5 * (rx - lx) * i) / 10, ly + (0.5 * (ry - ly) * i) / 10);
    }
    await page.mouse.up();
    await stillShown(page);
  } else if (scene === 'plane') {
    // From the left, the view plane 20 mm to the right of the centre; then turned 60 degrees.
    await page.locator('.view-buttons button', { hasText: 'L' }).first().click();
    for (const title of ['Volume', 'Shared viewing', 'Transfer function', 'Light']) {
      await page.locator('.lil-gui .lil-title', { hasText: title }).first().click();
    }
    await page.locator('[data-control="clip-view"] button').click();
    const depth = page.locator('[data-control="plane-1-depth"] input');
    await depth.fill('20');
    await depth.press('Enter');
    const box = await page.locator('canvas.frame-canvas').boundingBox();
    const y = box.y + box.height / 2;
    await page.mouse.move(box.x + box.width / 2, y);
    await page.mouse.down();
    for (let i = 1; i <= 10; ++i) await page.mouse.move(box.x + box.width / 2 - 12 * i, y);
    await page.mouse.up();
    await stillShown(page);
  } else if (scene === 'labels') {
    // From the left, sbrc_cone; the atlas added and drawn alone; the left temporal lobe's
    // regions hidden (Temporal_*_L) to show the insula and the hemisphere behind.
    await page.locator('.view-buttons button', { hasText: 'L' }).first().click();
    await page.locator('[data-control="mode"] select').selectOption('sbrc_cone');
    for (const title of ['Volume', 'Shared viewing', 'Transfer function', 'Light', 'Cut']) {
      await page.locator('.lil-gui .lil-title', { hasText: title }).first().click();
    }
    await page.locator('[data-control="labels-add"]').selectOption('aal.nii.gz');
    await page.waitForFunction(
      () => /116 of 116 shown/.test(document.querySelector('[data-control="labels-count"]')?.textContent ?? ''),
      null, { timeout: 120000 });
    await page.locator('[data-control="labels-alone"]').check();
    await stillShown(page);
    await page.locator('[data-control="labels-search"]').fill('Temporal');
    for (const row of await page.locator('.label-row:visible').all()) {
      if ((await row.locator('.label-name').textContent()).endsWith('_L')) {
        await row.locator('input.label-visible').click();
      }
    }
    await page.locator('[data-control="labels-search"]').fill('Temporal_Mid_L');
    await stillShown(page);
  } else {
    await page.locator('[data-control="mode"] select').selectOption('sbrc_cone');
    await page.waitForFunction(
      () => document.querySelector('[data-stat="mode"]')?.textContent === 'sbrc_cone (still)', null,
      { timeout: 120000 });
  }
  await page.waitForTimeout(3000);  // the still's refinement
  await page.screenshot({ path: out });
  console.log(`wrote ${out}`);
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
