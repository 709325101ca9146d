// Layer contours (all layers merged in one buffer) and unsupported rings; "layers up to k" by draw ranges.
import { BufferAttribute, BufferGeometry, Color, Group, LineBasicMaterial, LineSegments } from 'three';
import { COLORS } from './colors.js';
import { mergeRings, setRange, shareGeometry } from './buffers.js';

function ringGeometry(merged) {
  const g = new BufferGeometry();
  g.setAttribute('position', new BufferAttribute(merged.positions, 3));
  g.setIndex(new BufferAttribute(merged.index, 1));
  return g;
}

function lines(geom, material, order) {
  const l = new LineSegments(geom, material);
  l.frustumCulled = false;
  l.renderOrder = order;
  return l;
}

export function buildLayers(layers) {
  const contours = mergeRings(layers, 'contours', 'contourStarts');
  const unsupported = mergeRings(layers, 'unsupported', 'unsupportedStarts');

  const pastGeom = ringGeometry(contours);
  const currentGeom = shareGeometry(pastGeom);
  const unsupportedGeom = ringGeometry(unsupported);

  const group = new Group();
  group.name = 'layers';
  const past = lines(pastGeom, new LineBasicMaterial({
    color: new Color(COLORS.contour), transparent: true, opacity: 0.45,
  }), 1);
  const current = lines(currentGeom, new LineBasicMaterial({
    color: new Color(COLORS.currentContour), depthTest: false, transparent: true,
  }), 12);
  const unsup = lines(unsupportedGeom, new LineBasicMaterial({
    color: new Color(COLORS.unsupported), depthTest: false, transparent: true,
  }), 13);
  group.add(past, current, unsup);

  const cEnds = contours.ends;
  const uEnds = unsupported.ends;
  function setLayer(k) {
    const prev = k > 0 ? cEnds[k - 1] : 0;
    setRange(pastGeom, 0, prev);
    setRange(currentGeom, prev, k >= 0 ? cEnds[k] : 0);
    setRange(unsupportedGeom, 0, k >= 0 ? uEnds[k] : 0);
  }
  return {
    group,
    setLayer,
    contourPoints: contours.positions.length / 3,
    unsupportedPositions: unsupported.positions,
    contourPositions: contours.positions,
  };
}
