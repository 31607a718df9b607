// The panel's "Refine" section and window.dynpm.refine()/refinement() (docs/viewer.md "Selective
// refinement"): full resolution in a box, in the visible parts, or where the model has moved more
// than a distance at the current step (re-targeted as time moves), or where the camera would see
// an error above a number of pixels (re-targeted as the camera moves), and a coarse level
// elsewhere.
// While a refinement is on, the page draws a SelectiveNavigator (dpm/selective_navigator.js)
// instead of the level Navigator; viewer.js only calls the hooks levelChanged(), timeChanged()
// and describe().
import { DpmError } from './dpm/bytes.js';
import { Navigator } from './dpm/navigator.js';
import { elsewhereLevel, parseElsewhere, parseRequest, wantedSet } from './dpm/refine_targets.js';
import { SelectiveNavigator } from './dpm/selective_navigator.js';
import { SplitDependencies } from './dpm/split_dependencies.js';
import { fmt, int } from './fringe.js';
import { ViewSplitsFromWorker } from './moved_spheres.js';
import { besidePanel } from './orientation.js';

const $ = (id) => document.getElementById(id);

// What each request kind refines, for the status line.
const WHY = {
  box: () => 'in the box',
  sphere: () => 'in the sphere',
  part: (r) => `in part${r.parts.length === 1 ? '' : 's'} ${r.parts.join(', ')}`,
  field: (r) => `where ${r.name} ${r.above ? '>' : '<'} ${fmt(r.threshold)}`,
  moved: (r) => `where moved > ${fmt(r.distance)}`,
  view: (r) => `in view with error > ${fmt(r.pixels)} px` + (r.budget ? ` (budget ${int(r.budget)})` : ''),
};

// While the camera moves, a view is re-targeted at most this often (ms), and once it stops.
const FOLLOW_MS = 200;

export class RefineView {
  // viewer: {state, updateLevel(), partView() (a PartView or null)} of viewer.js.
  constructor(viewer) {
    this.viewer = viewer;
    this.ui = {
      mode: $('refine-mode'), box: $('refine-box'), boxRow: $('refine-box-row'), fromParts: $('refine-box-parts'),
      moved: $('refine-moved'), movedRow: $('refine-moved-row'), elsewhere: $('refine-elsewhere'), label: $('refine-label'),
      viewRow: $('refine-view-row'), pixels: $('refine-pixels'), pixelsLabel: $('refine-pixels-label'),
      budgetRow: $('refine-budget-row'), budget: $('refine-budget'),
    };
    this.dependencies = null;  // a SplitDependencies: from the decode worker, else derived here
    this.dependenciesFrom = null;  // 'worker' or 'page'
    this.selective = null;
    this.levelNav = null;  // the level Navigator, while the selective one is drawn
    this.requests = [];  // parsed
    this.texts = [];  // as given
    this.elsewhereText = '5%';
    this.elsewhere = parseElsewhere(this.elsewhereText);
    this.step = null;  // the step the targets were found at
    for (const input of [this.ui.mode, this.ui.box, this.ui.moved, this.ui.elsewhere, this.ui.budget]) input.addEventListener('change', () => this.fromPanel());
    this.ui.pixels.addEventListener('input', () => this.fromPanel());
    this.ui.fromParts.addEventListener('click', () => this.boxOfVisibleParts());
    this.followTimer = null;
    this.retargetMs = 0;  // the page's time in the last re-target (main thread)
    // A view's splits (the split spheres at the step, the screen errors for the camera) come from
    // a worker (moved_spheres.js): a re-target whose splits are not in waits for them
    // (`waiting`), the front drawn meanwhile staying as it was.
    this.viewSplits = new ViewSplitsFromWorker(() => this.viewSplitsCame());
    this.waiting = false;
    this.spheresFrom = null;  // 'worker', or 'page' when no worker could make them
    viewer.controls.addEventListener('change', () => this.cameraMoved());
  }

