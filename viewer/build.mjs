// Bundles src/main.js into one minified IIFE (three.js included, CSS injected from JS).
// Usage: node build.mjs [OUTFILE]   (default dist/viewer.js). Works offline after `npm ci`.
import { build } from 'esbuild';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const outfile = path.resolve(process.argv[2] || path.join(here, 'dist', 'viewer.js'));

await build({
  absWorkingDir: here,
  entryPoints: [path.join(here, 'src', 'main.js')],
  bundle: true,
  minify: true,
  format: 'iife',
  platform: 'browser',
  target: ['es2020'],
  outfile,
  legalComments: 'eof', // keeps the three.js MIT notice
  charset: 'utf8',
  logLevel: 'warning',
});

// The bundle is inlined in a <script> element: it must not close it or open an HTML comment there.
const text = readFileSync(outfile, 'utf8');
for (const bad of ['</script', '<!--']) {
  const at = text.toLowerCase().indexOf(bad);
  if (at >= 0) {
    console.error(`build.mjs: ${outfile} contains "${bad}" at ${at}; it cannot be inlined in report.html`);
    process.exit(1);
  }
}
console.log(`viewer bundle: ${outfile} (${(text.length / 1024).toFixed(0)} KiB)`);
