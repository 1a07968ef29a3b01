#!/usr/bin/env node
// The README's screenshot of the web client: a real `penumbra serve`, Debian's chromium driven by
// playwright-core, the ch2 head in sbrc_cone.
//   node scripts/client-screenshot.mjs build/release/server/app/penumbra docs/images/client_sbrc_cone.png
import { spawn } from 'node:child_process';
import { mkdtempSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const [penumbra, out] = process.argv.slice(2);
if (!penumbra || !out) {
  console.error('usage: client-screenshot.mjs PENUMBRA OUT.png');
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
  await page.goto(`${url}?volume=ch2.nii.gz`);
  await page.waitForFunction(() => document.querySelector('canvas.frame-canvas')?.dataset.frame !== undefined,
    null, { timeout: 120000 });
  await page.locator('[data-control="mode"] select').selectOption('sbrc_cone');
  await page.waitForFunction(
    () => document.querySelector('[data-stat="mode"]')?.textContent === 'sbrc_cone (still)', null,
    { timeout: 120000 });
  await page.screenshot({ path: out });
  console.log(`wrote ${out}`);
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