  // A view request with the camera's EYE, AT, UP, FOV and viewport filled in: `text` is "view"
  // or "view:PX=…[;BUDGET=…]" (or a whole view request, whose camera is replaced).
  withCamera(text) {
    if (text !== 'view' && !text.startsWith('view:')) return text;
    const keep = text.slice(5).split(';').filter((item) => /^(PX|BUDGET)=/.test(item));
    if (!keep.some((item) => item.startsWith('PX='))) keep.push('PX=1');
    const { camera, controls, canvas } = this.viewer;
    const xyz = (v) => `${v.x},${v.y},${v.z}`;
    // What shows beside the open panel: the centred window as wide as the part it leaves.
    const w = Math.max(1, Math.round(canvas.clientWidth * besidePanel(camera))), h = Math.max(1, canvas.clientHeight);
    return `view:EYE=${xyz(camera.position)};AT=${xyz(controls.target)};UP=${xyz(camera.up)};FOV=${camera.fov};W=${w};H=${h};${keep.join(';')}`;
  }

  // The camera moved: a view follows it, throttled (the last position always counts).
  cameraMoved() {
    if (!this.active || !this.requests.some((r) => r.kind === 'view') || this.followTimer) return;
    this.followTimer = setTimeout(() => {
      this.followTimer = null;
      if (this.active) this.refine(this.texts, this.elsewhereText);
    }, FOLLOW_MS);
  }

  get active() {
    return this.requests.length > 0 && this.viewer.state.nav === this.selective;
  }

  // Requests (texts in the CLI's syntax: box:…, sphere:…, part:…, field:…, moved:>D) and the
  // level elsewhere (5%, 20000 or error:0.01); no requests: the level navigator again.
  refine(texts, elsewhere = this.elsewhereText) {
    const { nav } = this.viewer.state;
    if (!(nav instanceof Navigator) && nav !== this.selective) throw new Error('the model is not loaded yet: await dynpm.ready');
    const given = (texts ?? []).map((x) => this.withCamera(String(x)));
    const requests = given.map((x) => parseRequest(x));
    const spec = parseElsewhere(String(elsewhere));
    Object.assign(this, { requests, texts: given, elsewhere: spec, elsewhereText: String(elsewhere) });
    this.showInPanel();
    if (!requests.length) return this.off();
    this.retarget();
    return this.refinement();
  }

  off() {
    const { state } = this.viewer;
    this.waiting = false;
    if (state.nav === this.selective && this.levelNav) this.swap(this.levelNav);
    this.ui.label.textContent = '';
    return this.refinement();
  }

  // The targets at the current step, the elsewhere level, the closure: the selective navigator
  // moves there (only the splits that change) and is drawn. A view whose splits for this camera
  // and step have not come from the worker yet waits for them (viewSplitsCame()).
  retarget() {
    const start = performance.now();
    const { state } = this.viewer;
    const { mesh } = state;
    this.currentDependencies();
    const views = this.viewSplitsNow();
    if (views === undefined) return;
    this.selective ??= new SelectiveNavigator(mesh, this.dependencies);
    const level = elsewhereLevel(mesh, this.elsewhere);
    const nav = this.selective;
    nav.setTarget(wantedSet(mesh, this.dependencies, this.requests, state.t, level, views), level);
    this.step = state.t;
    this.retargetMs = performance.now() - start;
    if (state.nav !== nav) {
      this.levelNav = state.nav;
      this.swap(nav);
    } else this.viewer.updateLevel();
  }

  // The view requests' splits for the camera at the current step: the worker's ({splits};
  // undefined while they are being made), or null when there is no view or no worker
  // (wantedSet() then makes the spheres and the screen errors here).
  viewSplitsNow() {
    this.waiting = false;
    const views = this.requests.filter((r) => r.kind === 'view');
    if (!views.length || this.viewSplits.failed || typeof Worker === 'undefined') {
      if (views.length) this.spheresFrom = 'page';
      return null;
    }
    const splits = this.viewSplits.get(this.viewer.state.mesh, this.dependencies.derived, this.viewer.state.t, views);
    if (!splits) return ((this.waiting = true), undefined);
    this.spheresFrom = 'worker';
    return splits;
  }

