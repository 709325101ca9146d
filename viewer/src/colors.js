// Colours shared by the 3-D scene and the HTML panel.
import { Color } from 'three';

export const BACKGROUND = '#f3f4f6';

// Region palette (Tableau 10, reds last so that red stays the "problem" colour).
const PALETTE = ['#4e79a7', '#59a14f', '#edc948', '#b07aa1', '#76b7b2', '#9c755f', '#ff9da7', '#f28e2b',
  '#bab0ac', '#86bcb6', '#8cd17d', '#a0cbe8', '#d4a6c8', '#e15759'];

export const COLORS = {
  contour: '#4a5568',
  currentContour: '#111111',
  travel: '#9aa3ae',
  glyph: '#5a6b7d',
  glyphTilted: '#d62fd6',
  axisLink: '#1f2933',
  axisBreak: '#ff7f00',
  axisNode: '#1f2933',
  unsupported: '#ff0000',
  collision: '#ff0000',
  grid: '#c9ced6',
  gridCenter: '#9aa3ae',
};

export function regionColor(index) {
  return PALETTE[((index % PALETTE.length) + PALETTE.length) % PALETTE.length];
}

// A prebuilt part (--substrate, --prebuilt): grey, apart from the regions' palette.
export const PREBUILT_COLOR = '#8a8f98';

// Maps region ids to palette entries by their position in the regions array.
export function regionColorMap(regions) {
  const map = new Map();
  regions.forEach((r, k) => map.set(r.id, regionColor(k)));
  return (id) => map.get(id) ?? regionColor(map.size + (id | 0));
}

// 8-bit sRGB, as the colour appears on screen (for pixel tests).
export function srgb8(css) {
  const h = new Color(css).getHex();
  return [(h >> 16) & 255, (h >> 8) & 255, h & 255];
}

// 8-bit linear (working colour space): vertex colours, which the renderer converts to sRGB on output.
export function rgb8(css) {
  const c = new Color(css);
  return [Math.round(c.r * 255), Math.round(c.g * 255), Math.round(c.b * 255)];
}
