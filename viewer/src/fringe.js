// Fringe colours and their legend (docs/viewer.md "Fields"): a value maps to a colour of a scheme
// (viridis, the rainbow blue → red of FE post-processors, or a diverging one for signed
// differences), either in N bands of equal width
// (each band one colour, as the legend shows it) or continuously. The legend is built from
// elements and text nodes only: names and units come from the file.

// Colour stops, evenly spaced from the low end to the high end.
export const SCHEMES = {
  viridis: [
    [0.267, 0.005, 0.329],
    [0.229, 0.322, 0.546],
    [0.128, 0.567, 0.551],
    [0.369, 0.789, 0.383],
    [0.993, 0.906, 0.144],
  ],
  rainbow: [
    [0, 0, 1],
    [0, 1, 1],
    [0, 1, 0],
    [1, 1, 0],
    [1, 0, 0],
  ],
  // Signed values about 0 (compare's field A − B): blue below, grey at 0, red above.
  diverging: [
    [0.23, 0.299, 0.754],
    [0.552, 0.69, 0.996],
    [0.866, 0.866, 0.866],
    [0.956, 0.604, 0.486],
    [0.706, 0.016, 0.15],
  ],
};

// The colour at s ∈ [0, 1] of a scheme, into out[i…i+2].
export function schemeColour(stops, s, out, i) {
  const x = Math.min(Math.max(s, 0), 1) * (stops.length - 1);
  const k = Math.min(Math.floor(x), stops.length - 2);
  const a = x - k;
  const c0 = stops[k], c1 = stops[k + 1];
  out[i] = c0[0] + (c1[0] - c0[0]) * a;
  out[i + 1] = c0[1] + (c1[1] - c0[1]) * a;
  out[i + 2] = c0[2] + (c1[2] - c0[2]) * a;
}

// How values become colours: range [lo, hi], `bands` bands (0: continuous), a scheme's stops.
export class Fringe {
  constructor({ lo, hi, bands = 10, scheme = 'viridis' }) {
    this.lo = lo;
    this.hi = Math.max(hi, lo);
    this.bands = bands;
    this.stops = SCHEMES[scheme] ?? SCHEMES.viridis;
  }
  // Which band x falls in (values outside the range take the end bands).
  band(x) {
    const { lo, hi, bands } = this;
    if (!(hi > lo)) return 0;
    return Math.min(Math.max(Math.floor(((x - lo) / (hi - lo)) * bands), 0), bands - 1);
  }
  // The colour of value x into out[i…i+2].
  colour(x, out, i) {
    const { lo, hi, bands } = this;
    if (bands > 0) return schemeColour(this.stops, (this.band(x) + 0.5) / bands, out, i);
    schemeColour(this.stops, hi > lo ? (x - lo) / (hi - lo) : 0, out, i);
  }
  // Band k's lower edge (k = bands: the upper end).
  edge(k) {
    return this.lo + ((this.hi - this.lo) * k) / this.bands;
  }
  css(s) {
    const c = [0, 0, 0];
    schemeColour(this.stops, s, c, 0);
    return `rgb(${c.map((x) => Math.round(x * 255)).join(',')})`;
  }
}

// The fringe options of the page's panel (ui: its inputs): scheme, bands (0: continuous),
// aggregate, range ('all' or 'step'), user min/max (null: automatic).
export function fringeOptions(ui) {
  const number = (input) => (input.value.trim() === '' || !Number.isFinite(Number(input.value)) ? null : Number(input.value));
  return {
    scheme: ui.scheme.value,
    bands: ui.continuous.checked ? 0 : Math.min(Math.max(Math.round(Number(ui.bands.value)) || 10, 1), 64),
    aggregate: ui.aggregate.value,
    range: ui.range.value,
    min: number(ui.rangeMin),
    max: number(ui.rangeMax),
  };
}

