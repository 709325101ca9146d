// The page's CSS, injected from the bundle (report.html has no stylesheet of its own).
import { BACKGROUND } from './colors.js';

const CSS = `
html, body { margin: 0; height: 100%; overflow: hidden; background: ${BACKGROUND};
  font: 12px/1.35 system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif; color: #1f2933; }
.px-canvas { position: fixed; inset: 0; width: 100vw; height: 100vh; display: block; outline: none; }
.px-panel { position: fixed; top: 10px; max-height: calc(100vh - 20px); overflow: auto; box-sizing: border-box;
  background: rgba(255,255,255,0.88); border: 1px solid #d5d9e0; border-radius: 6px; padding: 8px 10px;
  box-shadow: 0 1px 4px rgba(0,0,0,0.08); }
.px-left { left: 10px; width: 300px; }
.px-right { right: 10px; width: 270px; }
.px-panel h1 { font-size: 14px; margin: 0 0 2px; word-break: break-all; }
.px-panel h2 { font-size: 12px; margin: 10px 0 4px; text-transform: uppercase; letter-spacing: 0.04em; color: #52606d; }
.px-sub { color: #52606d; }
.px-slider-row { display: flex; align-items: center; gap: 6px; }
.px-slider-row input[type=range] { flex: 1; margin: 0; }
.px-layer-no { min-width: 64px; text-align: right; font-variant-numeric: tabular-nums; }
.px-strip { display: block; width: 100%; height: 4px; margin: 2px 0 4px; }
.px-kv { display: grid; grid-template-columns: auto 1fr; gap: 1px 8px; margin: 0; }
.px-kv dt { color: #52606d; white-space: nowrap; }
.px-kv dd { margin: 0; font-variant-numeric: tabular-nums; word-break: break-word; }
.px-kv dd.px-nested { color: #3e4c59; }
.px-kv dd.px-long { grid-column: 1 / -1; padding: 0 0 4px 10px; color: #3e4c59; }
.px-kv.px-metrics { grid-template-columns: minmax(0, 1fr) minmax(0, 1fr); }
.px-kv.px-metrics dt { white-space: normal; }
.px-bad { color: #d00; font-weight: 600; }
.px-marker { display: inline-block; background: #e00; color: #fff; border-radius: 3px; padding: 0 5px; margin-left: 6px;
  font-weight: 600; }
.px-toggles { display: flex; flex-wrap: wrap; gap: 2px 10px; }
.px-toggles label { white-space: nowrap; cursor: pointer; }
.px-legend { border-collapse: collapse; width: 100%; }
.px-legend td, .px-legend th { padding: 1px 4px; text-align: left; font-variant-numeric: tabular-nums; }
.px-legend th { color: #52606d; font-weight: normal; }
.px-swatch { display: inline-block; width: 10px; height: 10px; border-radius: 2px; vertical-align: -1px;
  border: 1px solid rgba(0,0,0,0.25); }
.px-hint { color: #7b8794; margin-top: 8px; }
.px-play-row { display: flex; gap: 6px; align-items: center; margin-bottom: 4px; }
.px-play-row button, .px-play-row select { font: inherit; padding: 1px 6px; }
.px-readout { font-variant-numeric: tabular-nums; white-space: pre-wrap; }
.px-readout.px-struck { color: #d00; font-weight: 600; }
.px-right summary { font-weight: 600; cursor: pointer; }
.px-error { position: fixed; left: 50%; top: 20px; transform: translateX(-50%); max-width: 80vw; z-index: 10;
  background: #fff0f0; border: 2px solid #d00; border-radius: 6px; padding: 10px 14px; color: #900;
  white-space: pre-wrap; font: 13px/1.4 ui-monospace, monospace; }
`;

export function injectStyle() {
  const el = document.createElement('style');
  el.textContent = CSS;
  document.head.appendChild(el);
}
