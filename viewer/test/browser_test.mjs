// Opens a polyaxis report.html in headless Chromium (SwiftShader WebGL) and checks the viewer.
// Usage: node test/browser_test.mjs REPORT_HTML [--screenshot OUT.png [--layer K]] [--timeout SECONDS]
// Fails (exit 1) on any console error, page error or failed request, on a blank canvas, or when moving
// the layer slider from the last to the first layer does not change the picture. Ends within the timeout.
import { chromium } from 'playwright-core';
import { existsSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const args = process.argv.slice(2);
const opt = (name) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : undefined; };
const report = args.find((a, i) => !a.startsWith('--') && !['--screenshot', '--timeout', '--layer'].includes(args[i - 1]));
const screenshot = opt('--screenshot');
const shotLayer = opt('--layer');
const timeoutS = Number(opt('--timeout') || 60);
const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';
const MIN_FRACTION = 0.01; // non-background pixels required, share of the canvas
const MIN_CHANGED = 200; // pixels that must change between the last and the first layer

if (!report) {
  console.error('usage: node test/browser_test.mjs REPORT_HTML [--screenshot OUT.png [--layer K]] [--timeout SECONDS]');
  process.exit(2);
}
const reportPath = path.resolve(report);
const name = path.basename(path.dirname(reportPath)) + '/' + path.basename(reportPath);
if (!existsSync(reportPath)) {
  console.error(`FAIL ${name}: no such file ${reportPath}`);
  process.exit(1);
}
if (!existsSync(CHROMIUM)) {
  console.error(`FAIL ${name}: no browser at ${CHROMIUM} (set CHROMIUM=...)`);
  process.exit(1);
}

const t0 = Date.now();
const elapsed = () => ((Date.now() - t0) / 1000).toFixed(2);
let browser = null;
const problems = [];

let finished = false;
async function finish(code, line) {
  if (finished) return new Promise(() => {}); // the first verdict wins; process.exit follows
  finished = true;
  (code === 0 ? console.log : console.error)(line);
  if (browser) await Promise.race([browser.close().catch(() => {}), new Promise((r) => setTimeout(r, 5000))]);
  process.exit(code); // playwright kills a browser that is still running when node exits
}

// fires early enough that closing the browser (at most 5 s) still ends within the timeout
const watchdogS = Math.max(1, timeoutS - 6);
const watchdog = setTimeout(() => {
  finish(1, `FAIL ${name}: timeout after ${watchdogS} s${problems.length ? `; ${problems.join('; ')}` : ''}`);
}, watchdogS * 1000);
watchdog.unref();

// Counts non-background pixels of the WebGL canvas and hashes the picture (runs in the page).
function measureCanvas() {
  const v = window.polyaxisViewer;
  const c = document.querySelector('canvas.px-canvas');
  const t = document.createElement('canvas');
  t.width = c.width;
  t.height = c.height;
  const ctx = t.getContext('2d', { willReadFrequently: true });
  ctx.drawImage(c, 0, 0);
  const d = ctx.getImageData(0, 0, t.width, t.height).data;
  const [br, bg, bb] = v.background;
  let count = 0;
  let h = 2166136261;
  const mask = new Uint8Array(t.width * t.height);
  for (let i = 0, p = 0; i < d.length; i += 4, p++) {
    if (Math.abs(d[i] - br) > 6 || Math.abs(d[i + 1] - bg) > 6 || Math.abs(d[i + 2] - bb) > 6) { count++; mask[p] = 1; }
    h = Math.imul(h ^ d[i], 16777619) ^ d[i + 1];
    h = Math.imul(h ^ d[i + 2], 16777619);
  }
  window.__pxLast = window.__pxCur;
  window.__pxCur = d;
  let changed = 0;
  if (window.__pxLast && window.__pxLast.length === d.length) {
    const a = window.__pxLast;
    for (let i = 0; i < d.length; i += 4) {
      if (Math.abs(a[i] - d[i]) + Math.abs(a[i + 1] - d[i + 1]) + Math.abs(a[i + 2] - d[i + 2]) > 12) changed++;
    }
  }
  return { width: t.width, height: t.height, count, hash: (h >>> 0).toString(16), changed };
}

