// Node check of the data decoder (no browser): node test/decode_test.mjs [DATA.json ...]
// Without arguments it generates the small fixture. Exercises the atob fallback (Node has no Uint8Array.fromBase64).
import { readFileSync, mkdtempSync, rmSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { decode } from '../src/data.js';

const here = path.dirname(fileURLToPath(import.meta.url));
let files = process.argv.slice(2);
let tmp = null;
if (!files.length) {
  tmp = mkdtempSync(path.join(tmpdir(), 'polyaxis-decode-'));
  const f = path.join(tmp, 'fixture.json');
  execFileSync(process.execPath, [path.join(here, 'fixture.mjs'), f], { stdio: 'ignore' });
  files = [f];
}
let failed = 0;
const check = (cond, msg) => { if (!cond) { console.error(`FAIL ${msg}`); failed++; } };
for (const f of files) {
  const raw = JSON.parse(readFileSync(f, 'utf8'));
  const d = decode(raw);
  const n = d.toolpath.n;
  check(d.layers.length === raw.layers.length, `${f}: layer count`);
  check(d.toolpath.flags.length === n && d.toolpath.region.length === n, `${f}: per-point arrays`);
  for (const l of d.layers) check(l.pathFirst + l.pathCount <= n, `${f}: layer ${l.index} path range`);
  console.log(`ok ${f}: ${d.regions.length} regions, ${d.layers.length} layers, ${n} points`);
}
// malformed inputs must fail with a message naming the field
const bad = [
  [{ format: 'polyaxis-view/2' }, /format/],
  [{ format: 'polyaxis-view/1', toolpath: { points: 'AAAA', flags: '' } }, /toolpath.points/],
  [{ format: 'polyaxis-view/1', regions: [{ positions: 'AAAAAAAAAAAAAAAA', indices: 'AQAAAA==' }] }, /regions\[0\]/],
  [{ format: 'polyaxis-view/1', layers: [{ path_first: 5, path_count: 1 }] }, /layers\[0\]/],
  [{ format: 'polyaxis-view/1', axis: { nodes: [[0, 0, 0]], links: [[0, 3, 1]] } }, /axis.links\[0\]/],
];
for (const [raw, re] of bad) {
  try { decode(raw); check(false, `accepted ${JSON.stringify(raw)}`); } catch (e) { check(re.test(e.message), `message "${e.message}" !~ ${re}`); }
}
if (tmp) rmSync(tmp, { recursive: true, force: true });
console.log(failed ? `decode_test: ${failed} failures` : 'decode_test: PASS');
process.exit(failed ? 1 : 0);