  // A view's splits came from the worker (or it failed): the view waiting for them re-targets.
  viewSplitsCame() {
    if (this.waiting && this.requests.some((r) => r.kind === 'view')) this.retarget();
  }

  // The split dependencies derived as far as the splits loaded, or as far as the decode worker
  // has sent them. Derived here, on the page's thread, only when no worker sends them (?worker=0)
  // or none has come yet.
  currentDependencies() {
    if (!this.dependencies) (this.dependencies = new SplitDependencies(this.viewer.state.mesh)), (this.dependenciesFrom = 'page');
    return this.dependencies.update();
  }

  // Hook of worker_decoder.js: dependencies the decode worker derived (moved_dependencies.js),
  // taken when they cover at least the splits of those in use; the selective navigator keeps its
  // applied splits (a prefix's dependencies do not change as more splits come).
  dependenciesReady(deps) {
    if (this.dependencies && this.dependencies.derived > deps.derived) return;
    (this.dependencies = deps), (this.dependenciesFrom = 'worker');
    if (this.selective) this.selective.dependencies = deps;
  }

  // Draws `nav` instead of the navigator drawn now: every face either drew is rewritten.
  swap(nav) {
    const { state } = this.viewer;
    const F = Math.max(state.nav.faceCount, nav.faceCount);
    for (let f = 0; f < F; f++) nav.dirty.add(f);
    state.nav = nav;
    this.viewer.updateLevel();
  }

  // Hooks of viewer.js. The resolution slider (or the arriving file) while refined: its vertex
  // count is the level elsewhere. Returns whether it handled the change.
  levelChanged(vertices, follow) {
    if (!this.active) return false;
    if (!follow) (this.elsewhere = { vertices }), (this.elsewhereText = String(vertices)), this.showInPanel();
    this.retarget();
    return true;
  }
  // Time moved: requests found at a step (all but parts) are found again. Returns whether it
  // redrew.
  timeChanged() {
    const atStep = this.requests.some((r) => r.kind !== 'part');
    if (!atStep || !(this.active || this.waiting) || (this.step === this.viewer.state.t && !this.waiting)) return false;
    this.retarget();  // a view whose spheres at this step are not in yet waits: drawn as it was
    return !this.waiting && this.active;
  }

  // "41 200 vertices: 29 200 elsewhere at 5%, 12 000 more in the box".
  describe() {
    const { mesh } = this.viewer.state;
    const nav = this.selective;
    const elsewhere = mesh.head.baseVertexCount + nav.level;
    const why = this.requests.map((r) => WHY[r.kind](r)).join(' or ');
    return `${int(nav.activeVertexCount)} vertices: ${int(elsewhere)} elsewhere at ${this.elsewhereText}, ` +
      `${int(nav.activeVertexCount - elsewhere)} more ${why}` + (this.requests.some((r) => r.kind !== 'part') ? ` at step ${this.step.toFixed(2)}` : '');
  }

  // window.dynpm.refinement(): what is refined and how many vertices and faces it took.
  refinement() {
    const nav = this.selective;
    const { dependenciesFrom, waiting, spheresFrom } = this;
    if (!this.active) return { active: false, requests: waiting ? this.texts.slice() : [], vertices: this.viewer.state.nav?.vertexCount ?? 0, dependenciesFrom, waiting, spheresFrom };
    const elsewhere = this.viewer.state.mesh.head.baseVertexCount + nav.level;
    return {
      active: true, requests: this.texts.slice(), elsewhere: this.elsewhereText, step: this.step,
      vertices: nav.activeVertexCount, elsewhereVertices: elsewhere, refinedVertices: nav.activeVertexCount - elsewhere,
      faces: nav.activeFaceCount, triangles: nav.triangleCount, quads: nav.quadCount, description: this.describe(),
      retargetMs: this.retargetMs, following: Boolean(this.followTimer), dependenciesFrom, waiting, spheresFrom,
    };
  }

