// Region meshes (semi-transparent, one colour each), their feature edges and build-direction arrows.
import {
  ArrowHelper, BufferAttribute, BufferGeometry, Color, DoubleSide, EdgesGeometry, Group, LineBasicMaterial,
  LineSegments, Mesh, MeshPhongMaterial, Vector3,
} from 'three';
import { PREBUILT_COLOR } from './colors.js';

// A prebuilt part (substrate) is less see-through than the regions deposited onto it.
const PREBUILT_OPACITY = 0.45;
const MAX_EDGE_TRIANGLES = 300000; // feature edges cost a hash map per edge; skip them on huge meshes

export function buildRegions(regions, colorOf, diag) {
  const group = new Group();
  group.name = 'regions';
  const arrows = new Group();
  arrows.name = 'arrows';
  const arrowLength = Math.max(diag * 0.28, 1e-3);
  for (const r of regions) {
    const color = new Color(r.prebuilt ? PREBUILT_COLOR : colorOf(r.id));
    if (r.indices.length > 0) {
      const geom = new BufferGeometry();
      geom.setAttribute('position', new BufferAttribute(r.positions, 3));
      geom.setIndex(new BufferAttribute(r.indices, 1));
      geom.computeBoundingSphere();
      const mesh = new Mesh(geom, new MeshPhongMaterial({
        color, transparent: true, opacity: r.prebuilt ? PREBUILT_OPACITY : 0.2, depthWrite: false, side: DoubleSide, flatShading: true,
        shininess: 20,
      }));
      mesh.renderOrder = 2;
      group.add(mesh);
      if (r.indices.length / 3 <= MAX_EDGE_TRIANGLES) {
        const edges = new LineSegments(new EdgesGeometry(geom, 25), new LineBasicMaterial({
          color: color.clone().multiplyScalar(0.6), transparent: true, opacity: 0.55,
        }));
        edges.renderOrder = 2;
        group.add(edges);
      }
    }
    const d = new Vector3(...r.buildDirection);
    if (d.lengthSq() > 0 && !r.prebuilt) {
      d.normalize();
      const arrow = new ArrowHelper(d, new Vector3(...r.basePoint), arrowLength,
        color.clone().multiplyScalar(0.75), arrowLength * 0.22, arrowLength * 0.1);
      arrows.add(arrow);
    }
  }
  return { group, arrows };
}
