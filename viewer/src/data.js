// Reads and checks the "polyaxis-view/1" data embedded in report.html.
// Binary arrays arrive as base64 strings of little-endian typed arrays; each is decoded once.

export const FORMAT = 'polyaxis-view/1';

const hasFromBase64 = typeof Uint8Array.fromBase64 === 'function';

export function bytesFromBase64(s, what) {
  if (s === undefined || s === null || s === '') return new Uint8Array(0);
  if (typeof s !== 'string') throw new Error(`${what}: expected a base64 string, got ${typeof s}`);
  try {
    if (hasFromBase64) return Uint8Array.fromBase64(s);
    const bin = atob(s);
    const n = bin.length;
    const out = new Uint8Array(n);
    for (let i = 0; i < n; i++) out[i] = bin.charCodeAt(i);
    return out;
  } catch (e) {
    throw new Error(`${what}: invalid base64 (${e.message})`);
  }
}

function typed(s, Ctor, what) {
  const b = bytesFromBase64(s, what);
  const size = Ctor.BYTES_PER_ELEMENT;
  if (b.byteLength % size !== 0) {
    throw new Error(`${what}: ${b.byteLength} bytes is not a multiple of ${size}`);
  }
  if (b.byteOffset % size !== 0) return new Ctor(b.slice().buffer);
  return new Ctor(b.buffer, b.byteOffset, b.byteLength / size);
}

function vec3s(s, what) {
  const a = typed(s, Float32Array, what);
  if (a.length % 3 !== 0) throw new Error(`${what}: ${a.length} floats is not a multiple of 3`);
  return a;
}

function vec3(v, what, fallback) {
  if (v === undefined || v === null) {
    if (fallback) return fallback.slice();
    throw new Error(`${what}: missing`);
  }
  if (!Array.isArray(v) || v.length !== 3 || !v.every((x) => typeof x === 'number' && Number.isFinite(x))) {
    throw new Error(`${what}: expected [x, y, z], got ${JSON.stringify(v)}`);
  }
  return v.slice();
}

function num(v, fallback = 0) {
  return typeof v === 'number' && Number.isFinite(v) ? v : fallback;
}

function range(v) {
  return Array.isArray(v) && v.length === 2 ? [num(v[0], NaN), num(v[1], NaN)] : [NaN, NaN];
}

function starts(v, npoints, what) {
  if (v === undefined || v === null) v = [];
  if (!Array.isArray(v)) throw new Error(`${what}: expected an array`);
  if (npoints === 0) return [];
  if (v.length === 0) return [0];
  let prev = -1;
  for (let k = 0; k < v.length; k++) {
    const s = v[k];
    if (!Number.isInteger(s) || s < 0 || s >= npoints || s <= prev) {
      throw new Error(`${what}[${k}] = ${s} is not an increasing index below ${npoints}`);
    }
    prev = s;
  }
  return v;
}

function decodeRegion(r, k) {
  const what = `regions[${k}]`;
  const positions = vec3s(r.positions, `${what}.positions`);
  const indices = typed(r.indices, Uint32Array, `${what}.indices`);
  if (indices.length % 3 !== 0) throw new Error(`${what}.indices: ${indices.length} is not a multiple of 3`);
  const nv = positions.length / 3;
  for (let i = 0; i < indices.length; i++) {
    if (indices[i] >= nv) throw new Error(`${what}.indices[${i}] = ${indices[i]} >= ${nv} vertices`);
  }
  return {
    id: Number.isInteger(r.id) ? r.id : k,
    parent: Number.isInteger(r.parent) ? r.parent : null,
    buildDirection: vec3(r.build_direction, `${what}.build_direction`, [0, 0, 1]),
    basePoint: vec3(r.base_point, `${what}.base_point`, [0, 0, 0]),
    volume: num(r.volume_mm3, NaN),
    supportFree: r.support_free,
    // Its layer strategy and why (plans before tilted layers have none).
    layers: r.layers && typeof r.layers.strategy === 'string' ? r.layers.strategy : null,
    layersWhy: r.layers && typeof r.layers.why === 'string' ? r.layers.why : '',
    // Already on the table (--substrate, --prebuilt): drawn grey, not deposited.
    prebuilt: r.prebuilt === true,
    positions,
    indices,
  };
}

