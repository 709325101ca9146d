// Writes a synthetic, valid "polyaxis-view/1" data file.
//   node test/fixture.mjs OUT.json            small: cube with a side arm, 2 regions, axis with a break link,
//                                             20 layers, zigzag toolpaths with some tilted axes,
//                                             one layer with unsupported rings, one collision
//   node test/fixture.mjs OUT.json --big [--points 1000000] [--layers 2000]
//                                             a vase of many layers, for load-time tests
import { writeFileSync } from 'node:fs';

const b64 = (typed) => Buffer.from(typed.buffer, typed.byteOffset, typed.byteLength).toString('base64');

class Path {
  constructor() { this.p = []; this.a = []; this.f = []; this.r = []; }
  get length() { return this.f.length; }
  add(p, axis, flag, region) { this.p.push(p[0], p[1], p[2]); this.a.push(axis[0], axis[1], axis[2]); this.f.push(flag); this.r.push(region); }
  encode(total) {
    return {
      points: b64(Float32Array.from(this.p)), axes: b64(Float32Array.from(this.a)), flags: b64(Uint8Array.from(this.f)),
      region: b64(Uint16Array.from(this.r)), total_points: total ?? this.length, shown_points: this.length,
    };
  }
}

const DEPOSIT = 1, NEW_PATH = 2;

function ringData(rings) {
  const pts = [];
  const starts = [];
  for (const ring of rings) { starts.push(pts.length / 3); for (const q of ring) pts.push(q[0], q[1], q[2]); }
  return pts.length ? { data: b64(Float32Array.from(pts)), starts } : { data: '', starts: [] };
}

function boxMesh(x0, y0, z0, x1, y1, z1) {
  const v = [];
  for (let k = 0; k < 8; k++) v.push(k & 1 ? x1 : x0, k & 2 ? y1 : y0, k & 4 ? z1 : z0);
  const quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
  const idx = [];
  for (const [a, b, c, d] of quads) idx.push(a, b, c, a, c, d);
  return { positions: b64(Float32Array.from(v)), indices: b64(Uint32Array.from(idx)) };
}

// points along the polyline a -> b every `step` mm (b included, a excluded)
function* along(a, b, step) {
  const d = Math.hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
  const n = Math.max(1, Math.round(d / step));
  for (let i = 1; i <= n; i++) yield a.map((x, j) => x + ((b[j] - x) * i) / n);
}

function rect(u0, v0, u1, v1, to3, step) {
  const c = [[u0, v0], [u1, v0], [u1, v1], [u0, v1]];
  const out = [];
  for (let e = 0; e < 4; e++) {
    const a = c[e], b = c[(e + 1) % 4];
    const n = Math.max(1, Math.round(Math.hypot(b[0] - a[0], b[1] - a[1]) / step));
    for (let i = 0; i < n; i++) out.push(to3(a[0] + ((b[0] - a[0]) * i) / n, a[1] + ((b[1] - a[1]) * i) / n));
  }
  return out;
}

