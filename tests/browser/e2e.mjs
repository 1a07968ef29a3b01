#!/usr/bin/env node
// End-to-end test of the web client: Debian's chromium (driven by playwright-core) against a real
// `penumbra serve` on 127.0.0.1 with a free port. The page loads, a frame appears, dragging changes
// it and turns the orientation marker, the preset list is hello's and a preset changes the frame,
// the six view buttons set the named views, a portrait tablet gets the panel as a drawer, the Cut
// panel crops, clips at the view plane and resets on a desktop and in the tablet's drawer,
// changing the mode changes the stats, a bad parameter shows the
// server's error, the sliders span hello's ranges, every numeric setting hello announces has a
// labelled control in its part's folder and empty-space skipping toggles, the light's sliders reach
// hello's ends and its position stays within the server's coordinates, the Labels panel draws the
// AAL atlas (its 116 labels listed, a search, one label shown alone, in the tablet's drawer too)
// and a tap on the frame says what lies there, a second page joins through the share link, its
// method and labels panels follow the owner and it sees the same frame, and after the server goes
// away and comes back the client reconnects and restores the session, its label map with it.
// Screenshots go to --out.
//
//   node tests/browser/e2e.mjs --penumbra build/release/server/app/penumbra \
//        --client client_web --out build/release/tests/browser/screenshots
//
// The client must be built (client_web/dist) and its node_modules installed (npm ci).

import { spawn } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';

const { values: options } = parseArgs({
  options: {
    penumbra: { type: 'string' },
    client: { type: 'string', default: fileURLToPath(new URL('../../client_web', import.meta.url)) },
    out: { type: 'string', default: 'browser-screenshots' },
    data: { type: 'string', default: '/usr/share/mricron/templates' },
    volume: { type: 'string', default: 'ch2.nii.gz' },
    chromium: { type: 'string', default: '/usr/bin/chromium' },
  },
});
if (!options.penumbra) {
  console.error('usage: e2e.mjs --penumbra PATH [--client DIR] [--out DIR] [--data DIR]');
  process.exit(2);
}
if (!existsSync(options.chromium)) {
  console.error(`no chromium at ${options.chromium}: apt-get install chromium (scripts/install-deps.sh)`);
  process.exit(1);
}
const clientDir = path.resolve(options.client);
const outDir = path.resolve(options.out);
mkdirSync(outDir, { recursive: true });
rmSync(path.join(outDir, 'failure.png'), { force: true });
const require = createRequire(path.join(clientDir, 'package.json'));
const { chromium } = require('playwright-core');

const started = Date.now();
const log = (...args) => console.log(`[${((Date.now() - started) / 1000).toFixed(1)}s]`, ...args);

// ---- the server ----------------------------------------------------------------------------------
const servers = new Set();

function startServer(port = 0) {
  const child = spawn(
    options.penumbra,
    ['serve', '--port', String(port), '--address', '127.0.0.1', '--data', options.data,
     '--web-root', path.join(clientDir, 'dist'),
     // Movies small enough for llvmpipe: the panel offers what the server's hello allows.
     '--max-movie-side', '128', '--max-movie-frames', '8'],
    { stdio: ['ignore', 'pipe', 'pipe'] },
  );
  servers.add(child);
  let output = '';
  child.stderr.on('data', (d) => (output += d));
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`penumbra serve did not start:\n${output}`)), 60000);
    child.stdout.on('data', (d) => {
      output += d;
      const m = /serving:\s+(http:\/\/127\.0\.0\.1:(\d+)\/)/.exec(output);
      if (m) {
        clearTimeout(timer);
        resolve({ child, url: m[1], port: Number(m[2]), output: () => output });
      }
    });
    child.on('exit', (code, signal) => {
      servers.delete(child);
      clearTimeout(timer);
      reject(new Error(`penumbra serve exited (${code ?? signal}):\n${output}`));
    });
  });
}

function stopServer(child) {
  return new Promise((resolve) => {
    if (child.exitCode !== null || child.signalCode !== null) return resolve();
    const kill = setTimeout(() => child.kill('SIGKILL'), 5000);
    child.once('exit', () => {
      clearTimeout(kill);
      servers.delete(child);
      resolve();
    });
    child.kill('SIGTERM');
  });
}

const killAll = () => {
  for (const child of servers) child.kill('SIGKILL');
};
process.on('exit', killAll);
for (const signal of ['SIGINT', 'SIGTERM']) {
  process.on(signal, () => {
    killAll();
    process.exit(1);
  });
}

// ---- page helpers --------------------------------------------------------------------------------
/** Downsampled grey image of the frame canvas and the fraction of pixels that are not background. */
async function canvasSignature(page) {
  return page.evaluate(() => {
    const canvas = document.querySelector('canvas.frame-canvas');
    const ctx = canvas.getContext('2d');
    const { width, height } = canvas;
    const data = ctx.getImageData(0, 0, width, height).data;
    const n = 32;
    const grid = new Array(n * n).fill(0);
    const counts = new Array(n * n).fill(0);
    let lit = 0;
    for (let y = 0; y < height; ++y) {
      for (let x = 0; x < width; ++x) {
        const k = (y * width + x) * 4;
        const grey = (data[k] + data[k + 1] + data[k + 2]) / 3;
        if (grey > 24) lit += 1;
        const cell = Math.floor((y * n) / height) * n + Math.floor((x * n) / width);
        grid[cell] += grey;
        counts[cell] += 1;
      }
    }
    // The frame number read with the pixels: refinement steps replace the still on screen.
    const frame = Number(canvas.dataset.frame ?? -1);
    const encoding = canvas.dataset.encoding;
    return { grid: grid.map((g, i) => g / Math.max(1, counts[i])), lit: lit / (width * height), width, height, frame, encoding };
  });
}

// The two pages' signatures of one frame: each is read with its frame number, until both show the
// same frame (a still's refinement steps reach the two pages at slightly different times).
async function sameFrameSignatures(first, second, tries = 80) {
  let a;
  let b;
  for (let i = 0; i < tries; ++i) {
    [a, b] = [await canvasSignature(first), await canvasSignature(second)];
    if (a.frame === b.frame) break;
    await first.waitForTimeout(250);
  }
  return [a, b];
}

function difference(a, b) {
  let sum = 0;
  for (let i = 0; i < a.grid.length; ++i) sum += Math.abs(a.grid[i] - b.grid[i]);
  return sum / a.grid.length;
}

async function frameInfo(page) {
  return page.evaluate(() => {
    const d = document.querySelector('canvas.frame-canvas')?.dataset ?? {};
    return {
      frame: Number(d.frame ?? -1),
      request: Number(d.request ?? -1),
      mode: d.mode,
      interactive: d.interactive,
      size: d.size,
    };
  });
}

