// The time-history plot (docs/viewer.md "Picking, history, section, measure"): one polyline per
// series over every step, the current step as a vertical line, value and time ends as text. Built
// with DOM calls only (createElementNS, attributes, text nodes): labels come from the file and the
// page runs under a CSP without inline styles.
import { download as saveAs } from './images.js';

const SVG = 'http://www.w3.org/2000/svg';
const W = 280, H = 150;
const PAD = { left: 46, right: 8, top: 8, bottom: 22 };
// Distinct on white, and apart from the section's magenta.
export const SERIES_COLOURS = ['#1f6fd1', '#e8710a', '#188038', '#9334e6', '#b31412', '#12848f', '#7a5c00', '#5f6368'];

function svg(tag, attributes = {}, ...children) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, String(v));
  e.append(...children);
  return e;
}

// x in few digits, but enough that the two ends of a range `span` wide differ.
function short(x, span) {
  const digits = Math.min(10, Math.max(4, Math.ceil(Math.log10(Math.abs(x) / span)) + 2));
  if (x === 0) return '0';
  return Math.abs(x) >= 1e4 || Math.abs(x) < 1e-3 ? x.toExponential(digits - 2) : String(Number(x.toPrecision(digits)));
}

export class HistoryPlot {
  // parent: the element the <svg> goes in.
  constructor(parent) {
    this.root = svg('svg', { viewBox: `0 0 ${W} ${H}`, class: 'history-plot', role: 'img' });
    parent.append(this.root);
    this.series = [];
    this.times = [];
    this.cursor = null;
    this.x = () => 0;
  }

  // series: [{label, values}], times: each step's time, quantity: what the y axis shows.
  draw(series, times, quantity) {
    this.series = series;
    this.times = times;
    this.quantity = quantity;
    const values = series.flatMap((s) => Array.from(s.values));
    // The values' own range (an intrusion of 1 mm on a distance of 150 mm must show), a little
    // wider so that a line at an end stays clear of the frame.
    let lo = Math.min(...values), hi = Math.max(...values);
    if (!(hi > lo)) (lo -= 0.5 * Math.abs(lo) || 1), (hi += 0.5 * Math.abs(hi) || 1);
    else (lo -= 0.04 * (hi - lo)), (hi += 0.04 * (hi - lo));
    const m = times.length;
    const t0 = times[0] ?? 0, t1 = times[m - 1] ?? 1;
    const span = t1 > t0 ? t1 - t0 : 1;
    const x = (t) => PAD.left + ((t - t0) / span) * (W - PAD.left - PAD.right);
    const y = (v) => H - PAD.bottom - ((v - lo) / (hi - lo)) * (H - PAD.top - PAD.bottom);
    this.x = (step) => {
      const s0 = Math.min(Math.max(Math.floor(step), 0), m - 1), s1 = Math.min(s0 + 1, m - 1);
      return x(times[s0] + (times[s1] - times[s0]) * (step - s0));
    };
    const axes = svg('path', { d: `M${PAD.left},${PAD.top}V${H - PAD.bottom}H${W - PAD.right}`, class: 'axes' });
    const text = (tx, ty, anchor, s) => svg('text', { x: tx, y: ty, 'text-anchor': anchor, class: 'tick' }, s);
    const labels = [
      text(PAD.left - 4, PAD.top + 8, 'end', short(hi, hi - lo)),
      text(PAD.left - 4, H - PAD.bottom, 'end', short(lo, hi - lo)),
      text(PAD.left, H - 6, 'start', short(t0, span)),
      text(W - PAD.right, H - 6, 'end', short(t1, span)),
      text((PAD.left + W) / 2, H - 6, 'middle', `time · ${quantity}`),
    ];
    const lines = series.map((s, i) => {
      const points = Array.from(s.values, (v, t) => `${x(times[t]).toFixed(2)},${y(v).toFixed(2)}`).join(' ');
      return svg('polyline', { points, fill: 'none', stroke: SERIES_COLOURS[i % SERIES_COLOURS.length], 'stroke-width': 1.5 }, svg('title', {}, s.label));
    });
    // The series' names, each in its colour, along the top.
    const names = series.slice(0, 4).map((s, i) => svg('text', { x: W - PAD.right, y: PAD.top + 9 + 10 * i, 'text-anchor': 'end', fill: SERIES_COLOURS[i % SERIES_COLOURS.length] }, s.label));
    if (series.length > 4) names.push(text(W - PAD.right, PAD.top + 49, 'end', `+${series.length - 4} more`));
    this.cursor = svg('line', { y1: PAD.top, y2: H - PAD.bottom, class: 'cursor' });
    this.root.replaceChildren(axes, ...labels, ...lines, ...names, this.cursor);
  }

  // The current step (fractional while playing) as the vertical line.
  mark(step) {
    if (!this.cursor) return;
    const at = this.x(step).toFixed(2);
    this.cursor.setAttribute('x1', at);
    this.cursor.setAttribute('x2', at);
    this.cursor.dataset.step = String(step);
  }
}

// The series as CSV: a column of steps, one of times, one per series (its label quoted).
export function historyCsv(series, times) {
  const quote = (s) => `"${String(s).replace(/"/g, '""')}"`;
  const rows = [['step', 'time', ...series.map((s) => quote(s.label))].join(',')];
  for (let t = 0; t < times.length; t++) rows.push([t, times[t], ...series.map((s) => s.values[t])].join(','));
  return `${rows.join('\n')}\n`;
}

// Saves text as a file through a temporary link (a blob: URL; no navigation, nothing inline).
export function download(text, name, type = 'text/csv') {
  const url = URL.createObjectURL(new Blob([text], { type }));
  saveAs(url, name);
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}
