// Number and value formatting for the panel.

export function fmtNum(v, digits = 4) {
  if (typeof v !== 'number') return String(v);
  if (!Number.isFinite(v)) return Number.isNaN(v) ? '–' : v > 0 ? '∞' : '−∞';
  if (Number.isInteger(v)) return Math.abs(v) >= 1e5 ? v.toLocaleString('en-US') : String(v);
  const a = Math.abs(v);
  if (a >= 1e5) return Math.round(v).toLocaleString('en-US');
  if (a !== 0 && a < 1e-3) return v.toExponential(2);
  // significant digits, but never more than 4 decimals and no trailing zeros
  const d = Math.min(4, Math.max(0, digits - 1 - Math.floor(Math.log10(a || 1))));
  return String(Number(v.toFixed(d)));
}

export function fmtValue(v) {
  if (v === null || v === undefined) return '–';
  if (typeof v === 'number') return fmtNum(v);
  if (typeof v === 'boolean') return v ? 'yes' : 'no';
  if (Array.isArray(v)) {
    const inner = v.slice(0, 12).map(fmtValue).join(', ');
    return `[${inner}${v.length > 12 ? `, … (${v.length})` : ''}]`;
  }
  if (typeof v === 'object') return Object.entries(v).map(([k, x]) => `${k}: ${fmtValue(x)}`).join(', ');
  return String(v);
}

export function fmtVec(v, digits = 3) {
  return `(${v.map((x) => String(Number(x.toFixed(digits)))).join(', ')})`;
}

export function fmtRange(r, unit = '°') {
  if (!r || Number.isNaN(r[0]) || Number.isNaN(r[1])) return '–';
  return `${fmtNum(r[0])} … ${fmtNum(r[1])}${unit}`;
}