try {
  browser = await chromium.launch({
    executablePath: CHROMIUM,
    headless: true,
    timeout: 30000,
    args: [
      '--no-sandbox', '--headless=new', '--use-gl=swiftshader', '--enable-unsafe-swiftshader', '--disable-gpu',
      '--disable-background-networking', '--no-first-run', '--disable-component-update', '--disable-sync',
    ],
    // playwright gives the browser a fresh temporary --user-data-dir of its own
  });
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console error: ${m.text().split('\n')[0].trim()}`); });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('requestfailed', (r) => problems.push(`request failed: ${r.url().slice(0, 200)} (${r.failure()?.errorText})`));
  page.on('crash', () => problems.push('page crashed'));
  page.on('request', (r) => {
    if (!r.url().startsWith('file:') && !r.url().startsWith('data:')) problems.push(`network request: ${r.url().slice(0, 200)}`);
  });

  const tNav = Date.now();
  await page.goto(pathToFileURL(reportPath).href, { waitUntil: 'load', timeout: timeoutS * 1000 });
  // wait for data-ready, or stop at the first error
  const deadline = t0 + watchdogS * 1000 - 2000;
  while (true) {
    if (problems.length) await finish(1, `FAIL ${name}: ${problems.join('; ')}`);
    const state = await page.evaluate(() => [document.body.dataset.ready, document.body.dataset.error]);
    if (state[0] === '1') break;
    if (state[1] === '1') {
      const msg = await page.evaluate(() => document.getElementById('px-error')?.textContent);
      await finish(1, `FAIL ${name}: ${msg}`);
    }
    if (Date.now() > deadline) await finish(1, `FAIL ${name}: viewer not ready (no data-ready) after ${elapsed()} s`);
    await new Promise((r) => setTimeout(r, 50));
  }
  const loadS = ((Date.now() - tNav) / 1000).toFixed(2);
  const info = await page.evaluate(() => {
    const v = window.polyaxisViewer;
    return { layers: v.layerCount, current: v.currentLayer, loadMs: v.loadMs, stats: v.stats, regions: v.stats.regions };
  });
  const first = await page.evaluate(measureCanvas);
  const total = first.width * first.height;
  const fraction = first.count / total;
  console.log(`loaded in ${loadS} s (viewer init ${info.loadMs.toFixed(0)} ms, decode ${info.stats.decodeMs.toFixed(0)} ms); `
    + `${info.layers} layers; ${info.stats.depositSegments} deposit + ${info.stats.travelSegments} travel segments, `
    + `${info.stats.glyphs} glyphs (stride ${info.stats.glyphStride})`);
  console.log(`layer ${info.current}: ${first.count} non-background pixels of ${total} (${(100 * fraction).toFixed(1)} %), hash ${first.hash}`);
  if (fraction < MIN_FRACTION) await finish(1, `FAIL ${name}: canvas nearly blank (${first.count} px)`);

  let changeNote = 'no layers';
  if (info.layers > 0) {
    // move the slider like a user: set the value and dispatch 'input'
    const tStep = Date.now();
    const now = await page.evaluate(() => {
      const s = document.getElementById('layer-slider');
      s.value = '0';
      s.dispatchEvent(new Event('input', { bubbles: true }));
      window.polyaxisViewer.renderNow(); // instead of waiting for the next animation frame
      return window.polyaxisViewer.currentLayer;
    });
    if (now !== 0) await finish(1, `FAIL ${name}: slider moved to 0 but currentLayer is ${now}`);
    const second = await page.evaluate(measureCanvas);
    const stepMs = Date.now() - tStep;
    const panelText = await page.evaluate(() => document.getElementById('px-layer-no').textContent);
    console.log(`layer 0: ${second.count} non-background pixels, hash ${second.hash}; ${second.changed} pixels changed `
      + `(slider step + render ${stepMs} ms, panel "${panelText}")`);
    if (second.changed < MIN_CHANGED && info.layers > 1) {
      await finish(1, `FAIL ${name}: the picture did not change from the last to the first layer (${second.changed} px)`);
    }
    // keyboard steps forward again
    await page.keyboard.press('ArrowRight');
    const afterKey = await page.evaluate(() => window.polyaxisViewer.currentLayer);
    if (info.layers > 1 && afterKey !== 1) await finish(1, `FAIL ${name}: ArrowRight gave layer ${afterKey}, expected 1`);
    // a toggle: hiding the regions must change the picture (then show them again)
    await page.click('#px-toggle-regions');
    await page.evaluate(() => window.polyaxisViewer.renderNow());
    await page.evaluate(measureCanvas);
    await page.click('#px-toggle-regions');
    await page.evaluate(() => window.polyaxisViewer.renderNow());
    const toggled = await page.evaluate(measureCanvas);
    if (toggled.changed < MIN_CHANGED && info.regions > 0) {
      await finish(1, `FAIL ${name}: the regions toggle did not change the picture (${toggled.changed} px)`);
    }
    changeNote = `slider last→first changed ${second.changed} px, regions toggle ${toggled.changed} px`;
  }
  // Long metric texts (the strategy's reason) read across the panel under their key, not squeezed
  // into the value column beside it.
  const long = await page.evaluate(() => {
    const dl = document.querySelector('.px-right dl.px-kv');
    const reason = [...document.querySelectorAll('.px-right dt')].find((dt) => dt.textContent === 'strategy_reason');
    const dd = reason ? reason.nextElementSibling : null;
    return {
      list: dl ? dl.clientWidth : 0,
      reason: dd && dd.textContent.length > 40 ? dd.getBoundingClientRect().width : null,
      widths: [...document.querySelectorAll('.px-right dd.px-long')].map((d) => d.getBoundingClientRect().width),
    };
  });
  if ((long.reason !== null && long.reason < 0.8 * long.list) || long.widths.some((w) => w < 0.8 * long.list)) {
    await finish(1, `FAIL ${name}: a long metric is squeezed into ${Math.min(...long.widths, long.reason ?? Infinity).toFixed(0)} px of a ${long.list} px list`);
  }
  let playNote = 'no playback';
  const hasPlayback = await page.evaluate(() => window.polyaxisViewer.playback !== null && window.polyaxisViewer.playback !== undefined);
  if (hasPlayback) {
    // Scrub like a user (the time slider), then play: the machine moves, the picture changes, and
    // the frame time while playing is measured.
    const pb = await page.evaluate(() => ({ duration: window.polyaxisViewer.playback.duration, frames: window.polyaxisViewer.playback.frames }));
    const scrub = async (share) => page.evaluate((v) => {
      const s = document.getElementById('px-time');
      s.value = String(Math.round(v * 10000));
      s.dispatchEvent(new Event('input', { bubbles: true }));
      window.polyaxisViewer.renderNow();
      return document.getElementById('px-playback-info').textContent;
    }, share);
    const early = await scrub(0.25);
    await page.evaluate(measureCanvas);
    const late = await scrub(0.75);
    const moved = await page.evaluate(measureCanvas);
    if (!/line \d+/.test(early) || !/line \d+/.test(late)) await finish(1, `FAIL ${name}: the playback readout names no line: "${late}"`);
    if (moved.changed < MIN_CHANGED) {
      await finish(1, `FAIL ${name}: scrubbing the playback from 25 % to 75 % did not change the picture (${moved.changed} px)`);
    }
    await page.evaluate(measureCanvas);
    await page.click('#px-play');
    await new Promise((r) => setTimeout(r, 2500));
    const times = await page.evaluate(() => { const p = window.polyaxisViewer.playback; p.pause(); return p.frameTimes(); });
    const played = await page.evaluate(measureCanvas);
    if (times.length < 3) await finish(1, `FAIL ${name}: playing drew ${times.length} frames in 2.5 s`);
    if (played.changed < MIN_CHANGED) await finish(1, `FAIL ${name}: playing did not change the picture (${played.changed} px)`);
    const sorted = times.slice().sort((a, b) => a - b);
    const mean = times.reduce((a, b) => a + b, 0) / times.length;
    const p95 = sorted[Math.min(sorted.length - 1, Math.floor(0.95 * sorted.length))];
    playNote = `playback ${pb.frames} frames over ${pb.duration.toFixed(0)} s: scrub changed ${moved.changed} px, `
      + `play changed ${played.changed} px, frame time mean ${mean.toFixed(1)} ms, p95 ${p95.toFixed(1)} ms (${times.length} frames)`;
    console.log(playNote);
    const robot = await page.evaluate(() => window.polyaxisViewer.playback.robot);
    if (robot) {
      // The arm is drawn where the program puts the torch: at frames across the program, the TCP
      // of the arm's forward kinematics (robot.js) is the tip the positioner's joints give, and at
      // the first frame it is the TCP of polyaxis's own forward kinematics (machine/robot.h).
      const worst = await page.evaluate((check) => {
        const p = window.polyaxisViewer.playback;
        let tip = 0, first = null;
        for (const share of [0, 0.2, 0.4, 0.6, 0.8, 1]) {
          const s = p.seek(p.frameTime(Math.floor(share * (p.frames - 1))));
          if (!s || !s.armTcp) return { error: 'no arm drawn' };
          tip = Math.max(tip, Math.hypot(s.armTcp[0] - s.joints[0], s.armTcp[1] - s.joints[1], s.armTcp[2] - s.joints[2]));
          if (first === null) first = Math.hypot(s.armTcp[0] - check[0], s.armTcp[1] - check[1], s.armTcp[2] - check[2]);
        }
        return { tip, first };
      }, robot.checkTcp);
      if (worst.error) await finish(1, `FAIL ${name}: ${worst.error}`);
      if (!(worst.tip <= 0.05) || !(worst.first <= 0.01)) {
        await finish(1, `FAIL ${name}: the ${robot.model} is drawn ${worst.tip} mm off the program's tip (${worst.first} mm off our own FK at frame 0)`);
      }
      playNote += `; ${robot.model} drawn within ${worst.tip.toExponential(1)} mm of the tip`;
      console.log(`robot: ${robot.model} TCP within ${worst.tip.toExponential(2)} mm of the tip, ${worst.first.toExponential(2)} mm of our FK`);
    }
    await page.evaluate(() => window.polyaxisViewer.playback.stop());
  }
  if (screenshot) {
    // the whole plan (last layer) unless --layer K asks for another one
    const k = shotLayer === undefined ? info.layers - 1 : Number(shotLayer);
    await page.evaluate((i) => window.polyaxisViewer.setLayer(i), k);
    await page.screenshot({ path: screenshot });
  }
  if (problems.length) await finish(1, `FAIL ${name}: ${problems.join('; ')}`);
  await finish(0, `PASS ${name}: ready in ${loadS} s, ${info.layers} layers, ${first.count} px drawn `
    + `(${(100 * fraction).toFixed(1)} %), ${changeNote}, ${playNote}, total ${elapsed()} s${screenshot ? `, screenshot ${screenshot}` : ''}`);
} catch (e) {
  await finish(1, `FAIL ${name}: ${e.message.split('\n')[0]}${problems.length ? `; ${problems.join('; ')}` : ''}`);
}
