// polyaxis report viewer: reads <script id="polyaxis-data"> and builds the 3-D view and panels.
import { Box3, Group } from 'three';
import { readData } from './data.js';
import { createView, expandBox } from './scene.js';
import { regionColorMap, BACKGROUND, srgb8 } from './colors.js';
import { buildRegions } from './regions.js';
import { buildAxis } from './axis.js';
import { buildLayers } from './layers.js';
import { buildToolpaths } from './toolpaths.js';
import { buildCollisions } from './markers.js';
import { buildPanel } from './panel.js';
import { buildPlayback } from './playback.js';
import { fmtNum } from './format.js';
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
  const { diag, center } = view.frame(box, framed);

  const regions = buildRegions(data.regions, colorOf, diag);
  const axis = buildAxis(data.axis);
  const glyphLength = Number.isFinite(data.bead) && data.bead > 0 ? 2 * data.bead : diag * 0.02;
  const paths = buildToolpaths(data.toolpath, data.layers, colorOf, glyphLength);
  const collisions = buildCollisions(data.collisions);
  // Everything fixed to the part, in one group: a table-table machine's playback turns it.
  const part = new Group();
  part.add(layers.group, paths.group, regions.group, regions.arrows, axis, collisions);
  view.scene.add(part);

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

  const player = startPlayback(data, panel, part, view, setLayer, center, paths, { regions: regions.group, contours: layers.group });

  setLayer(nLayers - 1);
  view.render();

  Object.assign(api, {
    layerCount: nLayers,
    setLayer: (i) => { const k = setLayer(i); view.render(); return k; },
    renderNow: () => view.render(),
    // The camera FACTOR times as far from what it looks at (for the docs' pictures).
    zoom: (factor) => {
      view.camera.position.sub(view.controls.target).multiplyScalar(Number(factor) || 1).add(view.controls.target);
      view.controls.update();
      view.render();
    },
    stats: { ...paths.stats, decodeMs: tDecoded - t0, contourPoints: layers.contourPoints, regions: data.regions.length },
    playback: player,
  });
  Object.defineProperty(api, 'currentLayer', { get: () => current, enumerable: true });
  api.loadMs = performance.now() - t0;
  api.ready = true;
  document.body.dataset.ready = '1';
}

// The share of the page's pixel ratio drawn while the machine plays.
const PLAYING_PIXEL_RATIO = 0.5;

// Wires the playback controls (panel.playback) to the machine (playback.js); null without playback
// data. The returned object is the test hook: seek(t), play(), pause(), stop() and frame times.
function startPlayback(data, panel, part, view, setLayer, centre, paths, shells) {
  const pb = data.playback;
  const c = panel.playback;
  if (!pb || !c) return null;
  const byIndex = new Map(data.layers.map((l, k) => [l.index, k]));
  const machine = buildPlayback(pb, part, view.scene, data.collisions, (layer) => {
    const k = byIndex.get(layer);
    if (k !== undefined) setLayer(k);
  });
  let t = 0, playing = false, lastTs = null;
  const fullRatio = view.renderer.getPixelRatio();
  // The camera follows the part's centre as the table carries it (the view keeps its direction, so
  // the table's turning shows), and comes back with it when the playback stops.
  let followed = centre.clone();
  function follow() {
    const now = centre.clone().applyMatrix4(part.matrix);
    const d = now.clone().sub(followed);
    view.camera.position.add(d);
    view.controls.target.add(d);
    view.controls.update();
    followed = now;
  }
  const intervals = [];
  const names = ['X', 'Y', 'Z', data.machine.tilt_axis || 'T', 'C'];
  function seek(to) {
    if (!machine.isActive()) machine.setActive(true);
    t = Math.max(0, Math.min(pb.duration, Number(to) || 0));
    const s = machine.show(t);
    follow();
    c.time.value = String(pb.duration > 0 ? Math.round((t / pb.duration) * 10000) : 0);
    if (s) {
      const axes = s.joints.map((v, a) => `${names[a]}${v.toFixed(a < 3 ? 2 : 1)}`).join(' ');
      c.readout.textContent = `t ${fmtNum(t)} s of ${fmtNum(pb.duration)} s · line ${s.line}\n${axes}\n` +
        `process ${s.processOn ? 'ON' : 'off'}${s.rapid ? ' · rapid' : ''} · layer ${s.layer}` +
        (s.struck !== null ? `\nCOLLISION at line ${s.struck}` : '');
      c.readout.classList.toggle('px-struck', s.struck !== null);
    }
    view.requestRender();
    return s;
  }
  function tick(ts) {
    if (!playing) return;
    if (lastTs !== null) {
      const dt = ts - lastTs;
      intervals.push(dt);
      if (intervals.length > 600) intervals.shift();
      const next = t + (dt / 1000) * Number(c.speed.value);
      if (next >= pb.duration) pause();
      seek(next);
    }
    lastTs = ts;
    if (playing) requestAnimationFrame(tick);
  }
  function play() {
    if (playing) return;
    if (t >= pb.duration) t = 0;
    playing = true;
    lastTs = null;
    paths.setLight(true);
    // The regions' shells and the contours are hidden while playing: the deposit shows the part.
    for (const o of Object.values(shells)) o.visible = false;
    // Half the pixels while playing: software WebGL pays for every blended pixel of every frame.
    view.renderer.setPixelRatio(PLAYING_PIXEL_RATIO * fullRatio);
    view.renderer.setSize(window.innerWidth, window.innerHeight, false);
    c.play.textContent = '❚❚ pause';
    requestAnimationFrame(tick);
  }
  function pause() {
    playing = false;
    paths.setLight(false, { travel: panel.checks.travel.checked, glyphs: panel.checks.glyphs.checked });
    for (const [key, o] of Object.entries(shells)) o.visible = panel.checks[key].checked;
    view.renderer.setPixelRatio(fullRatio);
    view.renderer.setSize(window.innerWidth, window.innerHeight, false);
    c.play.textContent = '▶ play';
    view.requestRender();
  }
  function stop() {
    pause();
    machine.setActive(false);
    follow();
    c.readout.classList.remove('px-struck');
    setLayer(data.layers.length - 1);
    view.requestRender();
  }
  c.play.addEventListener('click', () => (playing ? pause() : play()));
  c.stop.addEventListener('click', stop);
  c.time.addEventListener('input', () => seek((Number(c.time.value) / 10000) * pb.duration));
  window.addEventListener('keydown', (e) => {
    if (e.key !== ' ' || e.target instanceof HTMLInputElement || e.target instanceof HTMLButtonElement) return;
    e.preventDefault();
    if (playing) pause(); else play();
  });
  return {
    duration: pb.duration, frames: pb.n, seek: (to) => { const s = seek(to); view.render(); return s; }, play, pause, stop,
    isPlaying: () => playing,
    // Milliseconds between the animation frames while playing (each draws the moved machine).
    frameTimes: () => intervals.slice(),
    // A robot cell: the first frame's TCP by polyaxis's own forward kinematics (to hold the arm's
    // drawing to), and each frame's time (to seek exactly onto a frame).
    robot: pb.robot ? { model: pb.robot.model, checkTcp: pb.robot.checkTcp.slice() } : null,
    frameTime: (i) => pb.time[Math.max(0, Math.min(pb.n - 1, i))],
  };
}

try {
  start();
} catch (err) {
  showError(err);
  throw err;
}
