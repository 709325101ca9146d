// Helpers for big merged line buffers shown piecewise by draw ranges.
import { BufferAttribute, BufferGeometry } from 'three';

export function indexAttribute(array) {
  return new BufferAttribute(array, 1);
}

// A geometry over the same GPU buffers as geom (uploaded once), with its own draw range.
export function shareGeometry(geom) {
  const g = new BufferGeometry();
  for (const name of Object.keys(geom.attributes)) g.setAttribute(name, geom.getAttribute(name));
  if (geom.index) g.setIndex(geom.index);
  return g;
}

// Draw range [from, to) in index (or vertex) units.
export function setRange(geom, from, to) {
  geom.setDrawRange(from, Math.max(0, to - from));
}

// Merges the closed rings of every layer into one indexed LineSegments buffer, in layer order.
// ends[k] = number of indices that draw layers 0..k.
// With sampleEvery > 1 a second index (sampled, sampledEnds) holds only every n-th layer's rings.
export function mergeRings(layers, pointsKey, startsKey, sampleEvery = 1) {
  let floats = 0;
  let segments = 0;
  for (const l of layers) {
    const pts = l[pointsKey];
    const st = l[startsKey];
    floats += pts.length;
    const np = pts.length / 3;
    for (let r = 0; r < st.length; r++) {
      const m = (r + 1 < st.length ? st[r + 1] : np) - st[r];
      if (m >= 2) segments += m;
    }
  }
  const positions = new Float32Array(floats);
  const index = new Uint32Array(2 * segments);
  const ends = new Uint32Array(layers.length);
  let base = 0;
  let w = 0;
  layers.forEach((l, k) => {
    const pts = l[pointsKey];
    const st = l[startsKey];
    const np = pts.length / 3;
    positions.set(pts, 3 * base);
    for (let r = 0; r < st.length; r++) {
      const a = st[r];
      const b = r + 1 < st.length ? st[r + 1] : np; // ring = points a .. b-1, closed implicitly
      if (b - a < 2) continue;
      for (let i = a; i < b; i++) {
        index[w++] = base + i;
        index[w++] = base + (i + 1 < b ? i + 1 : a);
      }
    }
    base += np;
    ends[k] = w;
  });
  if (sampleEvery <= 1) return { positions, index, ends, sampled: index, sampledEnds: ends };
  let ns = 0;
  layers.forEach((l, k) => { if (k % sampleEvery === 0) ns += ends[k] - (k > 0 ? ends[k - 1] : 0); });
  const sampled = new Uint32Array(ns);
  const sampledEnds = new Uint32Array(layers.length);
  let ws = 0;
  layers.forEach((l, k) => {
    if (k % sampleEvery === 0) {
      const a = k > 0 ? ends[k - 1] : 0;
      sampled.set(index.subarray(a, ends[k]), ws);
      ws += ends[k] - a;
    }
    sampledEnds[k] = ws;
  });
  return { positions, index, ends, sampled, sampledEnds };
}
