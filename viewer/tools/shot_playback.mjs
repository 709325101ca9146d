// Screenshot of a report.html's machine playback at a share of the program time (for the docs).
// Usage: node tools/shot_playback.mjs REPORT_HTML OUT.png [SHARE=0.5] [ZOOM=1: the camera ZOOM times as far]
import { chromium } from 'playwright-core';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const [report, out, share = '0.5', zoom = '1'] = process.argv.slice(2);
if (!report || !out) {
  console.error('usage: node tools/shot_playback.mjs REPORT_HTML OUT.png [SHARE]');
  process.exit(2);
}
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true,
  args: ['--no-sandbox', '--headless=new', '--use-gl=swiftshader', '--enable-unsafe-swiftshader', '--disable-gpu'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(pathToFileURL(path.resolve(report)).href, { waitUntil: 'load' });
  await page.waitForFunction(() => document.body.dataset.ready === '1' || document.body.dataset.error === '1', null, { timeout: 120000 });
  const ok = await page.evaluate(([s, z]) => {
    const p = window.polyaxisViewer.playback;
    if (!p) return false;
    p.seek(Number(s) * p.duration);
    window.polyaxisViewer.zoom(Number(z));
    return true;
  }, [share, zoom]);
  if (!ok) throw new Error(`${report}: no playback`);
  await page.screenshot({ path: out });
} finally {
  await browser.close();
}
