// polyaxis report viewer: reads <script id="polyaxis-data"> and builds the 3-D view and panels.
import { Box3 } from 'three';
import { readData } from './data.js';
import { createView, expandBox } from './scene.js';
import { regionColorMap, BACKGROUND, srgb8 } from './colors.js';
import { buildRegions } from './regions.js';
import { buildAxis } from './axis.js';
import { buildLayers } from './layers.js';
import { buildToolpaths } from './toolpaths.js';
import { buildCollisions } from './markers.js';
import { buildPanel } from './panel.js';
import { injectStyle } from './style.js';

function showError(err) {
  const msg = err && err.message ? err.message : String(err);
  const box = document.createElement('div');
  box.className = 'px-error';
  box.id = 'px-error';
  box.textContent = `polyaxis viewer: ${msg}`;
  (document.body || document.documentElement).appendChild(box);
  if (document.body) document.body.dataset.error = '1';
  console.error(`polyaxis viewer: ${msg}`, err && err.stack ? `\n${err.stack}` : '');
}

function start() {
  const t0 = performance.now();
  const api = {
    ready: false, layerCount: 0, currentLayer: -1, loadMs: NaN, background: srgb8(BACKGROUND),
    setLayer() {}, renderNow() {},
  };
  window.polyaxisViewer = api;
  injectStyle();

  const data = readData(document);
  const tDecoded = performance.now();
  const view = createView(document.body);
  const colorOf = regionColorMap(data.regions);

  // framing box: regions, else toolpath, else contours
  const box = new Box3();
  let framed = data.regions.map((r) => r.positions);
  for (const a of framed) expandBox(box, a);
  const layers = buildLayers(data.layers);
  if (box.isEmpty()) expandBox(box, (framed = [data.toolpath.points])[0]);
  if (box.isEmpty()) expandBox(box, (framed = [layers.contourPositions])[0]);
  const { diag } = view.frame(box, framed);

  const regions = buildRegions(data.regions, colorOf, diag);
  const axis = buildAxis(data.axis);
  const glyphLength = Number.isFinite(data.bead) && data.bead > 0 ? 2 * data.bead : diag * 0.02;
  const paths = buildToolpaths(data.toolpath, data.layers, colorOf, glyphLength);
  const collisions = buildCollisions(data.collisions);
  view.scene.add(layers.group, paths.group, regions.group, regions.arrows, axis, collisions);

  const panel = buildPanel(document.body, data, colorOf, { tilted: paths.tiltedCount });
  const nLayers = data.layers.length;
  let current = -1;

  function setLayer(i) {
    const k = nLayers === 0 ? -1 : Math.max(0, Math.min(nLayers - 1, Math.round(Number(i)) || 0));
    current = k;
    layers.setLayer(k);
    paths.setLayer(k);
    panel.showLayer(k);
    view.requestRender();
    return k;
  }

  panel.slider.addEventListener('input', () => setLayer(panel.slider.value));
  window.addEventListener('keydown', (e) => {
    if (e.target === panel.slider || e.altKey || e.ctrlKey || e.metaKey) return; // the slider steps itself
    const step = { ArrowLeft: -1, ArrowRight: 1, PageDown: -10, PageUp: 10 }[e.key];
    if (step !== undefined) setLayer(current + step);
    else if (e.key === 'Home') setLayer(0);
    else if (e.key === 'End') setLayer(nLayers - 1);
    else return;
    e.preventDefault();
  });
  const targets = {
    regions: [regions.group], arrows: [regions.arrows], axis: [axis], contours: [layers.group],
    deposit: [paths.deposit], travel: [paths.travel], glyphs: [paths.glyphs],
  };
  for (const [key, cb] of Object.entries(panel.checks)) {
    const apply = () => {
      if (key === 'fade') {
        paths.pastMaterial.opacity = cb.checked ? 0.55 : 1;
        paths.pastMaterial.transparent = cb.checked;
        paths.pastMaterial.needsUpdate = true;
      } else {
        for (const o of targets[key]) o.visible = cb.checked;
      }
      view.requestRender();
    };
    cb.addEventListener('change', apply);
    if (key === 'axis' && !data.axis) { cb.checked = false; cb.disabled = true; }
    apply();
  }

  setLayer(nLayers - 1);
  view.render();

  Object.assign(api, {
    layerCount: nLayers,
    setLayer: (i) => { const k = setLayer(i); view.render(); return k; },
    renderNow: () => view.render(),
    stats: { ...paths.stats, decodeMs: tDecoded - t0, contourPoints: layers.contourPoints, regions: data.regions.length },
  });
  Object.defineProperty(api, 'currentLayer', { get: () => current, enumerable: true });
  api.loadMs = performance.now() - t0;
  api.ready = true;
  document.body.dataset.ready = '1';
}

try {
  start();
} catch (err) {
  showError(err);
  throw err;
}
