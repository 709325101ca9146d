// HTML overlay: title, layer slider and layer facts, toggles, region legend, collisions, metrics.
import { fmtNum, fmtRange, fmtValue, fmtVec } from './format.js';
import { COLORS, PREBUILT_COLOR } from './colors.js';

function el(tag, props = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(props)) {
    if (k === 'class') e.className = v;
    else if (k === 'text') e.textContent = v;
    else if (k === 'style') e.style.cssText = v;
    else if (k in e) e[k] = v;
    else e.setAttribute(k, v);
  }
  for (const c of children) if (c !== null && c !== undefined) e.append(c);
  return e;
}

function kvList(entries) {
  const dl = el('dl', { class: 'px-kv' });
  for (const [k, v, cls] of entries) dl.append(el('dt', { text: k }), el('dd', { class: cls || '' }, v));
  return dl;
}

// A text value longer than this is shown under its key, across the panel (strategy_reason).
const LONG_TEXT = 40;

// Metrics: every key; small objects are listed one level deeper.
function metricsList(metrics) {
  const entries = [];
  for (const [k, v] of Object.entries(metrics)) {
    if (v && typeof v === 'object' && !Array.isArray(v)) {
      entries.push([k, '']);
      for (const [k2, v2] of Object.entries(v)) entries.push([`  ${k2}`, fmtValue(v2), 'px-nested']);
    } else {
      entries.push([k, fmtValue(v), typeof v === 'string' && v.length > LONG_TEXT ? 'px-long' : '']);
    }
  }
  const dl = kvList(entries);
  dl.classList.add('px-metrics');
  dl.querySelectorAll('dt').forEach((dt) => {
    if (dt.textContent.startsWith('  ')) { dt.style.paddingLeft = '10px'; dt.textContent = dt.textContent.trim(); }
    // A long key may wrap after its underscores, so the values keep room for a word.
    const pieces = dt.textContent.split(/(?<=_)/);
    dt.textContent = '';
    pieces.forEach((p, i) => dt.append(...(i ? [el('wbr'), p] : [p])));
  });
  return dl;
}

