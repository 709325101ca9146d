// Opens a `polyaxis laminate` report.html in headless Chromium and checks it: no console or page
// error, no network request, the 3-D stack drawn on its canvas (non-white pixels), a drag turning it
// (the picture changes), and one SVG per sheet with its pieces.
// Usage: node test/laminate_page_test.mjs REPORT_HTML SHEETS [--screenshot OUT.png]
import { chromium } from 'playwright-core';
import { existsSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const [report, sheetsArg] = process.argv.slice(2);
const shotIndex = process.argv.indexOf('--screenshot');
const screenshot = shotIndex > 0 ? process.argv[shotIndex + 1] : undefined;
const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';
const MIN_DRAWN = 2000;   // non-white pixels of the stack's canvas
const MIN_CHANGED = 500;  // pixels a drag must change
if (!report || !existsSync(report) || !(Number(sheetsArg) > 0)) {
  console.error('usage: node test/laminate_page_test.mjs REPORT_HTML SHEETS [--screenshot OUT.png]');
  process.exit(2);
}
const problems = [];
const browser = await chromium.launch({ executablePath: CHROMIUM, headless: true, timeout: 30000,
  args: ['--no-sandbox', '--headless=new', '--disable-gpu', '--no-first-run', '--disable-background-networking'] });
let code = 0;
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console error: ${m.text()}`); });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('request', (r) => { if (!r.url().startsWith('file:') && !r.url().startsWith('data:')) problems.push(`network request: ${r.url()}`); });
  await page.goto(pathToFileURL(path.resolve(report)).href, { waitUntil: 'load', timeout: 30000 });
  const measure = () => page.evaluate(() => {
    const c = document.getElementById('view');
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let drawn = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i] < 240 || d[i + 1] < 240 || d[i + 2] < 240) drawn++;
    return { drawn, pixels: Array.from(d) };
  });
  const before = await measure();
  const box = await page.locator('#view').boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 120, box.y + box.height / 2 + 40, { steps: 5 });
  await page.mouse.up();
  const after = await measure();
  let changed = 0;
  for (let i = 0; i < before.pixels.length; i += 4) {
    if (Math.abs(before.pixels[i] - after.pixels[i]) + Math.abs(before.pixels[i + 1] - after.pixels[i + 1]) > 30) changed++;
  }
  const sheets = await page.evaluate(() => Array.from(document.querySelectorAll('figure svg')).map((s) => s.querySelectorAll('path').length));
  console.log(`stack: ${before.drawn} px drawn, ${changed} px changed by a drag; sheets: ${sheets.length} (${sheets.join(', ')} paths)`);
  if (before.drawn < MIN_DRAWN) problems.push(`the stack's canvas is nearly blank (${before.drawn} px)`);
  if (changed < MIN_CHANGED) problems.push(`a drag did not turn the stack (${changed} px changed)`);
  if (sheets.length !== Number(sheetsArg)) problems.push(`${sheets.length} sheet drawings, expected ${sheetsArg}`);
  if (sheets.some((n) => n < 3)) problems.push('a sheet drawing without its pieces');
  if (screenshot) await page.screenshot({ path: screenshot, fullPage: true });
} catch (e) {
  problems.push(String(e));
}
if (problems.length) {
  console.error(`FAIL ${report}: ${problems.join('; ')}`);
  code = 1;
} else {
  console.log(`PASS ${report}`);
}
await browser.close();
process.exit(code);
