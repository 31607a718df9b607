// The page's labels of what is shown (viewer.js): the time slider's, the resolution slider's
// (the level's error in model units and as a share of the box diagonal, or a refinement's
// description) and the status line (counts, step, time, error, bytes loaded, "…" while loading).
import { bytes, fmt, int } from './fringe.js';

// state, ui: viewer.js's; refine: refine_view.js's; field: the field shown (its error is
// named), or −1.
export function drawLabels(state, ui, refine, field) {
  const { mesh, nav, t } = state;
  const h = mesh.head;
  const step = Math.round(t * 100) / 100;
  const t0 = Math.floor(t), t1 = Math.min(t0 + 1, h.stepCount - 1);
  const time = h.times[t0] + (h.times[t1] - h.times[t0]) * (t - t0);
  ui.timeLabel.textContent = `step ${step.toFixed(2)} / ${h.stepCount - 1}, time ${fmt(time)}`;
  const diag = Math.hypot(...h.bboxMax.map((x, c) => x - h.bboxMin[c]));
  const n = nav.activeVertexCount ?? nav.vertexCount;  // a selective navigator's prefix has gaps
  ui.resolutionLabel.textContent = refine.active ? refine.describe() :
    `${int(n)} of ${int(h.vertexCount)} vertices (${((100 * n) / h.vertexCount).toFixed(1)}%), ` +
    `error ${fmt(nav.error)} model units (${fmt((100 * nav.error) / diag, 3)}% of the box diagonal): ` +
    `how far this level's surface may lie from the full mesh's, at any step` +
    // A model with fields is built with them in the cost by default (docs/simplify.md): its
    // stated error is the geometric one raised by the spread of the values a vertex stands for.
    (mesh.fields.length ? ', raised where the level merges different result values' : '') +
    (field >= 0 ? `, field error ${fmt(100 * nav.fieldError(field), 3)}% of its range` : '') +
    (mesh.splitsLoaded < h.splitCount ? `, ${int(mesh.vertexCountLoaded)} loaded` : '') +
    (mesh.splitsLoaded < h.splitCount && state.budgetLimits
      ? ` (the levels whose arrays fit ${bytes(state.memoryBudget)}${state.memoryShared ? ', half the page\'s budget: B has the other' : ''}: the slider's far end loads the rest)` : '');
  const loaded = state.totalBytes
    ? `${bytes(state.bytesLoaded)} / ${bytes(state.totalBytes)}`
    : bytes(state.bytesLoaded);
  ui.stats.textContent =
    `vertices ${int(n)} · triangles ${int(nav.triangleCount)} · quads ${int(nav.quadCount)} · ` +
    (h.stepCount > 1 ? `step ${step.toFixed(2)} · time ${fmt(time)} · ` : '') +  // a mesh has no time
    `error ${fmt(nav.error)} · ` +
    `loaded ${loaded}${state.loading ? ' …' : ''}`;
  ui.stats.dataset.faces = String(nav.faceCount);
}