// Waits for a still frame asked for after the frame `after` (a frameInfo, or null for any still).
// Refinement steps carry the request of the still they refine, so a step of the new still counts
// and a step of an earlier still does not; the still itself may never be shown, since the view
// skips a frame that a newer one replaces while it decodes. A preview (a costly still's smaller
// first frame) is not the still.
async function waitForStill(page, after = null, timeout = 30000) {
  await page.waitForFunction(
    (afterRequest) => {
      const d = document.querySelector('canvas.frame-canvas')?.dataset;
      return d && d.request !== undefined && Number(d.request) > afterRequest &&
        d.interactive === 'false' && d.preview !== 'true';
    },
    after ? after.request : -1,
    { timeout },
  );
  // Let a later frame that is already on its way land, so "the" frame is stable.
  await page.waitForTimeout(300);
  return frameInfo(page);
}

/** The topmost row of the frame (CSS pixels from the view's top) that shows the head. */
async function topmostLitRow(page) {
  return page.evaluate(() => {
    const canvas = document.querySelector('canvas.frame-canvas');
    const { width, height } = canvas;
    const data = canvas.getContext('2d').getImageData(0, 0, width, height).data;
    for (let y = 0; y < height; ++y) {
      for (let x = 0; x < width; ++x) {
        const k = (y * width + x) * 4;
        if ((data[k] + data[k + 1] + data[k + 2]) / 3 > 24) {
          return (y * canvas.getBoundingClientRect().height) / height;
        }
      }
    }
    return null;
  });
}

/** The crop box as drawn over the image: its corners' y (CSS pixels) and each shown handle. */
async function cropBoxOnScreen(page) {
  return page.evaluate(() => {
    const svg = document.querySelector('svg.crop-box-overlay');
    const d = svg?.querySelector('path')?.getAttribute('d') ?? '';
    // Each corner is written once per edge through it, always alike.
    const corners = new Set([...d.matchAll(/[ML]([-\d.]+,[-\d.]+)/g)].map((m) => m[1]));
    const ys = [...corners].map((corner) => Number(corner.split(',')[1]));
    const handles = {};
    for (const c of svg?.querySelectorAll('circle') ?? []) {
      if (c.style.display !== 'none') handles[c.dataset.face] = [Number(c.getAttribute('cx')), Number(c.getAttribute('cy'))];
    }
    return { shown: !!svg && svg.style.display !== 'none', corners: ys.sort((a, b) => a - b), handles };
  });
}

/** Drags from (x, y) down by `dy` CSS pixels in steps, with the mouse or (touch) a finger. */
async function dragDown(page, x, y, dy, touch = null) {
  const steps = 8;
  if (touch) {
    await touch.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [{ x, y }] });
    for (let i = 1; i <= steps; ++i) {
      await touch.send('Input.dispatchTouchEvent',
        { type: 'touchMove', touchPoints: [{ x, y: y + (dy * i) / steps }] });
    }
    await touch.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
    return;
  }
  await page.mouse.move(x, y);
  await page.mouse.down();
  for (let i = 1; i <= steps; ++i) await page.mouse.move(x, y + (dy * i) / steps);
  await page.mouse.up();
}

/** Which patient label the orientation marker shows furthest right and furthest up. */
async function markerAxes(page) {
  return page.evaluate(() => {
    const d = document.querySelector('svg.orientation-marker')?.dataset ?? {};
    return `${d.screenRight ?? '?'}${d.screenUp ?? '?'}`;
  });
}

/** What the Labels panel says it shows: "3 of 116 shown". */
async function labelsShown(page) {
  return (await page.locator('[data-control="labels-count"]').textContent()) ?? '';
}

/** Waits until the Labels panel shows `text` (the state the server answered with). */
async function waitForLabelsShown(page, text, timeout = 15000) {
  await page.waitForFunction(
    (t) => document.querySelector('[data-control="labels-count"]')?.textContent?.endsWith(t),
    text, { timeout });
}

/** Scrolls the panel (or the drawer) to the Labels folder's title, for a screenshot. */
async function showLabelsFolder(page) {
  await page.locator('.labels-panel').evaluate((e) => e.closest('.lil-gui').scrollIntoView());
}

/** Taps (clicks) the frame at fractions (fx, fy) of the canvas and waits for the pick's answer. */
async function pickAt(page, fx, fy) {
  const box = await page.locator('canvas.frame-canvas').boundingBox();
  await page.mouse.click(box.x + box.width * fx, box.y + box.height * fy);
  await page.waitForFunction(() => {
    const callout = document.querySelector('.pick-callout');
    return callout && !callout.closest('[hidden]') && callout.dataset.state !== 'pending';
  }, null, { timeout: 15000 });
  return page.evaluate(() => {
    const callout = document.querySelector('.pick-callout');
    return { state: callout.dataset.state, label: callout.dataset.label, text: callout.textContent };
  });
}

async function statText(page, key) {
  return page.locator(`[data-stat="${key}"]`).textContent();
}

// ---- the test ------------------------------------------------------------------------------------
const checks = [];
function check(name, ok, detail = '') {
  checks.push({ name, ok });
  log(`${ok ? 'PASS' : 'FAIL'} ${name}${detail ? `: ${detail}` : ''}`);
  if (!ok) throw new Error(`check failed: ${name} ${detail}`);
}

