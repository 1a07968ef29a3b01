#!/usr/bin/env node
// The README's screenshot of the web client: a real `penumbra serve`, Debian's chromium driven by
// playwright-core, the ch2 head in sbrc_cone; with `cut`, the head CT of the demo folder cut open
// at the midline from the Cut panel.
//   node scripts/client-screenshot.mjs build/release/server/app/penumbra docs/images/client_sbrc_cone.png
//   node scripts/client-screenshot.mjs build/release/server/app/penumbra docs/images/client_cut.png cut
import { spawn } from 'node:child_process';
import { mkdtempSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const [penumbra, out, scene = 'modes'] = process.argv.slice(2);
if (!penumbra || !out || !['modes', 'cut'].includes(scene)) {
  console.error('usage: client-screenshot.mjs PENUMBRA OUT.png [modes|cut]');
  process.exit(2);
}
const clientDir = fileURLToPath(new URL('../client_web', import.meta.url));
const { chromium } = createRequire(path.join(clientDir, 'package.json'))('playwright-core');

const server = spawn(penumbra, ['serve', '--port', '0', '--web-root', path.join(clientDir, 'dist')],
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
  await page.goto(`${url}?volume=${scene === 'cut' ? 'cranium_ct.nrrd' : 'ch2.nii.gz'}`);
  await page.waitForFunction(() => document.querySelector('canvas.frame-canvas')?.dataset.frame !== undefined,
    null, { timeout: 120000 });
  if (scene === 'cut') {
    // The view from the left, the left half cropped away by the Cut panel's left face.
    await page.locator('.view-buttons button', { hasText: 'L' }).first().click();
    // Folders start open: close those above the Cut panel so that it shows.
    for (const title of ['Volume', 'Shared viewing', 'Transfer function', 'Light']) {
      await page.locator('.lil-gui .lil-title', { hasText: title }).first().click();
    }
    const left = page.locator('[data-control="crop-left"] input');
    await left.fill('122');
    await left.press('Enter');
    await page.waitForTimeout(500);
    await page.waitForFunction(
      () => /still/.test(document.querySelector('[data-stat="mode"]')?.textContent ?? ''), null,
      { timeout: 120000 });
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
