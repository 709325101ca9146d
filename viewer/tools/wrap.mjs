// Dev helper: builds report.html from a data JSON exactly like the C++ report writer.
// Usage: node tools/wrap.mjs DATA.json OUT.html [BUNDLE.js]   (bundle default: dist/viewer.js)
import { readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const [dataPath, outPath, bundleArg] = process.argv.slice(2);
if (!dataPath || !outPath) {
  console.error('usage: node tools/wrap.mjs DATA.json OUT.html [BUNDLE.js]');
  process.exit(2);
}
const bundlePath = bundleArg || path.join(here, '..', 'dist', 'viewer.js');
const data = readFileSync(dataPath, 'utf8');
const bundle = readFileSync(bundlePath, 'utf8');
if (bundle.toLowerCase().includes('</script')) {
  console.error(`wrap.mjs: ${bundlePath} contains "</script"`);
  process.exit(1);
}
let title = '';
try {
  title = JSON.parse(data).title ?? '';
} catch (e) {
  console.error(`wrap.mjs: ${dataPath} is not JSON: ${e.message}`);
  process.exit(1);
}
const escHtml = (s) => String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
// Plain concatenation (no String.replace with the payload: "$&" in data must stay literal).
const html = '<!DOCTYPE html>\n'
  + '<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width,initial-scale=1">\n'
  + `<title>polyaxis — ${escHtml(title)}</title></head>\n`
  + '<body>\n'
  + '<script type="application/json" id="polyaxis-data">' + data.split('<').join('\\u003c') + '</script>\n'
  + '<script>' + bundle + '</script>\n'
  + '</body></html>\n';
writeFileSync(outPath, html);
console.log(`wrote ${outPath} (${(html.length / 1048576).toFixed(2)} MiB)`);
