// Collision positions as red markers drawn on top of everything.
import { BufferAttribute, BufferGeometry, Color, Points, PointsMaterial } from 'three';
import { COLORS } from './colors.js';

export function buildCollisions(collisions) {
  const pos = new Float32Array(collisions.length * 3);
  collisions.forEach((c, i) => pos.set(c.position, 3 * i));
  const geom = new BufferGeometry();
  geom.setAttribute('position', new BufferAttribute(pos, 3));
  const points = new Points(geom, new PointsMaterial({
    color: new Color(COLORS.collision), size: 11, sizeAttenuation: false, depthTest: false, transparent: true,
  }));
  points.name = 'collisions';
  points.renderOrder = 14;
  points.visible = collisions.length > 0;
  return points;
}
