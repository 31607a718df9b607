// The resolution by error (docs/viewer.md "The view's controls", Resolution): the panel's
// "max error" box takes E (model units) or E% (of the box diagonal), as `dynpm extract
// --max-error` does, and shows the coarsest level whose error is at most E — the level an
// engineer asks for in millimetres rather than in vertices. Beyond what has arrived, the rest
// of the file is asked for and the finest level follows it. The slider clears the box: it no
// longer says the level. Under selective refinement it sets the level elsewhere, as the slider
// does.

// "0.5" or "0.1%" → {value, percent}, or null.
export function parseMaxError(text) {
  const m = /^\s*([0-9]*\.?[0-9]+(?:e[+-]?[0-9]+)?)\s*(%?)\s*$/i.exec(text);
  if (!m) return null;
  const value = Number(m[1]);
  if (!Number.isFinite(value) || (m[2] && value > 100)) return null;
  return { value, percent: m[2] === '%' };
}

// The vertex count of the coarsest loaded level with error ≤ e (model units), or null when no
// loaded level reaches it and the file holds more.
export function vertexCountForError(mesh, e) {
  const n = mesh.vertexCountForError(e);
  if (mesh.levelError(n - mesh.head.baseVertexCount) > e && mesh.splitsLoaded < mesh.head.splitCount) return null;
  return n;
}

// viewer: {state, ui, setVertexCount} (viewer.js).
export function installErrorLevel(viewer) {
  const box = document.getElementById('resolution-error');
  const { state, ui } = viewer;
  box.addEventListener('change', () => {
    const text = box.value.trim();
    if (text === '') return box.setCustomValidity('');
    const given = parseMaxError(text);
    box.setCustomValidity(given ? '' : `"${text}": a number ≥ 0 in model units, or a percentage of the box diagonal (0.1%)`);
    box.reportValidity();
    if (!given || !state.nav) return;  // (as the slider: nothing before the base mesh)
    const h = state.mesh.head;
    const diagonal = Math.hypot(...h.bboxMax.map((x, c) => x - h.bboxMin[c]));
    const e = given.percent ? (given.value / 100) * diagonal : given.value;
    // Not reached yet: read on and follow the finest level (setVertexCount asks for the rest).
    viewer.setVertexCount(vertexCountForError(state.mesh, e) ?? h.vertexCount, true);
  });
  ui.resolution.addEventListener('input', () => ((box.value = ''), box.setCustomValidity('')));
}
