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

// Below the current layer at most this many layers' contours are drawn (every n-th layer):
// thousands of thin layers would only paint the part grey.
export const MAX_PAST_CONTOUR_LAYERS = 250;

export function buildLayers(layers) {
  const every = Math.max(1, Math.ceil(layers.length / MAX_PAST_CONTOUR_LAYERS));
  const contours = mergeRings(layers, 'contours', 'contourStarts', every);
  const unsupported = mergeRings(layers, 'unsupported', 'unsupportedStarts');

  const currentGeom = ringGeometry(contours);
  const pastGeom = shareGeometry(currentGeom);
  if (every > 1) pastGeom.setIndex(new BufferAttribute(contours.sampled, 1));
  const unsupportedGeom = ringGeometry(unsupported);

  const group = new Group();
  group.name = 'layers';
  const past = lines(pastGeom, new LineBasicMaterial({
    color: new Color(COLORS.contour), transparent: true, opacity: 0.4,
  }), 1);
  const current = lines(currentGeom, new LineBasicMaterial({
    color: new Color(COLORS.currentContour), depthTest: false, transparent: true,
  }), 12);
  const unsup = lines(unsupportedGeom, new LineBasicMaterial({
    color: new Color(COLORS.unsupported), depthTest: false, transparent: true,
  }), 13);
  group.add(past, current, unsup);

  const cEnds = contours.ends;
  const sEnds = contours.sampledEnds;
  const uEnds = unsupported.ends;
  function setLayer(k) {
    setRange(pastGeom, 0, k > 0 ? sEnds[k - 1] : 0);
    setRange(currentGeom, k > 0 ? cEnds[k - 1] : 0, k >= 0 ? cEnds[k] : 0);
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
