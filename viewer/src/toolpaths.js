// Toolpaths: one buffer of points shared by the deposit and travel segment indices (both in layer order),
// plus tool-axis glyphs. "Layers up to k" is a draw range; the current layer is drawn on its own range.
import {
  BufferAttribute, BufferGeometry, Color, DynamicDrawUsage, Group, LineBasicMaterial, LineSegments,
} from 'three';
import { COLORS, rgb8 } from './colors.js';
import { setRange, shareGeometry } from './buffers.js';

export const MAX_GLYPHS = 20000; // glyphs of all layers together
export const MAX_CURRENT_GLYPHS = 4000; // glyphs of the current layer
// While the machine plays back, the layers below the current one are drawn from every n-th layer
// only, at most this many deposit segments in all: software WebGL draws a frame of a million
// segments in about half a second, of this many in a few tens of milliseconds.
export const MAX_PLAYING_SEGMENTS = 30000;
const DEPOSIT_SHADE = 0.7; // deposit lines darker than their region's mesh, to stand out inside it
const TILT_LIMIT_COS = Math.cos((1 * Math.PI) / 180); // tilted: more than 1 degree from the layer normal

function lines(geom, material, order) {
  const l = new LineSegments(geom, material);
  l.frustumCulled = false;
  l.renderOrder = order;
  return l;
}

