// Node check of the data decoder (no browser): node test/decode_test.mjs [DATA.json ...]
// Without arguments it generates the small fixture. Exercises the atob fallback (Node has no Uint8Array.fromBase64).
import { readFileSync, mkdtempSync, rmSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { decode } from '../src/data.js';

const here = path.dirname(fileURLToPath(import.meta.url));
const b64 = (bytes) => Buffer.from(bytes.buffer, bytes.byteOffset, bytes.byteLength).toString('base64');
const f32 = (a) => b64(new Float32Array(a));
const u32 = (a) => b64(new Uint32Array(a));
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
  // playback: joints in fives, one time, line, layer and flag per frame, time never running back
  [{ format: 'polyaxis-view/1', playback: { joints: f32([1, 2, 3, 4]) } }, /playback.joints/],
  [{ format: 'polyaxis-view/1', playback: { joints: f32([1, 2, 3, 4, 5]), time: f32([0, 1]), line: '', layer: '', flags: '' } },
    /playback.time/],
  [{ format: 'polyaxis-view/1', playback: { joints: f32([0, 0, 0, 0, 0, 1, 1, 1, 0, 0]), time: f32([2, 1]), line: u32([1, 2]),
    layer: u32([0, 0]), flags: b64(new Uint8Array([0, 1])) } }, /runs backwards/],
];
// A good playback decodes to typed arrays of one length.
const pbRaw = { format: 'polyaxis-view/1', playback: { kinematics: 'xyzac-trt', sense: -1, rot_point: [0, 0, 0], offset: [0, 0, -80],
  joints: f32([0, 0, 0, 0, 0, 1, 1, 1, 10, 20]), time: f32([0, 1.5]), line: u32([4, 9]), layer: u32([0, 0]), flags: b64(new Uint8Array([0, 1])),
  duration_s: 1.5, total_frames: 2 } };
const pb = decode(pbRaw).playback;
check(pb && pb.n === 2 && pb.joints.length === 10 && pb.time[1] === 1.5 && pb.line[1] === 9 && (pb.flags[1] & 1) === 1 && pb.offset[2] === -80,
  'playback decodes');
check(decode({ format: 'polyaxis-view/1' }).playback === null, 'no playback: null');
for (const [raw, re] of bad) {
  try { decode(raw); check(false, `accepted ${JSON.stringify(raw)}`); } catch (e) { check(re.test(e.message), `message "${e.message}" !~ ${re}`); }
}
if (tmp) rmSync(tmp, { recursive: true, force: true });
console.log(failed ? `decode_test: ${failed} failures` : 'decode_test: PASS');
process.exit(failed ? 1 : 0);