let context;
let owner;
const userDataDir = mkdtempSync(path.join(tmpdir(), 'penumbra-e2e-chromium-'));
let failed = false;
try {
  let server = await startServer(0);
  log(`server at ${server.url}`);

  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: options.chromium,
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--disable-quic'],
    viewport: { width: 900, height: 560 },
    deviceScaleFactor: 1,
  });
  owner = context.pages()[0] ?? (await context.newPage());
  const consoleErrors = [];
  const pageErrors = [];
  owner.on('pageerror', (e) => {
    consoleErrors.push(String(e));
    pageErrors.push(String(e));
  });
  owner.on('console', (m) => m.type() === 'error' && consoleErrors.push(m.text()));

  // 1. The page loads and a frame appears.
  await owner.addInitScript(() => {
    window.__badgeTexts = [];
    new MutationObserver(() => {
      const badge = document.querySelector('.refinement-badge');
      const text = badge && !badge.hidden ? badge.textContent : '';
      if (text && window.__badgeTexts.at(-1) !== text) window.__badgeTexts.push(text);
    }).observe(document, { subtree: true, childList: true, attributes: true, characterData: true });
  });
  // JPEG frames for the checks below that read them (the page's choice; the default is H.264
  // where the browser decodes it: checked on a page of its own in 4b).
  await owner.goto(`${server.url}?volume=${encodeURIComponent(options.volume)}&encoding=jpeg`);
  let info = await waitForStill(owner, null, 60000);
  let first = await canvasSignature(owner);
  await owner.screenshot({ path: path.join(outDir, '01_loaded.png') });
  check('a frame appears and the canvas is not blank', first.lit > 0.02,
    `frame ${info.frame} ${info.size} mode ${info.mode}, ${(first.lit * 100).toFixed(1)}% lit`);
  check('the stats overlay shows the frame', /#\d+/.test(await statText(owner, 'frame')));
  // A new session's stills refine: the corner says so while they do, then that the still is done
  // (every text the badge showed is recorded from the page's start: see badgeTexts).
  await owner.waitForFunction(() => window.__badgeTexts.some((t) => t.startsWith('still done')),
    null, { timeout: 120000 }).catch(() => {});
  const badgeTexts = await owner.evaluate(() => window.__badgeTexts);
  const doneAt = badgeTexts.findIndex((t) => /^still done · \d+ steps?$/.test(t));
  check('the still refines and then says it is done',
    doneAt > 0 && badgeTexts.slice(0, doneAt).some((t) => t.startsWith('refining…')),
    badgeTexts.join(' → '));
  // The default camera looks at the face: the patient's left on the right, superior up.
  check('the orientation marker shows the anterior view', (await markerAxes(owner)) === 'LS',
    await markerAxes(owner));

  // 2. Dragging changes the frame, with interactive frames during the drag.
  await owner.evaluate(() => {
    window.__interactiveSeen = false;
    const canvas = document.querySelector('canvas.frame-canvas');
    new MutationObserver(() => {
      if (canvas.dataset.interactive === 'true') window.__interactiveSeen = true;
    }).observe(canvas, { attributes: true });
  });
  const box = await owner.locator('canvas.frame-canvas').boundingBox();
  const cx = box.x + box.width / 2;
  const cy = box.y + box.height / 2;
  await owner.mouse.move(cx, cy);
  await owner.mouse.down();
  for (let i = 1; i <= 12; ++i) {
    await owner.mouse.move(cx + i * 12, cy + i * 2);
    await owner.waitForTimeout(60);
  }
  await owner.mouse.up();
  info = await waitForStill(owner, info);
  const dragged = await canvasSignature(owner);
  await owner.screenshot({ path: path.join(outDir, '02_dragged.png') });
  check('dragging changes the frame', difference(first, dragged) > 2,
    `mean grey difference ${difference(first, dragged).toFixed(1)}`);
  check('frames were interactive during the drag and still after',
    (await owner.evaluate(() => window.__interactiveSeen)) && info.interactive === 'false');
  check('the orientation marker turns with the camera', (await markerAxes(owner)) !== 'LS',
    await markerAxes(owner));

  // 2b. Dragging the light on its sphere and an opacity point of the transfer function change it.
  let before = await canvasSignature(owner);
  const sphere = await owner.locator('[data-control="light-sphere"]').boundingBox();
  await owner.mouse.move(sphere.x + sphere.width * 0.5, sphere.y + sphere.height * 0.3);
  await owner.mouse.down();
  await owner.mouse.move(sphere.x + sphere.width * 0.15, sphere.y + sphere.height * 0.5, { steps: 5 });
  await owner.mouse.up();
  info = await waitForStill(owner, info);
  let after = await canvasSignature(owner);
  check('dragging the light changes the frame', difference(before, after) > 1,
    `mean grey difference ${difference(before, after).toFixed(1)}`);
  await owner.screenshot({ path: path.join(outDir, '02b_light.png') });

  before = after;
  const curve = await owner.locator('[data-control="tf-curve"]').boundingBox();
  // mri_skin's point at x 0.2, alpha 0.6: pull it down to nearly transparent.
  await owner.mouse.move(curve.x + curve.width * 0.2, curve.y + curve.height * 0.4);
  await owner.mouse.down();
  await owner.mouse.move(curve.x + curve.width * 0.2, curve.y + curve.height * 0.97, { steps: 5 });
  await owner.mouse.up();
  info = await waitForStill(owner, info);
  after = await canvasSignature(owner);
  check('dragging an opacity point changes the frame', difference(before, after) > 1,
    `mean grey difference ${difference(before, after).toFixed(1)}, lit ${(after.lit * 100).toFixed(1)}%`);
  await owner.screenshot({ path: path.join(outDir, '02c_transfer_function.png') });

  // 2d. The preset list is the server's (its hello's presets), and picking one shows it.
  const presetNames = await owner.evaluate(
    (url) =>
      new Promise((resolve, reject) => {
        const ws = new WebSocket(url);
        ws.onmessage = (e) => {
          resolve(JSON.parse(e.data).presets.map((p) => p.name));
          ws.close();
        };
        ws.onerror = () => reject(new Error('no hello'));
      }),
    `${server.url.replace(/^http/, 'ws')}ws?volume=${encodeURIComponent(options.volume)}`,
  );
  const offered = await owner.locator('[data-control="tf-preset"] select option').evaluateAll((els) =>
    els.map((e) => e.value));
  check("the preset list offers hello's presets",
    offered.length > 0 && [...offered].sort().join() === [...presetNames].sort().join(), offered.join(', '));
  before = after;
  await owner.locator('[data-control="tf-preset"] select').selectOption('grey_ramp');
  info = await waitForStill(owner, info);
  after = await canvasSignature(owner);
  check('picking a preset changes the frame', difference(before, after) > 1,
    `mean grey difference ${difference(before, after).toFixed(1)}`);
  await owner.screenshot({ path: path.join(outDir, '02d_preset.png') });

  // 3. Changing the mode changes the stats.
  const passesBefore = await owner.locator('[data-stat^="pass:"]').count();
  const lightBefore = await statText(owner, 'light_buffer');
  await owner.locator('[data-control="mode"] select').selectOption('dvr');
  await owner.waitForFunction(() =>
    document.querySelector('[data-stat="mode"]')?.textContent === 'dvr (still)', null, { timeout: 30000 });
  const lightAfter = await statText(owner, 'light_buffer');
  const passNames = await owner.locator('[data-stat^="pass:"]').evaluateAll((els) =>
    els.map((e) => e.dataset.stat));
  await owner.screenshot({ path: path.join(outDir, '03_mode_dvr.png') });
  check('changing the mode changes the stats',
    lightBefore !== 'none' && lightAfter === 'none' && !passNames.some((p) => p.includes('light_buffer')),
    `light buffer ${lightBefore} -> ${lightAfter}; passes ${passesBefore} -> ${passNames.join(', ')}`);

  // 3b. The view buttons set the named views: the marker says which side faces the viewer, and
  // each view is its own image.
  const expectedAxes = { anterior: 'LS', posterior: 'RS', left: 'PS', right: 'AS', superior: 'RA',
                         inferior: 'LA' };
  const viewImages = {};
  for (const [name, axes] of Object.entries(expectedAxes)) {
    await owner.locator(`.view-buttons button[data-view="${name}"]`).click();
    info = await waitForStill(owner, info);
    viewImages[name] = await canvasSignature(owner);
    check(`the ${name} view button sets the ${name} view`, (await markerAxes(owner)) === axes,
      `marker ${await markerAxes(owner)}, ${(viewImages[name].lit * 100).toFixed(1)}% lit`);
  }
  await owner.screenshot({ path: path.join(outDir, '03b_view_inferior.png') });
  check('the named views show different sides of the head',
    difference(viewImages.anterior, viewImages.posterior) > 2 &&
      difference(viewImages.left, viewImages.right) > 2 &&
      difference(viewImages.superior, viewImages.anterior) > 2,
    `anterior/posterior ${difference(viewImages.anterior, viewImages.posterior).toFixed(1)}, ` +
      `left/right ${difference(viewImages.left, viewImages.right).toFixed(1)}`);
  await owner.locator('.view-buttons button[data-view="anterior"]').click();
  info = await waitForStill(owner, info);

  // 3c. On a portrait tablet the view fills the screen and the panel folds into a drawer.
  await owner.setViewportSize({ width: 768, height: 1024 });
  await owner.waitForTimeout(400);
  const viewBox = await owner.locator('#view').boundingBox();
  const panelClosed = await owner.locator('#panel').boundingBox();
  await owner.screenshot({ path: path.join(outDir, '03c_portrait.png') });
  check('on a portrait tablet the view fills the screen',
    viewBox.width >= 760 && viewBox.height >= 1000 && !(await owner.locator('#panel').isVisible()),
    `view ${viewBox.width}x${viewBox.height}, panel at x ${panelClosed?.x}`);
  await owner.locator('.drawer-toggle').click();
  await owner.waitForTimeout(400);
  const panelOpen = await owner.locator('#panel').boundingBox();
  await owner.screenshot({ path: path.join(outDir, '03d_portrait_drawer.png') });
  check('the drawer opens over the view',
    (await owner.locator('#panel').isVisible()) && panelOpen.x + panelOpen.width <= 769 &&
      panelOpen.x >= 768 - 330 && (await owner.locator('[data-control="mode"] select').isVisible()),
    `panel at x ${panelOpen.x}, ${panelOpen.width} wide`);
  // The Cut panel works in the drawer: its view plane, tapped there, cuts the head across the
  // view; its reset brings it back.
  // The baseline is a still of the portrait view: a reset of the (uncut) cut asks for one.
  await owner.locator('[data-control="cut-reset"] button').click();
  info = await waitForStill(owner, info);
  const beforeTabletCut = await canvasSignature(owner);
  await owner.locator('[data-control="clip-view"] button').click();
  info = await waitForStill(owner, info);
  const tabletCut = await canvasSignature(owner);
  await owner.screenshot({ path: path.join(outDir, '03e_portrait_clip_plane.png') });
  check('in the drawer, clip at the view plane cuts the head',
    (await owner.locator('[data-control="plane-1"]').isVisible()) &&
      difference(beforeTabletCut, tabletCut) > 2,
    `difference ${difference(beforeTabletCut, tabletCut).toFixed(1)}`);
  await owner.locator('[data-control="cut-reset"] button').click();
  info = await waitForStill(owner, info);
  check('and the reset in the drawer brings the whole head back',
    difference(beforeTabletCut, await canvasSignature(owner)) < 1.5 &&
      !(await owner.locator('[data-control="plane-1"]').isVisible()),
    `difference ${difference(beforeTabletCut, await canvasSignature(owner)).toFixed(1)}`);
  // The crop box's handles take a finger: the crop turned on in the drawer, the drawer closed,
  // the superior handle dragged down by touch cuts the head.
  await owner.locator('[data-control="crop"] input').check();
  info = await waitForStill(owner, info);
  await owner.locator('.drawer-toggle').click();
  await owner.waitForTimeout(400);
  const touch = await context.newCDPSession(owner);
  await touch.send('Emulation.setTouchEmulationEnabled', { enabled: true, maxTouchPoints: 2 });
  const tabletBox = await cropBoxOnScreen(owner);
  const beforeTouch = await canvasSignature(owner);
  const tabletTop = (await owner.locator('#view').boundingBox()).y;
  await dragDown(owner, tabletBox.handles.superior[0], tabletTop + tabletBox.handles.superior[1], 160,
    touch);
  info = await waitForStill(owner, info);
  const touched = await cropBoxOnScreen(owner);
  await owner.screenshot({ path: path.join(outDir, '03e_portrait_crop_box.png') });
  check('on the tablet a finger drags the superior face down and the head is cut',
    Math.abs(touched.handles.superior[1] - (tabletBox.handles.superior[1] + 160)) < 2 &&
      difference(beforeTouch, await canvasSignature(owner)) > 1,
    `handle ${tabletBox.handles.superior[1]} -> ${touched.handles.superior[1]}`);
  await touch.send('Emulation.setTouchEmulationEnabled', { enabled: false });
  await touch.detach();
  await owner.locator('.drawer-toggle').click();
  await owner.waitForTimeout(400);
  await owner.locator('[data-control="cut-reset"] button').click();
  info = await waitForStill(owner, info);
  await owner.locator('.drawer-toggle').click();
  await owner.waitForTimeout(400);
  check('and closes again', !(await owner.locator('#panel').isVisible()));
  await owner.setViewportSize({ width: 900, height: 560 });
  await owner.waitForTimeout(400);
  check('wider than tall, the panel is beside the view again',
    (await owner.locator('#panel').isVisible()) && !(await owner.locator('.drawer-toggle').isVisible()));
  info = await waitForStill(owner, null);

  // 3d. The Cut panel on a desktop: a crop face moved in cuts the head, the view plane cuts away
  // what lies before it, its depth moves it, and each change is a still the server keeps.
  const uncut = await canvasSignature(owner);
  const cropLeft = owner.locator('[data-control="crop-left"] input');
  await cropLeft.fill('0');
  await cropLeft.press('Enter');
  info = await waitForStill(owner, info);
  const cropped = await canvasSignature(owner);
  await owner.screenshot({ path: path.join(outDir, '03f_crop.png') });
  check('a crop face moved in cuts the head and turns the crop on',
    difference(uncut, cropped) > 2 &&
      (await owner.locator('[data-control="crop"] input').isChecked()),
    `difference ${difference(uncut, cropped).toFixed(1)}`);
  await owner.locator('[data-control="cut-reset"] button').click();
  info = await waitForStill(owner, info);
  await owner.locator('[data-control="clip-view"] button').click();
  info = await waitForStill(owner, info);
  const planed = await canvasSignature(owner);
  check('clip at the view plane adds plane 1 and cuts the head across the view',
    (await owner.locator('[data-control="plane-1"] input').isChecked()) &&
      difference(uncut, planed) > 2 && difference(cropped, planed) > 2,
    `difference ${difference(uncut, planed).toFixed(1)}`);
  const depth = owner.locator('[data-control="plane-1-depth"] input');
  await depth.fill('40');
  await depth.press('Enter');
  info = await waitForStill(owner, info);
  const deeper = await canvasSignature(owner);
  await owner.screenshot({ path: path.join(outDir, '03g_clip_plane.png') });
  check('its depth moves the cut', difference(planed, deeper) > 1,
    `difference ${difference(planed, deeper).toFixed(1)}`);
  await owner.locator('[data-control="plane-1"] input').click();
  info = await waitForStill(owner, info);
  check('turned off, the plane cuts nothing',
    difference(uncut, await canvasSignature(owner)) < 1.5,
    `difference ${difference(uncut, await canvasSignature(owner)).toFixed(1)}`);
  await owner.locator('[data-control="cut-reset"] button').click();
  info = await waitForStill(owner, info);

  // 3e. The crop box on the image: with the crop on it is drawn around the head, a handle on each
  // face that lies across the view (seen from the front, not the anterior and posterior ones); the
  // superior face's handle dragged down stays under the pointer, moves the box's top face down
  // and cuts the head off where that face now lies on the image; a still follows.
  await owner.locator('[data-control="crop"] input').check();
  info = await waitForStill(owner, info);
  const boxShown = await cropBoxOnScreen(owner);
  check('with the crop on, the box is drawn with a handle on each face across the view',
    boxShown.shown && boxShown.corners.length === 8 &&
      Object.keys(boxShown.handles).sort().join(' ') === 'inferior left right superior',
    `handles ${Object.keys(boxShown.handles).join(' ')}`);
  const superiorInput = owner.locator('[data-control="crop-superior"] input');
  const superiorBefore = Number(await superiorInput.inputValue());
  const uncutTop = await topmostLitRow(owner);
  const viewTop = (await owner.locator('#view').boundingBox()).y;
  const [hx, hy] = boxShown.handles.superior;
  await dragDown(owner, hx, viewTop + hy, 64);
  info = await waitForStill(owner, info);
  const superiorAfter = Number(await superiorInput.inputValue());
  const boxAfter = await cropBoxOnScreen(owner);
  const topRow = await topmostLitRow(owner);
  // Seen from the front with the eye below it, the top face's four corners are the box's highest
  // on the image: the head's cut top lies between its near and far edges.
  const [nearTop, , , farTop] = boxAfter.corners;
  await owner.screenshot({ path: path.join(outDir, '03h_crop_box_dragged.png') });
  check('the superior handle dragged down moves the top face down and stays under the pointer',
    superiorAfter < superiorBefore - 10 && Math.abs(boxAfter.handles.superior[1] - (hy + 64)) < 2,
    `superior ${superiorBefore} -> ${superiorAfter} mm, handle at ${boxAfter.handles.superior[1]}`);
  check('and the head is cut off where the top face of the box lies on the image',
    topRow !== null && topRow > uncutTop + 5 && topRow >= nearTop - 3 && topRow <= farTop + 3,
    `head's top from ${uncutTop?.toFixed(1)} to ${topRow?.toFixed(1)}, top face from ${nearTop} to ${farTop}`);
  await owner.locator('[data-control="cut-reset"] button').click();
  info = await waitForStill(owner, info);
  check('the reset hides the box', !(await cropBoxOnScreen(owner)).shown);

  // 4. A bad parameter shows the server's error.
  const sampleDistance = owner.locator('[data-control="sample_distance"] input');
  await sampleDistance.fill('5');
  await sampleDistance.press('Enter');
  const notice = owner.locator('.notice.error', { hasText: '/settings/sample_distance' });
  await notice.first().waitFor({ timeout: 15000 });
  const noticeText = await notice.first().textContent();
  await owner.screenshot({ path: path.join(outDir, '04_server_error.png') });
  check("a bad parameter shows the server's error", /out_of_range/.test(noticeText), noticeText);
  check('the field shows the value the server kept',
    Number(await sampleDistance.inputValue()) < 1, await sampleDistance.inputValue());
  await notice.first().locator('button.close').click();
  check('a notice closes', (await notice.count()) === 0);

  // 4b. The sliders span the ranges the server's hello announces (the client has none of its
  // own): a value past the end stops at it. Empty-space skipping is a toggle the server takes.
  const slabSamples = owner.locator('[data-control="slab_samples"] input');
  await slabSamples.fill('99');
  await slabSamples.press('Enter');
  check('a slider stops at the end of the range hello announced',
    (await owner.locator('[data-control="slab_samples"] .lil-slider').count()) === 1 &&
      (await slabSamples.inputValue()) === '16', await slabSamples.inputValue());
  await slabSamples.fill('0');
  await slabSamples.press('Enter');
  info = await waitForStill(owner, info);
  const skipping = owner.locator('[data-control="empty_space_skipping"] input');
  const skippingBefore = await skipping.isChecked();
  await skipping.click();
  info = await waitForStill(owner, info);
  check('empty-space skipping toggles and the server keeps it',
    skippingBefore && !(await skipping.isChecked()) &&
      (await owner.locator('.notice.error', { hasText: 'empty_space_skipping' }).count()) === 0,
    `checked ${skippingBefore} -> ${await skipping.isChecked()}`);
  await skipping.click();
  info = await waitForStill(owner, info);
  // H.264: the Image folder's encoding set to h264 (offered: this browser has WebCodecs), the
  // frames come as one stream that VideoDecoder decodes in order, the same picture as JPEG's; the
  // still's last refinement step comes as a JPEG.
  const jpegLook = await canvasSignature(owner);
  await owner.locator('[data-control="encoding"] select').selectOption('h264');
  await owner.waitForFunction(
    () => document.querySelector('canvas.frame-canvas')?.dataset.encoding === 'h264', null,
    { timeout: 30000 });
  const h264Look = await canvasSignature(owner);
  check('H.264 frames decode with WebCodecs and show the picture the JPEG frames showed',
    h264Look.encoding === 'h264' && difference(jpegLook, h264Look) < 2 &&
      (await owner.locator('.notice.error', { hasText: 'encoding' }).count()) === 0,
    `${h264Look.encoding}: mean grey difference ${difference(jpegLook, h264Look).toFixed(2)}`);
  const endedAsJpeg = await owner.waitForFunction(() => {
    const d = document.querySelector('canvas.frame-canvas')?.dataset;
    return d?.encoding === 'jpeg' && d.interactive === 'false' && d.refining === 'false';
  }, null, { timeout: 60000 }).then(() => true, () => false);
  check('on an H.264 stream the still ends as a JPEG, the stream still H.264',
    endedAsJpeg &&
      (await owner.locator('[data-control="encoding"] select').inputValue()) === 'h264');
  info = await waitForStill(owner, info);
  // Back to JPEG: the refinement steps come as JPEG too (an H.264 stream sends them as H.264).
  await owner.locator('[data-control="encoding"] select').selectOption('jpeg');
  await owner.waitForFunction(() => {
    const d = document.querySelector('canvas.frame-canvas')?.dataset;
    return d?.encoding === 'jpeg' && d.refining === 'true';
  }, null, { timeout: 30000 });
  info = await waitForStill(owner, info);
  // A page that asks for nothing: this browser decodes H.264 (VideoDecoder.isConfigSupported),
  // so its new session's frames come as H.264.
  const chooser = await context.newPage();
  await chooser.goto(`${server.url}?volume=${encodeURIComponent(options.volume)}`);
  const chosen = await chooser.waitForFunction(
    () => document.querySelector('canvas.frame-canvas')?.dataset.encoding === 'h264', null,
    { timeout: 60000 }).then(() => true, () => false);
  check('a new session picks H.264 where the browser can decode it',
    chosen && (await chooser.locator('[data-control="encoding"] select').inputValue()) === 'h264',
    await chooser.locator('[data-control="encoding"] select').inputValue());
  await chooser.close();

  // 4c. Every numeric setting the server's hello announces has a control, labelled by its name, in
  // the folder of its part of the settings (the client lists none of them).
  const ranges = await owner.evaluate(() => new Promise((resolve, reject) => {
    const ws = new WebSocket(`ws://${location.host}/ws`);
    ws.onmessage = (e) => {
      ws.close();
      resolve(JSON.parse(e.data).ranges);
    };
    ws.onerror = () => reject(new Error('no hello'));
  }));
  const announced = Object.keys(ranges).filter((p) => p.startsWith('settings/'));
  const folderOfPart = { '': 'Sampling', light_buffer: 'Light buffer & slices',
    scattering: 'Shell & cone scattering', shading: 'Shading' };
  const placed = await owner.evaluate((paths) => paths.map((p) => {
    const controls = document.querySelectorAll(`[data-setting="${p}"]`);
    const control = controls[0];
    const folder = control?.closest('.lil-gui');
    return {
      path: p,
      count: controls.length,
      visible: control !== undefined && control.offsetParent !== null || folder?.classList.contains('lil-closed'),
      label: control?.querySelector('.lil-name')?.textContent,
      folder: folder?.querySelector(':scope > .lil-title')?.textContent,
    };
  }), announced);
  const misplaced = placed.filter(({ path: p, count, visible, label, folder }) => {
    const members = p.split('/').slice(1);
    const part = members.length > 1 ? members[0] : '';
    return count !== 1 || !visible || label !== members[members.length - 1].replace(/_/g, ' ') ||
      folder !== folderOfPart[part];
  });
  check("every numeric setting of hello has a labelled control in its part's folder",
    announced.length > 10 && misplaced.length === 0,
    `${announced.length} settings; misplaced: ${JSON.stringify(misplaced)}`);

  // 4d. The light's sliders reach the ends of hello's ranges (intensity to the server's maximum),
  // and the point light's position never leaves the server's coordinates.
  const intensity = owner.locator('[data-control="light.intensity"] input');
  await intensity.fill(String(ranges['light/intensity'].max * 10));
  await intensity.press('Enter');
  const intensityShown = Number(await intensity.inputValue());
  info = await waitForStill(owner, info);
  await intensity.fill('1');
  await intensity.press('Enter');
  info = await waitForStill(owner, info);
  check("the light's intensity slider reaches the end of hello's range",
    intensityShown === ranges['light/intensity'].max &&
      (await owner.locator('.notice.error', { hasText: '/light/' }).count()) === 0,
    `typed ${ranges['light/intensity'].max * 10}, shows ${intensityShown}`);
  await owner.locator('[data-control="light.type"] select').selectOption('point');
  info = await waitForStill(owner, info);
  const positionX = owner.locator('[data-control="light.position.x"] input');
  await positionX.fill(String(ranges.vec3.max * 10));
  await positionX.press('Enter');
  const positionShown = Number(await positionX.inputValue());
  info = await waitForStill(owner, info);
  check("the point light's position slider stays within the server's coordinates",
    (await owner.locator('[data-control="light.position.x"] .lil-slider').count()) === 1 &&
      positionShown > 1 && positionShown <= ranges.vec3.max &&
      (await owner.locator('.notice.error', { hasText: '/light/' }).count()) === 0,
    `typed ${ranges.vec3.max * 10}, shows ${positionShown}`);
  await positionX.fill('0');
  await positionX.press('Enter');
  await owner.locator('[data-control="light.type"] select').selectOption('directional');
  info = await waitForStill(owner, info);

  // 4e. Labels: the AAL atlas drawn inside the head through the Labels panel, a cut at the view
  // plane showing the brain; its 116 labels listed; a search finds the cunei; "only" shows one
  // alone (the server's state says so and the frame changes); a tap on the frame's centre says
  // what lies there without moving the camera; hiding the label it names, or a drag, takes the
  // answer away.
  const addLabels = owner.locator('[data-control="labels-add"]');
  const labelMaps = await addLabels.locator('option').evaluateAll((els) =>
    els.map((e) => e.value).filter((v) => v !== ''));
  check('the Labels panel offers the atlas as a label map',
    labelMaps.includes('aal.nii.gz') && !labelMaps.includes(options.volume), labelMaps.join(', '));
  await owner.locator('[data-control="clip-view"] button').click();
  info = await waitForStill(owner, info);
  const unlabelled = await canvasSignature(owner);
  await addLabels.selectOption('aal.nii.gz');
  await waitForLabelsShown(owner, '116 of 116 shown', 60000);
  info = await waitForStill(owner, info);
  const labelled = await canvasSignature(owner);
  await showLabelsFolder(owner);
  await owner.screenshot({ path: path.join(outDir, '08_labels_added.png') });
  check('adding the atlas lists its 116 labels and colours the brain',
    (await owner.locator('.label-row').count()) === 116 && difference(unlabelled, labelled) > 1,
    `${await owner.locator('.label-row').count()} rows, difference ${difference(unlabelled, labelled).toFixed(1)}`);
  await owner.locator('[data-control="labels-search"]').fill('Cuneus');
  const found = await owner.locator('.label-row:visible .label-name').allTextContents();
  check('a search for "Cuneus" lists the cunei and precunei alone',
    found.join() === 'Cuneus_L,Cuneus_R,Precuneus_L,Precuneus_R', found.join(', '));
  await owner.locator('.label-row[data-label="45"] .label-only').click();
  await waitForLabelsShown(owner, '1 of 116 shown');
  info = await waitForStill(owner, info);
  const alone = await canvasSignature(owner);
  const checkedRows = await owner.locator('.label-row input.label-visible:checked').evaluateAll((els) =>
    els.map((e) => e.closest('.label-row').dataset.label));
  check('"only" shows Cuneus_L alone: the server says so and the frame changes',
    checkedRows.join() === '45' && difference(labelled, alone) > 1,
    `shown ${checkedRows.join()}, difference ${difference(labelled, alone).toFixed(1)}`);
  await owner.screenshot({ path: path.join(outDir, '08b_labels_only_cuneus.png') });
  const axesBeforeTap = await markerAxes(owner);
  const requestBeforeTap = (await frameInfo(owner)).request;
  const centre = await pickAt(owner, 0.5, 0.5);
  check('a tap on the frame centre says what lies there',
    (centre.state === 'hit' && /R -?\d+\.\d · A -?\d+\.\d · S -?\d+\.\d mm/.test(centre.text)) ||
      (centre.state === 'miss' && centre.text.includes('nothing here')),
    `${centre.state}: ${centre.text}`);
  check('and moves neither the camera nor asks for a frame',
    (await markerAxes(owner)) === axesBeforeTap && (await frameInfo(owner)).request === requestBeforeTap,
    `request ${requestBeforeTap} -> ${(await frameInfo(owner)).request}`);
  // Every label again; taps along the cut find one, which the answer names and the list selects.
  await owner.locator('[data-control="labels-show-all"]').click();
  await waitForLabelsShown(owner, '116 of 116 shown');
  info = await waitForStill(owner, info);
  await owner.locator('[data-control="labels-search"]').fill('');
  let labelPick = null;
  let labelPoint = null;
  for (const [fx, fy] of [[0.55, 0.4], [0.45, 0.4], [0.5, 0.35], [0.6, 0.45], [0.4, 0.45], [0.5, 0.3]]) {
    const answer = await pickAt(owner, fx, fy);
    if (answer.label) {
      labelPick = answer;
      labelPoint = [fx, fy];
      break;
    }
  }
  const selectedRow = await owner.locator('.label-row.selected').getAttribute('data-label').catch(() => null);
  await owner.screenshot({ path: path.join(outDir, '09_labels_pick.png') });
  check('a tap on a labelled region names the label, and the list selects it',
    labelPick !== null && selectedRow === labelPick.label &&
      (await owner.locator('.pick-marker').isVisible()),
    `${labelPick?.text}; selected row ${selectedRow}`);
  // Hiding the label the answer names changes what lies there, not the camera: the answer goes.
  if (labelPick !== null) {
    await owner.locator(`.label-row[data-label="${labelPick.label}"] input.label-visible`).click();
    await waitForLabelsShown(owner, '115 of 116 shown');
    info = await waitForStill(owner, info);
    check('hiding the label the answer names takes the answer away',
      !(await owner.locator('.pick-callout').isVisible()));
    await owner.locator('[data-control="labels-show-all"]').click();
    await waitForLabelsShown(owner, '116 of 116 shown');
    info = await waitForStill(owner, info);
    await pickAt(owner, ...labelPoint);
  }
  const frameBox = await owner.locator('canvas.frame-canvas').boundingBox();
  await dragDown(owner, frameBox.x + frameBox.width * 0.8, frameBox.y + frameBox.height * 0.5, 20);
  info = await waitForStill(owner, info);
  check('a drag takes the answer away', !(await owner.locator('.pick-callout').isVisible()));
  // "Labels only": the atlas drawn by itself as lit surfaces, the head not drawn (the blend, set
  // aside, hidden); a tap names the surface's label; then inside the head again.
  const insideHead = await canvasSignature(owner);
  await showLabelsFolder(owner);
  await owner.locator('[data-control="labels-alone"]').check();
  await owner.waitForFunction(() =>
    document.querySelector('[data-control="labels-blend-row"]')?.hidden === true);
  info = await waitForStill(owner, info);
  const surfacesAlone = await canvasSignature(owner);
  let surfacePick = null;
  for (const [fx, fy] of [[0.5, 0.5], [0.55, 0.4], [0.45, 0.4], [0.5, 0.35], [0.6, 0.45]]) {
    surfacePick = await pickAt(owner, fx, fy);
    if (surfacePick.label) break;
  }
  await owner.screenshot({ path: path.join(outDir, '09b_labels_alone.png') });
  check('"labels only" draws the atlas alone as surfaces, and a tap names one',
    difference(insideHead, surfacesAlone) > 1 && surfacePick.state === 'hit' &&
      surfacePick.label !== undefined,
    `difference ${difference(insideHead, surfacesAlone).toFixed(1)}; ${surfacePick.text}`);
  await owner.locator('[data-control="labels-alone"]').uncheck();
  await owner.waitForFunction(() =>
    document.querySelector('[data-control="labels-blend-row"]')?.hidden === false);
  info = await waitForStill(owner, info);
  // On a portrait tablet the labels list in the drawer scrolls, its rows big enough for a finger;
  // a label hidden there is hidden in the session.
  await owner.setViewportSize({ width: 768, height: 1024 });
  await owner.waitForTimeout(400);
  await owner.locator('.drawer-toggle').click();
  await owner.waitForTimeout(400);
  await owner.locator('.labels-list').scrollIntoViewIfNeeded();
  const list = await owner.locator('.labels-list').evaluate((e) => ({
    scrolls: e.scrollHeight > e.clientHeight + 100,
    rowHeight: e.querySelector('.label-row').getBoundingClientRect().height,
    height: e.clientHeight,
  }));
  await owner.locator('.labels-list').evaluate((e) => e.scrollBy(0, 400));
  await owner.locator('.label-row[data-label="57"]').scrollIntoViewIfNeeded();
  await owner.locator('.label-row[data-label="57"] input.label-visible').click();
  await waitForLabelsShown(owner, '115 of 116 shown');
  info = await waitForStill(owner, info);
  await showLabelsFolder(owner);
  check('in the drawer the labels list scrolls, its rows finger-sized, and a label hides there',
    list.scrolls && list.rowHeight >= 36 && list.height >= 200 &&
      !(await owner.locator('.label-row[data-label="57"] input.label-visible').isChecked()),
    `row ${list.rowHeight}px, list ${list.height}px`);
  // With the drawer open, a tap on the part of the frame beside it still picks.
  let tabletPick = null;
  for (const [fx, fy] of [[0.3, 0.45], [0.25, 0.55], [0.35, 0.35], [0.3, 0.6]]) {
    const answer = await pickAt(owner, fx, fy);
    if (answer.label) {
      tabletPick = answer;
      break;
    }
  }
  await owner.screenshot({ path: path.join(outDir, '10_portrait_labels.png') });
  check('beside the open drawer a tap names the label under it', tabletPick !== null &&
    (await owner.locator('.pick-callout').isVisible()), tabletPick?.text);
  await owner.locator('.drawer-toggle').click();
  await owner.setViewportSize({ width: 900, height: 560 });
  await owner.waitForTimeout(400);
  info = await waitForStill(owner, null);

  // 5. A second page joins through the share link and sees the same frame.
  const link = await owner.locator('#share-link').inputValue();
  check('the share link carries the session id', /[?&]join=[0-9a-f]+/.test(link), link);
  const viewer = await context.newPage();
  viewer.on('pageerror', (e) => consoleErrors.push(`viewer: ${String(e)}`));
  await viewer.goto(link);
  await viewer.waitForFunction(() => document.querySelector('canvas.frame-canvas')?.dataset.frame !== undefined,
    null, { timeout: 30000 });
  check('the viewer is read-only',
    (await viewer.locator('.role').textContent()).includes('read-only') &&
      (await viewer.locator('[data-control="mode"] select').isDisabled()));
  // The owner's changes reach the viewer's panels (the server's `state`), not only its frames.
  const modeShown = () => document.querySelector('[data-control="mode"] select')?.value;
  const viewerModeIs = (mode) => viewer.waitForFunction(
    (m) => document.querySelector('[data-control="mode"] select')?.value === m, mode,
    { timeout: 15000 });
  const modeAtJoin = await viewer.evaluate(modeShown);
  await owner.locator('[data-control="mode"] select').selectOption('phong');
  await viewerModeIs('phong');
  await owner.locator('[data-control="mode"] select').selectOption('dvr');
  await viewerModeIs('dvr');
  check("the viewer's method panel follows the owner's mode", modeAtJoin === 'dvr',
    `${modeAtJoin} at join, then phong and dvr as the owner chose them`);
  // The labels arrive after joined: the viewer's panel lists them, read-only.
  await waitForLabelsShown(viewer, '115 of 116 shown');
  check("the viewer's Labels panel lists the owner's labels, read-only",
    (await viewer.locator('.label-row').count()) === 116 &&
      (await viewer.locator('.label-row[data-label="57"] input.label-visible').isDisabled()) &&
      (await viewer.locator('[data-control="labels-show-all"]').isDisabled()),
    await labelsShown(viewer));
  // The owner moves the camera; both pages must end on the same still frame.
  const ownerBefore = await frameInfo(owner);
  await owner.locator('canvas.frame-canvas').focus();
  await owner.keyboard.press('ArrowLeft');
  await owner.keyboard.press('ArrowLeft');
  const a = await waitForStill(owner, ownerBefore);
  await viewer.waitForFunction((f) => Number(document.querySelector('canvas.frame-canvas')?.dataset.frame) >= f,
    a.frame, { timeout: 30000 });
  await owner.waitForTimeout(300);
  const [ownerImage, viewerImage] = await sameFrameSignatures(owner, viewer);
  const viewerPick = await pickAt(viewer, 0.5, 0.5);
  await viewer.screenshot({ path: path.join(outDir, '05_viewer.png') });
  check('a viewer may pick too', ['hit', 'miss'].includes(viewerPick.state), viewerPick.text);
  await owner.screenshot({ path: path.join(outDir, '05_owner.png') });
  check('the viewer sees the same frame', ownerImage.frame === viewerImage.frame &&
    difference(ownerImage, viewerImage) < 1,
    `owner #${ownerImage.frame}, viewer #${viewerImage.frame}, difference ${difference(ownerImage, viewerImage).toFixed(2)}`);
  await viewer.close();

  // Export: the view as a PNG larger than its frames, downloaded from the link the panel shows.
  await owner.locator('.export-sides').selectOption('1024');
  await owner.locator('.export-panel').evaluate((e) => e.closest('.lil-gui').scrollIntoView());
  await owner.locator('.export-start').click();
  await owner.locator('.export-status[data-state="running"]').waitFor({ timeout: 15000 });
  await owner.screenshot({ path: path.join(outDir, '05_export_running.png') });
  await owner.locator('.export-status[data-state="done"]').waitFor({ timeout: 180000 });
  check('the download link shows once the export is done, not before',
    await owner.locator('.export-link').isVisible());
  await owner.screenshot({ path: path.join(outDir, '05_export_done.png') });
  const exported = await owner.evaluate(async () => {
    const link = document.querySelector('.export-link');
    const response = await fetch(link.href);
    const bytes = new Uint8Array(await response.arrayBuffer());
    const view = new DataView(bytes.buffer);
    const text = new TextDecoder('latin1').decode(bytes);
    return {
      status: response.status,
      type: response.headers.get('content-type'),
      disposition: response.headers.get('content-disposition'),
      png: bytes[1] === 0x50 && bytes[2] === 0x4e && bytes[3] === 0x47,
      width: view.getUint32(16),
      height: view.getUint32(20),
      state: text.includes('Penumbra state'),
      line: document.querySelector('.export-status').textContent,
    };
  });
  const [canvasWidth, canvasHeight] = await owner.evaluate(() => {
    const c = document.querySelector('canvas.frame-canvas');
    return [c.width, c.height];
  });
  check('the export panel downloads a PNG of the view at the size asked for, with its state',
    exported.status === 200 && exported.png && exported.state &&
      Math.max(exported.width, exported.height) === 1024 &&
      Math.abs(exported.width / exported.height - canvasWidth / canvasHeight) < 0.01 &&
      /attachment; filename="penumbra-.*\.png"/.test(exported.disposition),
    JSON.stringify(exported));

  // A movie of the view turning, downloaded and opened by the browser's own video element.
  await owner.locator('.export-kind').selectOption('turntable');
  await owner.locator('.export-start').click();
  await owner.locator('.export-status[data-state="done"]', { hasText: 'MP4' })
    .waitFor({ timeout: 180000 });
  await owner.screenshot({ path: path.join(outDir, '05_export_movie_done.png') });
  const movie = await owner.evaluate(async () => {
    const link = document.querySelector('.export-link');
    const response = await fetch(link.href);
    const blob = await response.blob();
    const bytes = new Uint8Array(await blob.arrayBuffer());
    const video = document.createElement('video');
    video.muted = true;
    const opened = await new Promise((resolve) => {
      video.onloadedmetadata = () => resolve(true);
      video.onerror = () => resolve(false);
      video.src = URL.createObjectURL(blob);
    });
    return {
      status: response.status,
      type: response.headers.get('content-type'),
      disposition: response.headers.get('content-disposition'),
      ftyp: new TextDecoder('latin1').decode(bytes.slice(4, 8)),
      opened,
      width: video.videoWidth,
      height: video.videoHeight,
      seconds: video.duration,
      line: document.querySelector('.export-status').textContent,
    };
  });
  check('the export panel downloads a turntable MP4 that the browser plays, at the size offered',
    movie.status === 200 && movie.type === 'video/mp4' && movie.ftyp === 'ftyp' && movie.opened &&
      Math.max(movie.width, movie.height) === 128 && movie.width % 2 === 0 &&
      movie.height % 2 === 0 && Math.abs(movie.seconds - 8 / 30) < 0.05 &&
      /attachment; filename="penumbra-.*-turntable\.mp4"/.test(movie.disposition) &&
      movie.line.includes('MP4, 8 frames'),
    JSON.stringify(movie));
  check('no page errors so far', consoleErrors.length === 0, consoleErrors.join(' | '));

  // 6. The server goes away: a clear message; it comes back: the session is restored.
  const port = server.port;
  await stopServer(server.child);
  await owner.locator('.connection-banner', { hasText: 'lost' }).waitFor({ timeout: 15000 });
  await owner.screenshot({ path: path.join(outDir, '06_connection_lost.png') });
  check('a lost connection is reported', true, await owner.locator('.connection-banner').textContent());
  server = await startServer(port);
  log(`server restarted at ${server.url}`);
  await owner.locator('.notice.info', { hasText: 'Reconnected' }).waitFor({ timeout: 30000 });
  const restored = await waitForStill(owner, null, 30000);
  await owner.screenshot({ path: path.join(outDir, '07_restored.png') });
  check('after reconnecting the session is restored (mode dvr kept)', restored.mode === 'dvr',
    `frame #${restored.frame} mode ${restored.mode}`);
  await waitForLabelsShown(owner, '115 of 116 shown', 30000).catch(() => {});
  check('and its label map drawn again, with the label hidden before',
    (await labelsShown(owner)).endsWith('115 of 116 shown') &&
      (await owner.locator('.label-row').count()) === 116, await labelsShown(owner));

  // While the server was down the browser logs the refused WebSocket: only uncaught errors count.
  check('no uncaught page errors', pageErrors.length === 0, pageErrors.join(' | '));
  await stopServer(server.child);
} catch (e) {
  failed = true;
  console.error(e);
  if (owner) await owner.screenshot({ path: path.join(outDir, 'failure.png') }).catch(() => {});
} finally {
  await context?.close().catch(() => {});
  for (const child of [...servers]) await stopServer(child);
  rmSync(userDataDir, { recursive: true, force: true });
}
log(`${checks.filter((c) => c.ok).length} checks passed${failed ? ', FAILED' : ''}; screenshots in ${outDir}`);
process.exit(failed ? 1 : 0);