export function buildToolpaths(tp, layers, colorOf, glyphLength) {
  const { n, points, axes, flags, region } = tp;
  const L = layers.length;

  // Per-point colour by region (normalized bytes).
  const colors = new Uint8Array(3 * n);
  const lut = new Map();
  let lastId = -1, cr = 0, cg = 0, cb = 0;
  for (let i = 0; i < n; i++) {
    const id = region[i];
    if (id !== lastId) {
      let c = lut.get(id);
      if (!c) { c = rgb8(colorOf(id)).map((x) => Math.round(x * DEPOSIT_SHADE)); lut.set(id, c); }
      [cr, cg, cb] = c;
      lastId = id;
    }
    colors[3 * i] = cr; colors[3 * i + 1] = cg; colors[3 * i + 2] = cb;
  }

  // Pass 1: count segments and glyph candidates per layer.
  let nDep = 0, nTrav = 0, nCand = 0;
  const candCount = new Uint32Array(L);
  const tiltedCount = new Uint32Array(L);
  const depositCount = new Uint32Array(L);
  const hasAxes = axes.length === 3 * n && n > 0;
  for (let k = 0; k < L; k++) {
    const { pathFirst: a, pathCount: c, normal: nm } = layers[k];
    let dep = 0, cand = 0, tilted = 0;
    for (let i = a; i < a + c; i++) {
      const f = flags[i];
      if (i > 0 && !(f & 2)) {
        if (f & 1) dep++;
        else nTrav++;
      }
      if (f & 1) cand++;
      if (hasAxes && axes[3 * i] * nm[0] + axes[3 * i + 1] * nm[1] + axes[3 * i + 2] * nm[2] < TILT_LIMIT_COS) tilted++;
    }
    nDep += dep;
    nCand += cand;
    depositCount[k] = dep;
    candCount[k] = cand;
    tiltedCount[k] = tilted;
  }
  const stride = Math.max(1, Math.ceil(nCand / MAX_GLYPHS));
  let nGlyph = 0;
  {
    let counter = 0;
    for (let k = 0; k < L; k++) {
      // glyphs chosen: candidates whose running number is a multiple of stride
      const c = candCount[k];
      const firstMultiple = Math.ceil(counter / stride) * stride;
      if (firstMultiple < counter + c) nGlyph += Math.floor((counter + c - 1 - firstMultiple) / stride) + 1;
      counter += c;
    }
  }
  if (!hasAxes) nGlyph = 0;

  // Pass 2: fill index buffers and glyphs in layer order.
  const depIdx = new Uint32Array(2 * nDep);
  const travIdx = new Uint32Array(2 * nTrav);
  const depEnds = new Uint32Array(L), travEnds = new Uint32Array(L), glyphEnds = new Uint32Array(L);
  const gPos = new Float32Array(6 * nGlyph);
  const gCol = new Uint8Array(6 * nGlyph);
  const plain = rgb8(COLORS.glyph), tiltedColor = rgb8(COLORS.glyphTilted);
  let wd = 0, wt = 0, wg = 0, counter = 0;
  const putGlyph = (pos, col, w, i, nm) => {
    const x = points[3 * i], y = points[3 * i + 1], z = points[3 * i + 2];
    const ax = axes[3 * i], ay = axes[3 * i + 1], az = axes[3 * i + 2];
    const o = 6 * w;
    pos[o] = x; pos[o + 1] = y; pos[o + 2] = z;
    pos[o + 3] = x + ax * glyphLength; pos[o + 4] = y + ay * glyphLength; pos[o + 5] = z + az * glyphLength;
    const c = ax * nm[0] + ay * nm[1] + az * nm[2] < TILT_LIMIT_COS ? tiltedColor : plain;
    col[o] = col[o + 3] = c[0]; col[o + 1] = col[o + 4] = c[1]; col[o + 2] = col[o + 5] = c[2];
  };
  for (let k = 0; k < L; k++) {
    const { pathFirst: a, pathCount: c, normal: nm } = layers[k];
    for (let i = a; i < a + c; i++) {
      const f = flags[i];
      if (i > 0 && !(f & 2)) {
        if (f & 1) { depIdx[wd++] = i - 1; depIdx[wd++] = i; }
        else { travIdx[wt++] = i - 1; travIdx[wt++] = i; }
      }
      if (f & 1) {
        if (nGlyph > 0 && counter % stride === 0) putGlyph(gPos, gCol, wg++, i, nm);
        counter++;
      }
    }
    depEnds[k] = wd; travEnds[k] = wt; glyphEnds[k] = wg;
  }
  if (wd !== depIdx.length || wt !== travIdx.length || wg !== nGlyph) {
    throw new Error(`internal: toolpath buffer sizes disagree (${wd}/${depIdx.length}, ${wt}/${travIdx.length}, ${wg}/${nGlyph})`);
  }

  // The light index for playback: the deposit of every EVERY-th layer, in layer order.
  const every = Math.max(1, Math.ceil(nDep / MAX_PLAYING_SEGMENTS));
  let nLight = 0;
  for (let k = 0; k < L; k += every) nLight += 2 * depositCount[k];
  const lightIdx = new Uint32Array(nLight);
  const lightEnds = new Uint32Array(L);
  {
    let w = 0;
    for (let k = 0; k < L; k++) {
      if (k % every === 0) {
        const a = k > 0 ? depEnds[k - 1] : 0;
        lightIdx.set(depIdx.subarray(a, depEnds[k]), w);
        w += depEnds[k] - a;
      }
      lightEnds[k] = w;
    }
  }

  const position = new BufferAttribute(points, 3);
  const color = new BufferAttribute(colors, 3, true);
  const depPast = new BufferGeometry();
  depPast.setAttribute('position', position);
  depPast.setAttribute('color', color);
  depPast.setIndex(new BufferAttribute(depIdx, 1));
  const depCur = shareGeometry(depPast);
  const depLight = new BufferGeometry();
  depLight.setAttribute('position', position);
  depLight.setAttribute('color', color);
  depLight.setIndex(new BufferAttribute(lightIdx, 1));
  depLight.setDrawRange(0, 0);
  const trav = new BufferGeometry();
  trav.setAttribute('position', position);
  trav.setIndex(new BufferAttribute(travIdx, 1));
  const glyphPast = new BufferGeometry();
  glyphPast.setAttribute('position', new BufferAttribute(gPos, 3));
  glyphPast.setAttribute('color', new BufferAttribute(gCol, 3, true));

  // The current layer's glyphs, denser than the global stride.
  const cPos = new Float32Array(6 * MAX_CURRENT_GLYPHS);
  const cCol = new Uint8Array(6 * MAX_CURRENT_GLYPHS);
  const glyphCur = new BufferGeometry();
  const cPosAttr = new BufferAttribute(cPos, 3).setUsage(DynamicDrawUsage);
  const cColAttr = new BufferAttribute(cCol, 3, true).setUsage(DynamicDrawUsage);
  glyphCur.setAttribute('position', cPosAttr);
  glyphCur.setAttribute('color', cColAttr);
  glyphCur.setDrawRange(0, 0);

  const pastMaterial = new LineBasicMaterial({ vertexColors: true, transparent: true, opacity: 0.55 });
  const deposit = new Group();
  const pastLines = lines(depPast, pastMaterial, 3);
  const lightLines = lines(depLight, pastMaterial, 3);
  lightLines.visible = false;
  deposit.add(pastLines, lightLines, lines(depCur, new LineBasicMaterial({ vertexColors: true }), 4));
  const travel = lines(trav, new LineBasicMaterial({
    color: new Color(COLORS.travel), transparent: true, opacity: 0.35,
  }), 3);
  const glyphs = new Group();
  glyphs.add(lines(glyphPast, new LineBasicMaterial({ vertexColors: true, transparent: true, opacity: 0.45 }), 5),
    lines(glyphCur, new LineBasicMaterial({ vertexColors: true }), 6));
  const group = new Group();
  group.name = 'toolpaths';
  group.add(deposit, travel, glyphs);

  function setLayer(k) {
    if (k < 0 || L === 0) {
      for (const g of [depPast, depLight, depCur, trav, glyphPast, glyphCur]) g.setDrawRange(0, 0);
      return;
    }
    const dPrev = k > 0 ? depEnds[k - 1] : 0;
    setRange(depPast, 0, dPrev);
    setRange(depLight, 0, k > 0 ? lightEnds[k - 1] : 0);
    setRange(depCur, dPrev, depEnds[k]);
    setRange(trav, 0, travEnds[k]);
    setRange(glyphPast, 0, 2 * (k > 0 ? glyphEnds[k - 1] : 0));
    let g = 0;
    if (hasAxes) {
      const { pathFirst: a, pathCount: c, normal: nm } = layers[k];
      const s = Math.max(1, Math.ceil(candCount[k] / MAX_CURRENT_GLYPHS));
      let cnt = 0;
      for (let i = a; i < a + c && g < MAX_CURRENT_GLYPHS; i++) {
        if (!(flags[i] & 1)) continue;
        if (cnt++ % s === 0) putGlyph(cPos, cCol, g++, i, nm);
      }
      cPosAttr.needsUpdate = true;
      cColAttr.needsUpdate = true;
    }
    glyphCur.setDrawRange(0, 2 * g);
  }

  // Light drawing while the machine plays: the lower layers sampled, no travel or glyphs (the
  // head's motion shows them). SHOWN: the travel and glyph toggles, restored when it ends.
  function setLight(on, shown = { travel: true, glyphs: true }) {
    pastLines.visible = !on;
    lightLines.visible = on;
    travel.visible = !on && shown.travel;
    glyphs.visible = !on && shown.glyphs;
  }

  return {
    group, deposit, travel, glyphs, setLayer, setLight, pastMaterial,
    stats: { depositSegments: nDep, travelSegments: nTrav, glyphs: nGlyph, glyphStride: stride },
    tiltedCount, depositCount,
  };
}