function small() {
  const bead = 0.9;
  const path = new Path();
  const layers = [];
  const rot = (axis, deg, about) => { // rotate unit axis by deg about a unit vector (Rodrigues)
    const t = (deg * Math.PI) / 180, c = Math.cos(t), s = Math.sin(t);
    const [kx, ky, kz] = about, [x, y, z] = axis;
    const dot = kx * x + ky * y + kz * z;
    return [x * c + (ky * z - kz * y) * s + kx * dot * (1 - c), y * c + (kz * x - kx * z) * s + ky * dot * (1 - c),
      z * c + (kx * y - ky * x) * s + kz * dot * (1 - c)];
  };
  // one planar layer: perimeter loop + zigzag raster, in (u, v) plane coordinates
  function layer(region, index, normal, origin, to3, u0, v0, u1, v1, t, tiltFn, unsupportedRings) {
    const first = path.length;
    const inset = bead / 2;
    const loop = rect(u0 + inset, v0 + inset, u1 - inset, v1 - inset, to3, 2.0);
    loop.forEach((p, i) => path.add(p, tiltFn(p, true), i === 0 ? NEW_PATH : DEPOSIT, region));
    path.add(loop[0], tiltFn(loop[0], true), DEPOSIT, region);
    // zigzag raster along u, stepping in v
    let v = v0 + 1.5 * bead, dir = 1, prev = null;
    while (v <= v1 - 1.5 * bead) {
      const a = to3(dir > 0 ? u0 + 1.5 * bead : u1 - 1.5 * bead, v), b = to3(dir > 0 ? u1 - 1.5 * bead : u0 + 1.5 * bead, v);
      if (prev === null) path.add(a, tiltFn(a, false), 0, region); // travel to the raster start
      else path.add(a, tiltFn(a, false), DEPOSIT, region); // step-over
      for (const q of along(a, b, 2.5)) path.add(q, tiltFn(q, false), DEPOSIT, region);
      prev = b; v += bead * 1.6; dir = -dir;
    }
    const area = (u1 - u0) * (v1 - v0);
    const contour = ringData([rect(u0, v0, u1, v1, to3, 2.5)]);
    const uns = ringData(unsupportedRings || []);
    const unsArea = (unsupportedRings || []).length ? 5.0 : 0;
    let maxTilt = 0;
    for (let i = first; i < path.length; i++) {
      const ax = path.a.slice(3 * i, 3 * i + 3);
      const d = ax[0] * normal[0] + ax[1] * normal[1] + ax[2] * normal[2];
      maxTilt = Math.max(maxTilt, (Math.acos(Math.min(1, d)) * 180) / Math.PI);
    }
    layers.push({
      index, region, origin, normal, thickness_mm: t, area_mm2: area, unsupported_area_mm2: unsArea,
      max_tilt_deg: Number(maxTilt.toFixed(3)), tilt_deg: region === 0 ? [-maxTilt, maxTilt] : [90 - maxTilt, 90 + maxTilt],
      c_deg: region === 0 ? [0, 0] : [-90, -90],
      contours: contour.data, contour_starts: contour.starts, unsupported: uns.data, unsupported_starts: uns.starts,
      path_first: first, path_count: path.length - first,
    });
  }
  // region 0: cube [0,20]^3 built along +Z, 12 layers; its top 4 layers tilt the perimeter axes outward 20 deg
  const t0 = 20 / 12;
  for (let k = 0; k < 12; k++) {
    const z = (k + 1) * t0;
    const tilt = (p, perimeter) => {
      if (!(perimeter && k >= 8)) return [0, 0, 1];
      const out = [p[0] - 10, p[1] - 10, 0];
      const n = Math.hypot(out[0], out[1]) || 1;
      return rot([0, 0, 1], 20, [-out[1] / n, out[0] / n, 0]); // lean away from the centre
    };
    const unsupported = k === 5 ? [rect(2, 2, 4, 4, (u, v) => [u, v, z], 0.5), rect(15, 15, 16, 16, (u, v) => [u, v, z], 0.5)] : null;
    layer(0, k, [0, 0, 1], [0, 0, z], (u, v) => [u, v, z], 0, 0, 20, 20, t0, tilt, unsupported);
  }
  // region 1: arm x in [20,32], y in [5,15], z in [8,16], built along +X, 8 layers; layer 3 tilted 10 deg about y
  const t1 = 12 / 8;
  for (let j = 0; j < 8; j++) {
    const x = 20 + (j + 1) * t1;
    const tilt = () => (j === 3 ? rot([1, 0, 0], 10, [0, 1, 0]) : [1, 0, 0]);
    layer(1, 12 + j, [1, 0, 0], [x, 0, 0], (u, v) => [x, u, v], 5, 8, 15, 16, t1, tilt, null);
  }
  const n = path.length;
  let length = 0;
  for (let i = 1; i < n; i++) {
    if (path.f[i] & NEW_PATH) continue;
    length += Math.hypot(path.p[3 * i] - path.p[3 * i - 3], path.p[3 * i + 1] - path.p[3 * i - 2], path.p[3 * i + 2] - path.p[3 * i - 1]);
  }
  return {
    format: 'polyaxis-view/1',
    title: 'cube_arm.stl',
    metrics: {
      part: 'cube_arm.stl', triangles: 24, volume_mm3: 8960, regions: 2, layers: layers.length, path_points: n,
      support_free: false, collision_free: false, unsupported_area_mm2: 5.0, collisions: 1,
      fidelity_symdiff_ratio: 0.012345, max_cusp_mm: 0.08213, reorientations: 1, path_length_mm: length,
      build_time_s: 3600.456, material_mm3: 8960, near_net_saving: 0.6312,
      axis_ranges: { x: [0, 32], y: [0, 20], z: [0, 20], a: [-20, 90], c: [-90, 0] },
      timings_s: { read: 0.00123, analyse: 0.0153, slice: 0.0341, toolpath: 0.0222, total: 0.2 },
      warnings: ['layer 5: unsupported area 5 mm²', 'collision at layer 19'],
    },
    machine: { name: 'ded5_ac', kinematics: 'xyzac-trt', tilt_axis: 'A' },
    bead_width_mm: bead,
    regions: [
      { id: 0, parent: null, build_direction: [0, 0, 1], base_point: [10, 10, 0], volume_mm3: 8000, support_free: false, ...boxMesh(0, 0, 0, 20, 20, 20) },
      { id: 1, parent: 0, build_direction: [1, 0, 0], base_point: [20, 10, 12], volume_mm3: 960, support_free: true, ...boxMesh(20, 5, 8, 32, 15, 16) },
    ],
    axis: {
      nodes: [[10, 10, 0], [10, 10, 5], [10, 10, 10], [10, 10, 15], [10, 10, 20], [20, 10, 12], [26, 10, 12], [32, 10, 12]],
      links: [[0, 1, 0], [1, 2, 0], [2, 3, 0], [3, 4, 0], [2, 5, 1], [5, 6, 0], [6, 7, 0]],
    },
    layers,
    toolpath: path.encode(),
    collisions: [{ position: [32, 10, 17], what: 'nozzle cone vs arm (layer 19)' }],
  };
}