function decodeToolpath(t) {
  if (!t) {
    return { n: 0, points: new Float32Array(0), axes: new Float32Array(0), flags: new Uint8Array(0),
      region: new Uint16Array(0), total: 0, shown: 0 };
  }
  const points = vec3s(t.points, 'toolpath.points');
  const n = points.length / 3;
  let axes = vec3s(t.axes, 'toolpath.axes');
  if (axes.length !== 0 && axes.length !== points.length) {
    throw new Error(`toolpath.axes: ${axes.length / 3} axes for ${n} points`);
  }
  const flags = bytesFromBase64(t.flags, 'toolpath.flags');
  if (flags.length !== n) throw new Error(`toolpath.flags: ${flags.length} flags for ${n} points`);
  // Region ids are Uint16 per point; accept Uint8 too (same count of bytes as points).
  const rb = bytesFromBase64(t.region, 'toolpath.region');
  let region;
  if (rb.length === 2 * n) region = new Uint16Array(rb.buffer, rb.byteOffset, n);
  else if (rb.length === n) region = Uint16Array.from(rb);
  else if (rb.length === 0) region = new Uint16Array(n);
  else throw new Error(`toolpath.region: ${rb.length} bytes for ${n} points (expected Uint16 per point)`);
  return { n, points, axes, flags, region, total: num(t.total_points, n), shown: num(t.shown_points, n) };
}

function decodeLayer(l, k, npath) {
  const what = `layers[${k}]`;
  const contours = vec3s(l.contours, `${what}.contours`);
  const contourStarts = starts(l.contour_starts, contours.length / 3, `${what}.contour_starts`);
  const unsupported = vec3s(l.unsupported, `${what}.unsupported`);
  const unsupportedStarts = starts(l.unsupported_starts, unsupported.length / 3, `${what}.unsupported_starts`);
  const pathFirst = Number.isInteger(l.path_first) ? l.path_first : 0;
  const pathCount = Number.isInteger(l.path_count) ? l.path_count : 0;
  if (pathFirst < 0 || pathCount < 0 || pathFirst + pathCount > npath) {
    throw new Error(`${what}: path points [${pathFirst}, ${pathFirst + pathCount}) outside the ${npath} toolpath points`);
  }
  const normal = vec3(l.normal, `${what}.normal`, [0, 0, 1]);
  const len = Math.hypot(normal[0], normal[1], normal[2]) || 1;
  return {
    index: Number.isInteger(l.index) ? l.index : k,
    region: Number.isInteger(l.region) ? l.region : null,
    origin: vec3(l.origin, `${what}.origin`, [0, 0, 0]),
    normal: normal.map((x) => x / len),
    thickness: num(l.thickness_mm, NaN),
    // Least and largest over the layer: they differ on tilted layers (plans before them have none).
    thicknessRange: range(l.thickness_range_mm ?? [l.thickness_mm, l.thickness_mm]),
    area: num(l.area_mm2, NaN),
    unsupportedArea: num(l.unsupported_area_mm2, 0),
    maxTilt: num(l.max_tilt_deg, NaN),
    tilt: range(l.tilt_deg),
    c: range(l.c_deg),
    contours,
    contourStarts,
    unsupported,
    unsupportedStarts,
    pathFirst,
    pathCount,
  };
}

function decodeAxis(a) {
  if (!a) return null;
  const nodes = Array.isArray(a.nodes) ? a.nodes : [];
  const pos = new Float32Array(nodes.length * 3);
  nodes.forEach((p, i) => pos.set(vec3(p, `axis.nodes[${i}]`), 3 * i));
  const links = Array.isArray(a.links) ? a.links : [];
  for (let i = 0; i < links.length; i++) {
    const l = links[i];
    if (!Array.isArray(l) || l.length < 2 || !(l[0] >= 0 && l[0] < nodes.length) || !(l[1] >= 0 && l[1] < nodes.length)) {
      throw new Error(`axis.links[${i}] = ${JSON.stringify(l)} does not join two of the ${nodes.length} nodes`);
    }
  }
  return { nodes: pos, links: links.map((l) => [l[0] | 0, l[1] | 0, l[2] ? 1 : 0]) };
}