// An element with a class, a background colour (CSSOM, which the page's CSP allows) and
// children: strings become Text nodes (Element.append), never markup.
export function element(tag, { className, background } = {}, ...children) {
  const e = document.createElement(tag);
  if (className) e.className = className;
  if (background) e.style.background = background;
  e.append(...children);
  return e;
}

// 1,234,567; not toLocaleString, whose first call takes 0.1 s (locale data) in the first
// picture's task.
export const int = (n) => String(n).replace(/\B(?=(\d{3})+$)/g, ',');
export function bytes(n) {
  return n < 1 << 20 ? `${(n / 1024).toFixed(1)} KiB` : `${(n / (1 << 20)).toFixed(1)} MiB`;
}

export function fmt(x, digits = 4) {
  if (x === 0) return '0';
  const a = Math.abs(x);
  return a >= 1e5 || a < 1e-3 ? x.toExponential(2) : String(Number(x.toPrecision(digits)));
}

// A legend's labels in one format, as a results viewer prints them: the same decimals on every
// label, enough to tell the step between neighbours to three digits (0.2590 … 0.0259, 0.0000;
// 460.9 … 46.1, 0.0; no zeros that every label ends in: 40 … 5, 0), or all in exponent form
// (2.60e-4) when fixed decimals would be too long or too short. `values` evenly spaced, `step`
// their spacing.
export function legendLabels(values, step) {
  const largest = Math.max(...values.map(Math.abs));
  if (!(step > 0) || !Number.isFinite(largest)) return values.map((x) => fmt(x));
  const fixed = (d) => values.map((x) => x.toFixed(d).replace(/^-(0\.?0*)$/, '$1'));
  let decimals = Math.max(0, Math.ceil(-Math.log10(step)) + 2);
  if (largest < 1e5 && largest >= 1e-3 && decimals <= 6) {
    while (decimals > 0 && fixed(decimals).every((label) => label.endsWith('0'))) decimals--;  // 40, 35, …
    return fixed(decimals);
  }
  const digits = Math.min(6, Math.max(2, Math.ceil(Math.log10(largest / step)) + 2));
  return values.map((x) => x.toExponential(digits - 1).replace(/^-(0\.?0*e\+0)$/, '$1'));
}

// The legend's children: the title (name and unit), the bands top (high) to bottom with their
// edges, or a continuous bar, and the peak line. `peak`: {value, where} or null.
export function fringeLegend(fringe, { title, unit, peak }) {
  const u = unit ? ` ${unit}` : '';
  const children = [element('div', { className: 'title' }, title, unit ? ` [${unit}]` : '')];
  if (fringe.bands > 0) {
    const edges = Array.from({ length: fringe.bands + 1 }, (_, k) => fringe.edge(fringe.bands - k));
    const labels = legendLabels(edges, (fringe.hi - fringe.lo) / fringe.bands);
    const rows = [];
    for (let k = fringe.bands - 1; k >= 0; k--)
      rows.push(element('div', { className: 'band' },
        element('span', { className: 'swatch', background: fringe.css((k + 0.5) / fringe.bands) }),
        element('span', { className: 'edge' }, labels[fringe.bands - 1 - k])));
    rows.push(element('div', { className: 'band' }, element('span', { className: 'swatch blank' }),
      element('span', { className: 'edge' }, labels[fringe.bands])));
    children.push(element('div', { className: 'bands' }, ...rows));
  } else {
    const stops = Array.from({ length: 9 }, (_, k) => fringe.css(k / 8)).join(',');
    const [lo, mid, hi] = legendLabels([fringe.lo, (fringe.lo + fringe.hi) / 2, fringe.hi], (fringe.hi - fringe.lo) / 2);
    children.push(
      element('div', { className: 'bar', background: `linear-gradient(to right,${stops})` }),
      element('div', { className: 'ends' }, element('span', {}, lo), element('span', {}, mid), element('span', {}, hi)));
  }
  if (peak) children.push(element('div', { className: 'peak' }, `▲ max |value| ${fmt(peak.value)}${u} at ${peak.where}`));
  return children;
}