  // The panel: a mode (off, box, visible parts, follow deformation), its numbers, the level
  // elsewhere. A request it cannot read is said in the label, and nothing changes.
  fromPanel() {
    const { mode, box, moved, elsewhere } = this.ui;
    const texts = { off: [], box: [`box:${box.value.replace(/\s+/g, '')}`], parts: [this.visibleParts()], picked: [this.pickedParts()], moved: [`moved:>${moved.value}`], view: [this.viewFromPanel()] }[mode.value];
    try {
      if (texts.includes(null)) throw new DpmError('pick an element first (a click on the model): its part is refined');
      this.refine(texts, elsewhere.value.trim());
    } catch (e) {
      if (!(e instanceof DpmError)) throw e;
      this.ui.label.textContent = e.message;
    }
  }

  // "view:PX=…[;BUDGET=…]" from the slider and the budget (the camera is added by refine()).
  viewFromPanel() {
    const budget = Math.max(0, Math.round(Number(this.ui.budget.value) || 0));
    return `view:PX=${this.ui.pixels.value}` + (budget ? `;BUDGET=${budget}` : '');
  }

  showInPanel() {
    const { ui } = this;
    const kinds = this.requests.map((r) => r.kind);
    const parts = ui.mode.value === 'picked' ? 'picked' : 'parts';
    const mode = !kinds.length ? 'off' : kinds.includes('view') ? 'view' : kinds.includes('moved') ? 'moved' : kinds.includes('part') ? parts : 'box';
    ui.mode.value = mode;
    ui.boxRow.hidden = mode !== 'box';
    ui.movedRow.hidden = mode !== 'moved';
    ui.viewRow.hidden = ui.budgetRow.hidden = mode !== 'view';
    const view = this.requests.find((r) => r.kind === 'view');
    if (view) {
      ui.pixels.value = String(view.pixels);
      ui.pixelsLabel.textContent = `${fmt(view.pixels)} px`;
      ui.budget.value = String(view.budget);
    }
    ui.elsewhere.value = this.elsewhereText;
    const box = this.requests.find((r) => r.kind === 'box');
    if (box) ui.box.value = [...box.min, ...box.max].map((x) => fmt(x, 6)).join(', ');
    const m = this.requests.find((r) => r.kind === 'moved');
    if (m) ui.moved.value = String(m.distance);
    if (!this.requests.length) ui.label.textContent = '';
  }

  // part:ids of the parts shown (all of them when none is hidden).
  visibleParts() {
    const parts = this.viewer.partView();
    const ids = [...new Set(this.viewer.state.mesh.partId)].filter((id) => !parts?.hidden.has(id));
    return `part:${ids.join(',')}`;
  }

  // part:ids of the picked elements' parts (inspect.js), or null when nothing is picked.
  pickedParts() {
    const ids = [...new Set((window.dynpm.picks?.() ?? []).map((p) => p.part))];
    return ids.length ? `part:${ids.join(',')}` : null;
  }

  // The box around the visible parts' vertices at the current step, into the box's numbers.
  boxOfVisibleParts() {
    const { state } = this.viewer;
    const { mesh } = state;
    const parts = this.viewer.partView();
    const n = mesh.vertexCountLoaded;
    const p = mesh.positionsAt(state.t, n, new Float32Array(3 * n));
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    const { corners } = this.currentDependencies();
    for (let f = 0; f < mesh.faceCountAt[this.dependencies.derived]; f++) {
      if (parts?.hidden.has(mesh.partId[f])) continue;
      for (let k = 0; k < 4; k++) {
        const v = corners[4 * f + k];
        if (v >= 0) for (let c = 0; c < 3; c++) (lo[c] = Math.min(lo[c], p[3 * v + c])), (hi[c] = Math.max(hi[c], p[3 * v + c]));
      }
    }
    if (!(lo[0] <= hi[0])) return;
    this.ui.mode.value = 'box';
    this.ui.box.value = [...lo, ...hi].map((x) => fmt(x, 6)).join(', ');
    this.fromPanel();
  }
}

// window.dynpm.refine(requests, elsewhere) and refinement().
export function installRefine(viewer) {
  const view = new RefineView(viewer);
  Object.assign((window.dynpm ??= {}), {
    refine: (requests, elsewhere) => view.refine(requests, elsewhere),
    refinement: () => view.refinement(),
  });
  return view;
}