function big(nPoints, nLayers) {
  const H = 100, t = H / nLayers, bead = 0.9, seg = 64;
  const radius = (z) => 25 + 8 * Math.sin(z / 15);
  const dr = (z) => (8 / 15) * Math.cos(z / 15);
  const perLayer = Math.floor(nPoints / nLayers);
  const points = new Float32Array(3 * nPoints), axes = new Float32Array(3 * nPoints);
  const flags = new Uint8Array(nPoints), region = new Uint16Array(nPoints);
  const layers = [];
  const cN = 120;
  let w = 0;
  for (let k = 0; k < nLayers; k++) {
    const z = (k + 1) * t;
    const r = radius(z);
    const reg = z < H / 2 ? 0 : 1;
    const lean = Math.atan(dr(z)); // tilt the axis along the wall slope
    const count = k === nLayers - 1 ? nPoints - w : perLayer;
    const first = w;
    const loops = 3; // concentric loops from the wall inwards, travel between them
    for (let i = 0; i < count; i++) {
      const loop = Math.floor((i * loops) / count);
      const inLoop = (i * loops) / count - loop;
      const th = 2 * Math.PI * inLoop + k * 0.01;
      const rr = r - bead * (0.5 + loop);
      points[3 * w] = rr * Math.cos(th); points[3 * w + 1] = rr * Math.sin(th); points[3 * w + 2] = z;
      const tiltHere = loop === 0 ? lean : 0;
      axes[3 * w] = -Math.sin(tiltHere) * Math.cos(th); axes[3 * w + 1] = -Math.sin(tiltHere) * Math.sin(th); axes[3 * w + 2] = Math.cos(tiltHere);
      const loopStart = i === 0 || Math.floor(((i - 1) * loops) / count) !== loop;
      flags[w] = i === 0 ? NEW_PATH : loopStart ? 0 : DEPOSIT;
      region[w] = reg;
      w++;
    }
    const ring = [];
    for (let j = 0; j < cN; j++) { const th = (2 * Math.PI * j) / cN; ring.push([r * Math.cos(th), r * Math.sin(th), z]); }
    const rings = [ring];
    const unsupported = k % 250 === 125 ? [[[r - 2, -1, z], [r, -1, z], [r, 1, z], [r - 2, 1, z]]] : [];
    const c = ringData(rings), u = ringData(unsupported);
    const tiltDeg = (Math.abs(lean) * 180) / Math.PI;
    layers.push({
      index: k, region: reg, origin: [0, 0, z], normal: [0, 0, 1], thickness_mm: t, area_mm2: Math.PI * r * r,
      unsupported_area_mm2: unsupported.length ? 4 : 0, max_tilt_deg: tiltDeg, tilt_deg: [-tiltDeg, tiltDeg], c_deg: [-180, 180],
      contours: c.data, contour_starts: c.starts, unsupported: u.data, unsupported_starts: u.starts,
      path_first: first, path_count: count,
    });
  }
  // region meshes: the vase wall split at H/2
  const regionMesh = (z0, z1) => {
    const rings = 40, pos = [], idx = [];
    for (let i = 0; i <= rings; i++) {
      const z = z0 + ((z1 - z0) * i) / rings;
      for (let j = 0; j < seg; j++) { const th = (2 * Math.PI * j) / seg; pos.push(radius(z) * Math.cos(th), radius(z) * Math.sin(th), z); }
    }
    for (let i = 0; i < rings; i++) for (let j = 0; j < seg; j++) {
      const a = i * seg + j, b = i * seg + ((j + 1) % seg), c = a + seg, d = b + seg;
      idx.push(a, b, d, a, d, c);
    }
    return { positions: b64(Float32Array.from(pos)), indices: b64(Uint32Array.from(idx)) };
  };
  return {
    format: 'polyaxis-view/1',
    title: `vase_${nPoints}pts_${nLayers}layers.stl`,
    metrics: { part: 'vase (synthetic)', layers: nLayers, path_points: nPoints, support_free: false, timings_s: { total: 1.5 } },
    machine: { name: 'ded5_ac', kinematics: 'xyzac-trt', tilt_axis: 'A' },
    bead_width_mm: bead,
    regions: [
      { id: 0, parent: null, build_direction: [0, 0, 1], base_point: [0, 0, 0], volume_mm3: 1e5, support_free: true, ...regionMesh(0, H / 2) },
      { id: 1, parent: 0, build_direction: [0, 0, 1], base_point: [0, 0, H / 2], volume_mm3: 1e5, support_free: false, ...regionMesh(H / 2, H) },
    ],
    axis: { nodes: [[0, 0, 0], [0, 0, H / 2], [0, 0, H]], links: [[0, 1, 0], [1, 2, 1]] },
    layers,
    toolpath: { points: b64(points), axes: b64(axes), flags: b64(flags), region: b64(region), total_points: nPoints, shown_points: nPoints },
    collisions: [],
  };
}

const args = process.argv.slice(2);
const out = args.find((a) => !a.startsWith('--') && !/^\d+$/.test(a));
if (!out) {
  console.error('usage: node test/fixture.mjs OUT.json [--big [--points N] [--layers L]]');
  process.exit(2);
}
const opt = (name, def) => { const i = args.indexOf(name); return i >= 0 ? Number(args[i + 1]) : def; };
const data = args.includes('--big') ? big(opt('--points', 1000000), opt('--layers', 2000)) : small();
const text = JSON.stringify(data);
writeFileSync(out, text);
console.log(`wrote ${out}: ${data.layers.length} layers, ${Buffer.from(data.toolpath.flags, 'base64').length} path points, ${(text.length / 1048576).toFixed(2)} MiB`);
