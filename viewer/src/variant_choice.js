// A family file's variant on the page (docs/family.md): ?variant=NAME|INDEX, variant 0 without
// it, and the panel's variant list. VARI comes before BASE, so from the base mesh on every
// callback of the decode sees the variant's view of the decoded mesh (dpm/variants.js): its
// steps, times and field values, sharing the arrays the decoder keeps filling. A file that is not
// a family passes through.
import { findVariant, variantView } from './dpm.js';

// The decode's callbacks with the variant's view in place of the decoded mesh; `choose(which)`
// (on the returned object) turns every later callback to another variant and returns its view.
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
  wrapped.choose = (other) => ((which = findVariant(real, other)), (view = variantView(real, which)));
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

// The panel's list of a family's members (#variant, shown for a family file only). Choosing one
// shows its steps on the same vertices and faces: the camera, the level and the step (clamped to
// the member's last) stay, and the address's ?variant= follows, so a reload shows it again.
// viewer: viewer.js's {state, ui, states, deformation, setTime, setColour, redraw};
// meshChanged(mesh): the page's own holders of the mesh (the field view, picking).
export class VariantList {
  constructor(viewer, which, meshChanged) {
    this.viewer = viewer;
    this.which = which;
    this.meshChanged = meshChanged;
    this.decode = null;
    this.ui = { section: document.getElementById('variant-section'), list: document.getElementById('variant') };
    this.ui.list.addEventListener('change', () => this.choose(Number(this.ui.list.value)));
    Object.assign((window.dynpm ??= {}), {
      setVariant: (other) => this.choose(other),
      variant: () => (viewer.state.mesh?.variant ? { ...viewer.state.mesh.variant } : null),  // {index, name, count}
    });
  }

  callbacks(callbacks) {
    return (this.decode = variantCallbacks(this.which, callbacks));
  }

  // At BASE (a variant's view when the file is a family): the list, with this variant chosen.
  onBase(mesh) {
    if (!mesh.variant) return;
    const { state, ui, states, deformation } = this.viewer;
    showVariant(mesh, state, ui, [states, deformation]);
    // Option(text, value): the names from VARI are text.
    this.ui.list.replaceChildren(...mesh.variants.map((v, k) => new Option(`${k}: ${v.name} (${v.steps.length} steps)`, String(k))));
    this.ui.list.value = String(mesh.variant.index);
    this.ui.section.hidden = false;
  }

  // Shows variant `which` (a name or an index); returns its name. Before the base mesh or on a
  // file that is not a family, an error.
  choose(which) {
    const { state, ui, deformation } = this.viewer;
    if (!state.mesh?.variant || !state.nav) throw new Error('the model is not a family file (or its base mesh is not in yet)');
    const mesh = this.decode.choose(which);
    state.nav.mesh = mesh;
    this.onBase(mesh);
    Object.assign(state, { base0Count: 0, ranges: new Map() });  // step 0 and ranges are the variant's
    deformation.ghostVertices = 0;
    this.meshChanged(mesh);
    const params = new URLSearchParams(location.search);
    params.set('variant', mesh.variant.name);
    history.replaceState(null, '', `${location.pathname}?${params}`);
    this.viewer.setTime(Math.min(state.t, mesh.head.stepCount - 1));
    this.viewer.redraw();  // every visible vertex's positions, whatever the step
    if (state.colour !== 'part') this.viewer.setColour(state.colour);
    return mesh.variant.name;
  }
}