// The machine playback (absent from pages written from plan.json alone): kinematics, bodies and
// frames, one per G-code block as the controller reads it.
function decodePlayback(p) {
  if (!p) return null;
  const joints = typed(p.joints, Float32Array, 'playback.joints');
  if (joints.length % 5 !== 0) throw new Error(`playback.joints: ${joints.length} floats is not a multiple of 5`);
  const n = joints.length / 5;
  const time = typed(p.time, Float32Array, 'playback.time');
  const line = typed(p.line, Uint32Array, 'playback.line');
  const layer = typed(p.layer, Int32Array, 'playback.layer');
  const flags = bytesFromBase64(p.flags, 'playback.flags');
  for (const [what, a] of [['time', time], ['line', line], ['layer', layer], ['flags', flags]]) {
    if (a.length !== n) throw new Error(`playback.${what}: ${a.length} values for ${n} frames`);
  }
  for (let i = 1; i < n; i++) {
    if (!(time[i] >= time[i - 1])) throw new Error(`playback.time[${i}] = ${time[i]} runs backwards`);
  }
  const nz = p.nozzle || {};
  const table = p.table || {};
  const plate = p.plate || {};
  let robot = null;
  if (p.robot) {
    const arm = typed(p.arm, Float32Array, 'playback.arm');
    if (arm.length !== 6 * n) throw new Error(`playback.arm: ${arm.length} floats for ${n} frames of six joints`);
    const list = (v, k, what) => {
      if (!Array.isArray(v) || v.length !== k || !v.every((x) => Number.isFinite(x))) throw new Error(`playback.robot.${what}: expected ${k} numbers`);
      return v.map(Number);
    };
    const r = p.robot;
    robot = { model: String(r.model ?? ''), geometry: list(r.geometry_mm, 7, 'geometry_mm'), sign: list(r.sign, 6, 'sign'),
      zero: list(r.zero_deg, 6, 'zero_deg'), base: list(r.base, 4, 'base'), tcp: list(r.tcp, 7, 'tcp'),
      checkTcp: list(r.check_tcp, 3, 'check_tcp'), arm };
  }
  return {
    kinematics: String(p.kinematics ?? 'xyz'),
    sense: p.sense === 1 ? 1 : -1,
    rotPoint: vec3(p.rot_point, 'playback.rot_point', [0, 0, 0]),
    offset: vec3(p.offset, 'playback.offset', [0, 0, 0]),
    pivotLength: num(p.pivot_length_mm, 0),
    nozzle: {
      halfAngle: num(nz.tip_half_angle_deg, 30), coneHeight: num(nz.cone_height_mm, 20),
      cylinderRadius: num(nz.cylinder_radius_mm, 25), cylinderHeight: num(nz.cylinder_height_mm, 150),
    },
    table: { radius: num(table.radius_mm, 250), centre: Array.isArray(table.centre) ? [num(table.centre[0]), num(table.centre[1])] : [0, 0],
      top: num(table.top_z_mm, -10) },
    plate: { x: range(plate.x_mm), y: range(plate.y_mm), top: num(plate.top_z_mm, 0), thickness: num(plate.thickness_mm, 10) },
    totalFrames: num(p.total_frames, n),
    duration: num(p.duration_s, n ? time[n - 1] : 0),
    n, joints, time, line, layer, flags, robot,
  };
}

export function decode(raw) {
  if (!raw || typeof raw !== 'object') throw new Error('polyaxis-data: not a JSON object');
  if (raw.format !== FORMAT) {
    throw new Error(`polyaxis-data: format ${JSON.stringify(raw.format)} is not supported (expected "${FORMAT}")`);
  }
  const toolpath = decodeToolpath(raw.toolpath);
  const regions = (raw.regions || []).map(decodeRegion);
  const layers = (raw.layers || []).map((l, k) => decodeLayer(l, k, toolpath.n));
  const collisions = (raw.collisions || []).map((c, i) => ({
    position: vec3(c.position, `collisions[${i}].position`),
    what: String(c.what ?? ''),
    line: Number.isInteger(c.line) ? c.line : 0,
  }));
  return {
    title: String(raw.title ?? ''),
    metrics: raw.metrics && typeof raw.metrics === 'object' ? raw.metrics : {},
    machine: raw.machine && typeof raw.machine === 'object' ? raw.machine : {},
    bead: num(raw.bead_width_mm, NaN),
    regions,
    axis: decodeAxis(raw.axis),
    layers,
    toolpath,
    collisions,
    playback: decodePlayback(raw.playback),
  };
}

export function readData(doc) {
  const el = doc.getElementById('polyaxis-data');
  if (!el) throw new Error('the page has no script element with id "polyaxis-data" (type application/json)');
  let raw;
  try {
    raw = JSON.parse(el.textContent);
  } catch (e) {
    throw new Error(`polyaxis-data is not valid JSON: ${e.message}`);
  }
  return decode(raw);
}