export function buildPanel(root, data, colorOf, extra) {
  const { machine, regions, layers, toolpath, collisions } = data;
  const tiltName = machine.tilt_axis ? `${machine.tilt_axis}` : 'tilt';

  // ---- left panel
  const left = el('div', { class: 'px-panel px-left', id: 'px-panel' });
  left.append(el('h1', { text: data.title || 'polyaxis plan' }));
  const mparts = [machine.name, machine.kinematics, machine.tilt_axis ? `tilt axis ${machine.tilt_axis}` : '']
    .filter(Boolean);
  left.append(el('div', { class: 'px-sub', text: mparts.length ? `machine: ${mparts.join(' · ')}` : 'machine: –' }));
  const shown = toolpath.shown !== toolpath.total
    ? `${fmtNum(toolpath.shown)} of ${fmtNum(toolpath.total)} toolpath points shown`
    : `${fmtNum(toolpath.n)} toolpath points`;
  left.append(el('div', { class: 'px-sub', text: `${regions.length} region${regions.length === 1 ? '' : 's'} · ${layers.length} layer${layers.length === 1 ? '' : 's'} · ${shown}` }));

  // layer slider
  left.append(el('h2', { text: 'Layer' }));
  const slider = el('input', {
    type: 'range', id: 'layer-slider', min: '0', max: String(Math.max(0, layers.length - 1)), step: '1',
    value: String(Math.max(0, layers.length - 1)), disabled: layers.length === 0, title: 'layer (←/→)',
  });
  const layerNo = el('span', { class: 'px-layer-no', id: 'px-layer-no' });
  left.append(el('div', { class: 'px-slider-row' }, slider, layerNo));
  // strip under the slider: layers with unsupported area in red
  const strip = el('canvas', { class: 'px-strip', width: 280, height: 4 });
  left.append(strip);
  if (layers.some((l) => l.unsupportedArea > 0)) {
    const ctx = strip.getContext('2d');
    ctx.fillStyle = COLORS.unsupported;
    const w = strip.width;
    layers.forEach((l, k) => {
      if (l.unsupportedArea > 0) {
        const x = layers.length > 1 ? (k / (layers.length - 1)) * (w - 2) : 0;
        ctx.fillRect(Math.floor(x), 0, 2, strip.height);
      }
    });
  }
  const layerInfo = el('div', { id: 'px-layer-info' });
  left.append(layerInfo);

  // toggles
  left.append(el('h2', { text: 'Show' }));
  const toggles = el('div', { class: 'px-toggles' });
  const checks = {};
  for (const [key, label, on] of [['regions', 'part / regions', true], ['arrows', 'build arrows', true],
    ['axis', 'axis', true], ['contours', 'contours', true], ['deposit', 'deposit paths', true],
    ['travel', 'travel', true], ['glyphs', 'tool axes', true], ['fade', 'fade lower layers', true]]) {
    const cb = el('input', { type: 'checkbox', checked: on, id: `px-toggle-${key}` });
    checks[key] = cb;
    toggles.append(el('label', {}, cb, ` ${label}`));
  }
  left.append(toggles);

  // legend
  if (regions.length) {
    left.append(el('h2', { text: 'Regions' }));
    const table = el('table', { class: 'px-legend' });
    table.append(el('tr', {}, ...['', 'id', 'direction', 'volume', 'supp.-free', 'layers'].map((h) => el('th', { text: h }))));
    for (const r of regions) {
      const sf = r.supportFree === true ? 'yes' : r.supportFree === false ? 'no' : '–';
      table.append(el('tr', { title: r.parent !== null ? `parent region ${r.parent}` : 'root region' },
        el('td', {}, el('span', { class: 'px-swatch', style: `background:${r.prebuilt ? PREBUILT_COLOR : colorOf(r.id)}` })),
        el('td', { text: String(r.id) }),
        el('td', { text: fmtVec(r.buildDirection, 2) }),
        el('td', { text: Number.isNaN(r.volume) ? '–' : `${fmtNum(r.volume)} mm³` }),
        el('td', { text: sf, class: r.supportFree === false ? 'px-bad' : '' }),
        el('td', r.prebuilt ? { text: 'prebuilt', title: 'already on the table: not deposited' } : { text: r.layers ?? '–', title: r.layersWhy })));
    }
    left.append(table);
  }

  // machine playback: the program as the controller runs it
  let playback = null;
  if (data.playback && data.playback.n > 0) {
    const pb = data.playback;
    left.append(el('h2', { text: 'Machine playback' }));
    const play = el('button', { id: 'px-play', text: '▶ play', title: 'play or pause the program (space)' });
    const stop = el('button', { id: 'px-stop', text: '■ stop', title: 'leave the playback: the part as planned' });
    const speed = el('select', { id: 'px-speed', title: 'machine seconds per second' });
    for (const v of [1, 10, 100, 1000, 10000]) speed.append(el('option', { value: String(v), text: `${fmtNum(v)}×` }));
    speed.value = String(pb.duration > 20000 ? 1000 : pb.duration > 2000 ? 100 : 10);
    const time = el('input', { type: 'range', id: 'px-time', min: '0', max: '10000', step: '1', value: '0', title: 'program time' });
    const readout = el('div', { id: 'px-playback-info', class: 'px-readout' });
    left.append(el('div', { class: 'px-play-row' }, play, stop, speed));
    left.append(el('div', { class: 'px-slider-row' }, time));
    left.append(readout);
    const frames = pb.totalFrames !== pb.n ? `${fmtNum(pb.n)} of ${fmtNum(pb.totalFrames)} blocks kept` : `${fmtNum(pb.n)} blocks`;
    readout.textContent = `${frames}, ${fmtNum(pb.duration)} s of machine time`;
    playback = { play, stop, speed, time, readout };
  }

  if (collisions.length) {
    left.append(el('h2', { text: `Collisions (${collisions.length})`, class: 'px-bad' }));
    const list = collisions.slice(0, 8).map((c) => [fmtVec(c.position, 1), c.what]);
    if (collisions.length > 8) list.push(['…', `${collisions.length - 8} more`]);
    left.append(kvList(list));
  }
  if (extra && extra.hint) left.append(el('div', { class: 'px-hint', text: extra.hint }));
  left.append(el('div', { class: 'px-hint', text: 'drag: orbit · right-drag/shift-drag: pan · wheel: zoom · ←/→: layer' }));

  // ---- right panel: metrics
  const right = el('div', { class: 'px-panel px-right', id: 'px-metrics' });
  const details = el('details', { open: true }, el('summary', { text: 'Metrics' }), metricsList(data.metrics));
  right.append(details);

  root.append(left, right);

  function showLayer(k) {
    layerNo.textContent = layers.length ? `${k + 1} / ${layers.length}` : '– / 0';
    if (String(slider.value) !== String(k)) slider.value = String(k);
    layerInfo.replaceChildren();
    if (k < 0 || k >= layers.length) return;
    const l = layers[k];
    const unsupported = l.unsupportedArea > 0;
    const head = el('div', {}, el('b', { text: `layer ${l.index}` }), ` (build order ${k}) · region ${l.region ?? '–'}`);
    if (unsupported) head.append(el('span', { class: 'px-marker', text: 'UNSUPPORTED', id: 'px-unsupported-marker' }));
    layerInfo.append(head);
    layerInfo.append(kvList([
      ['normal', fmtVec(l.normal)],
      ['origin', fmtVec(l.origin, 2)],
      ['thickness', `${fmtNum(l.thickness)} mm on the axis`],
      ['thickness range', fmtRange(l.thicknessRange, ' mm')],
      ['area', `${fmtNum(l.area)} mm²`],
      ['unsupported', `${fmtNum(l.unsupportedArea)} mm²`, unsupported ? 'px-bad' : ''],
      ['max tilt', `${fmtNum(l.maxTilt)}°`],
      [`${tiltName} range`, fmtRange(l.tilt)],
      ['C range', fmtRange(l.c)],
      ['path points', `${fmtNum(l.pathCount)} (from ${fmtNum(l.pathFirst)})`],
      ...(extra && extra.tilted ? [['tilted axes', String(extra.tilted[k])]] : []),
    ]));
  }

  return { slider, checks, showLayer, playback };
}
