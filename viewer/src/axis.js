// Centroidal axis graph: nodes as points, links as lines, break links in their own colour.
import {
  BufferAttribute, BufferGeometry, Color, Group, LineBasicMaterial, LineSegments, Points, PointsMaterial,
} from 'three';
import { COLORS } from './colors.js';

export function buildAxis(axis) {
  const group = new Group();
  group.name = 'axis';
  if (!axis || axis.nodes.length === 0) return group;
  const nodes = new BufferGeometry();
  nodes.setAttribute('position', new BufferAttribute(axis.nodes, 3));
  const points = new Points(nodes, new PointsMaterial({
    color: new Color(COLORS.axisNode), size: 6, sizeAttenuation: false, depthTest: false, transparent: true,
  }));
  points.renderOrder = 11;
  group.add(points);

  const n = axis.links.length;
  if (n > 0) {
    const pos = new Float32Array(n * 6);
    const col = new Float32Array(n * 6);
    const link = new Color(COLORS.axisLink), brk = new Color(COLORS.axisBreak);
    axis.links.forEach(([a, b, isBreak], k) => {
      pos.set(axis.nodes.subarray(3 * a, 3 * a + 3), 6 * k);
      pos.set(axis.nodes.subarray(3 * b, 3 * b + 3), 6 * k + 3);
      const c = isBreak ? brk : link;
      for (let j = 0; j < 2; j++) col.set([c.r, c.g, c.b], 6 * k + 3 * j);
    });
    const geom = new BufferGeometry();
    geom.setAttribute('position', new BufferAttribute(pos, 3));
    geom.setAttribute('color', new BufferAttribute(col, 3));
    const lines = new LineSegments(geom, new LineBasicMaterial({ vertexColors: true, depthTest: false, transparent: true }));
    lines.renderOrder = 10;
    group.add(lines);
  }
  return group;
}
