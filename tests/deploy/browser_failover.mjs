#!/usr/bin/env node
// The web client through the loopback cluster's nginx, over wss:// with the access token of its
// page's URL: an owner page opens a volume and picks a mode, a viewer page opens its share link;
// the replica that holds their session is killed (kill -9), and both pages must show frames again
// within 5 s, the owner's with its mode, the viewer's of the same session. cluster_test.py runs
// it with the cluster it started:
//
//   node browser_failover.mjs --client client_web --page 'https://127.0.0.1:PORT/?volume=V&token=T'
//        --replica PID:PORT --replica PID:PORT ...

import { createRequire } from 'node:module';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { parseArgs } from 'node:util';

const { values: options } = parseArgs({
  options: {
    client: { type: 'string' },
    page: { type: 'string' },
    replica: { type: 'string', multiple: true },
    chromium: { type: 'string', default: '/usr/bin/chromium' },
  },
});
const require = createRequire(path.join(path.resolve(options.client), 'package.json'));
const { chromium } = require('playwright-core');
const replicas = options.replica.map((r) => {
  const [pid, port] = r.split(':').map(Number);
  return { pid, port };
});

const started = Date.now();
const log = (...args) => console.log(`[browser ${((Date.now() - started) / 1000).toFixed(1)}s]`, ...args);
function check(name, ok, detail = '') {
  log(`${ok ? 'ok' : 'FAIL'}: ${name}${detail ? ` (${detail})` : ''}`);
  if (!ok) throw new Error(`check failed: ${name} ${detail}`);
}

async function frameInfo(page) {
  return page.evaluate(() => {
    const d = document.querySelector('canvas.frame-canvas')?.dataset ?? {};
    return { frame: Number(d.frame ?? -1), mode: d.mode, interactive: d.interactive };
  });
}

/** Waits for a still frame, in `mode` when given, newer than `after` (a frame number). */
async function waitForStill(page, { after = -1, mode, timeout = 30000 } = {}) {
  await page.waitForFunction(
    ({ after, mode }) => {
      const d = document.querySelector('canvas.frame-canvas')?.dataset;
      return d && d.frame !== undefined && Number(d.frame) !== after && d.interactive === 'false' &&
        (mode === undefined || d.mode === mode);
    },
    { after, mode },
    { timeout },
  );
  return frameInfo(page);
}

async function sessionsOf(port) {
  const text = await (await fetch(`http://127.0.0.1:${port}/metrics`)).text();
  const m = /^penumbra_sessions (\S+)$/m.exec(text);
  return m ? Number(m[1]) : 0;
}

const userDataDir = mkdtempSync(path.join(tmpdir(), 'penumbra-cluster-chromium-'));
let context;
let status = 0;
try {
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: options.chromium,
    headless: true,
    // The cluster's certificate is self-signed, made by nginx's entry point on first start.
    ignoreHTTPSErrors: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync'],
    viewport: { width: 640, height: 420 },
    deviceScaleFactor: 1,
  });
  const errors = [];
  const owner = context.pages()[0] ?? (await context.newPage());
  owner.on('pageerror', (e) => errors.push(`owner: ${String(e)}`));
  await owner.goto(options.page);
  await waitForStill(owner);
  await owner.locator('[data-control="mode"] select').selectOption('dvr');
  const before = await waitForStill(owner, { mode: 'dvr' });
  check('the owner page shows frames through nginx over wss:// with the token of its URL', true,
    `frame #${before.frame}`);

  const link = await owner.locator('#share-link').inputValue();
  check('the share link names the session, its volume and the token',
    /[?&]join=[0-9a-f]+/.test(link) && /[?&]volume=/.test(link) && /[?&]token=/.test(link), link);
  const viewer = await context.newPage();
  viewer.on('pageerror', (e) => errors.push(`viewer: ${String(e)}`));
  await viewer.goto(link);
  const watched = await waitForStill(viewer, { mode: 'dvr' });
  const role = await viewer.locator('.role').textContent();
  check('the viewer page watches the session', role.includes('read-only'), role);

  const holders = [];
  for (const r of replicas) {
    if ((await sessionsOf(r.port).catch(() => 0)) > 0) holders.push(r);
  }
  check('one replica holds the session', holders.length === 1, `${holders.length}`);
  process.kill(holders[0].pid, 'SIGKILL');
  const killedAt = Date.now();

  await Promise.all([
    owner.locator('.notice.info', { hasText: 'Reconnected' }).waitFor({ timeout: 10000 }),
    waitForStill(owner, { after: before.frame, mode: 'dvr', timeout: 10000 }),
  ]);
  const ownerSeconds = (Date.now() - killedAt) / 1000;
  const notice = await owner.locator('.notice.info', { hasText: 'Reconnected' }).textContent();
  check('the owner page re-created its session on another replica, mode kept',
    /re-opened on another/.test(notice), notice);
  await waitForStill(viewer, { after: watched.frame, mode: 'dvr', timeout: 10000 });
  const viewerSeconds = (Date.now() - killedAt) / 1000;
  check('the viewer page follows its owner to the same session',
    (await viewer.locator('.role').textContent()) === role, role);
  check(`the owner page has frames again within 5 s`, ownerSeconds <= 5, `${ownerSeconds.toFixed(2)} s`);
  check(`the viewer page has frames again within 5 s`, viewerSeconds <= 5, `${viewerSeconds.toFixed(2)} s`);
  check('no uncaught page errors', errors.length === 0, errors.join(' | '));
  console.log(`browser reconnect after kill -9: owner ${ownerSeconds.toFixed(2)} s, viewer ${viewerSeconds.toFixed(2)} s`);
} catch (e) {
  log(`FAIL: ${e instanceof Error ? e.message : String(e)}`);
  status = 1;
} finally {
  await context?.close().catch(() => {});
  rmSync(userDataDir, { recursive: true, force: true });
}
process.exit(status);
