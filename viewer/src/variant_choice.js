// A family file's variant on the page (docs/family.md): ?variant=NAME|INDEX, variant 0 without
// it. VARI comes before BASE, so from the base mesh on every callback of the decode sees the
// variant's view of the decoded mesh (dpm/variants.js): its steps, times and field values,
// sharing the arrays the decoder keeps filling. A file that is not a family passes through.
import { findVariant, variantView } from './dpm.js';

export function variantCallbacks(which, callbacks) {
  let real = null;
  let view = null;
  const shown = (mesh) => {
    if (!mesh.variants?.length) return mesh;
    if (real !== mesh) {
      real = mesh;
      view = variantView(mesh, which == null ? 0 : findVariant(mesh, which));
    }
    return view;
  };
  const wrapped = { ...callbacks };
  if (callbacks.onBase) wrapped.onBase = (mesh) => callbacks.onBase(shown(mesh));
  if (callbacks.onSplits) wrapped.onSplits = (mesh, first, n) => callbacks.onSplits(shown(mesh), first, n);
  if (callbacks.onNavigator)
    wrapped.onNavigator = (nav) => {
      if (nav.mesh === real) nav.mesh = view;
      callbacks.onNavigator(nav);
    };
  return wrapped;
}

// The page's state from a variant's view on: its steps and times (ui.time, and the tools' onHead),
// and its name beside the file's.
export function showVariant(mesh, state, ui, tools) {
  state.mesh = mesh;
  ui.time.max = String(mesh.head.stepCount - 1);
  ui.title.textContent = `${state.name} — ${mesh.variant.name} (variant ${mesh.variant.index} of ${mesh.variant.count})`;
  for (const tool of tools) tool.onHead(mesh.head);
}
