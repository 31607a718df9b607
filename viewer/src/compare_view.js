// The second model of a comparison (docs/viewer.md "Compare"): `?compare=PATH` (a file of the
// page's own origin) or `dynpm view A.dpm B.dpm` shows B on a canvas of its own right of the
// first model's, with its own decode worker and range fetches, and everything else linked to
// the first: one camera (both canvases orbit it), the same time step (clamped to B's last), the
// same fraction of the vertices (the same count when both hold one hierarchy), the colour mode
// with the first's legend range. When both files hold one hierarchy (compare_math.js) the
// colour list offers |p_A(t) − p_B(t)|, drawn on both with a marker at its largest. B may be a
// family file's member (`&compareVariant=NAME|INDEX`, as `?variant=` for the first; the same
// file as the first's for two members of one family, which always hold one hierarchy: then B is
// the member's view of the mesh the first's decode fills, fetched and decoded once). B may also
// be drawn over A on A's canvas (`&compareLayout=edges|surface`, compare_overlay.js), and two
// hierarchies may be linked by error instead of the share of vertices (the panel's "Link by").
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

import { hierarchyDifference, linkedVertexCount, positionDifference } from './compare_math.js';
import { Navigator, ProgressiveMesh, updateIndices } from './dpm.js';
import { BaseLevel } from './base_level.js';
import { CompareOverlay } from './compare_overlay.js';
import { growDrawBuffers, uploadIndices } from './draw_buffers.js';
import { edgeMaterial, fieldColoursAtVertices } from './edge_lines.js';
import { commonFields, FIELD_DIFFERENCE, FieldDifference } from './field_difference.js';
import { FieldView } from './field_view.js';
import { element, fmt, int } from './fringe.js';
import { verticesBeforePause } from './model_file.js';
import { panelChoice } from './panel.js';
import { PartView } from './part_view.js';
import { greySnapshot } from './snapshot.js';
import { variantCallbacks } from './variant_choice.js';
import { decodeInWorker, decodeOnPage } from './worker_decoder.js';

export const DIFFERENCE = 'difference';
const HEADLIGHT = new THREE.Vector3(0.3, 0.5, 1);  // in camera space, as the first model's

// The second model's path from ?compare= (only of this origin, as ?file=) or dpm.json's
// `compare` (dynpm view A B), with its name, the family member ?compareVariant= names (null:
// variant 0 of a family file) and the layout ?compareLayout= or dpm.json's `compareLayout`
// (`dynpm view A B --layout L`) names (null: side by side); null when there is none.
export function compareFile(params, config) {
  const query = params.get('compare');
  if (query && new URL(query, location.href).origin !== location.origin)
    throw new Error(`?compare=${query}: not on this server (${location.origin})`);
  const variant = params.get('compareVariant'), layout = params.get('compareLayout') ?? config?.compareLayout ?? null;
  // Named by its file name, as ?model= names the first (model_file.js).
  if (query) return { file: query, name: decodeURIComponent(new URL(query, location.href).pathname.split('/').pop()), variant, layout };
  return config?.compare ? { file: config.compare, name: config.compareName ?? config.compare, variant, layout } : null;
}

// A model's name in its label, with the family member shown (variant_choice.js's view).
const shownName = (name, mesh) => (mesh?.variant ? `${name} [${mesh.variant.name}]` : name);

// The level's line under a model's name: vertices, share, error, step and time.
function levelText(mesh, nav, t) {
  const h = mesh.head;
  const n = nav.vertexCount;
  const t0 = Math.floor(t), t1 = Math.min(t0 + 1, h.stepCount - 1);
  const time = h.times[t0] + (h.times[t1] - h.times[t0]) * (t - t0);
  return `${int(n)} of ${int(h.vertexCount)} vertices (${((100 * n) / h.vertexCount).toFixed(1)}%), error ${fmt(nav.error)}` +
    (h.stepCount > 1 ? `, step ${(Math.round(t * 100) / 100).toFixed(2)} of ${h.stepCount - 1}, time ${fmt(time)}` : '') +
    (mesh.splitsLoaded < h.splitCount ? `, ${int(mesh.vertexCountLoaded)} loaded` : '');
}

export class CompareView {
  // viewer: {state, scene, camera, controls, deformation, ui, requestRender, resize} (viewer.js).
  constructor(viewer, { file, name, variant, layout }, { antialias }) {
    this.viewer = viewer;
    this.url = new URL(file, location.href).href;
    this.name = name;
    this.variant = variant;  // a family file's member (null: variant 0)
    document.body.classList.add('compare');
    this.canvas = element('canvas', { className: 'compare-view' });
    this.labels = [element('div', { className: 'compare-label left' }), element('div', { className: 'compare-label right' })];
    document.body.append(this.canvas, ...this.labels);
    this.renderer = new THREE.WebGLRenderer({ canvas: this.canvas, antialias });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.setClearColor(0xeef0f3);
    this.scene = new THREE.Scene();
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8890a0, 1.6));
    this.light = new THREE.DirectionalLight(0xffffff, 1.6);
    this.scene.add(this.light);
    // The first model's camera: orbiting here moves both, as orbiting there does.
    this.controls = new OrbitControls(viewer.camera, this.canvas);
    this.controls.target = viewer.controls.target;
    this.controls.zoomToCursor = true;
    this.controls.addEventListener('change', () => viewer.requestRender());
    this.surface = new THREE.Mesh(new THREE.BufferGeometry(), new THREE.MeshLambertMaterial({
      vertexColors: true, flatShading: true, side: THREE.DoubleSide,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    }));
    this.edgeLines = new THREE.LineSegments(new THREE.BufferGeometry(), edgeMaterial());
    this.markers = [viewer.scene, this.scene].map((scene) => {
      const m = new THREE.Mesh(new THREE.SphereGeometry(1, 16, 12),
        new THREE.MeshBasicMaterial({ color: 0xd0103a, depthTest: false, transparent: true, opacity: 0.9 }));
      m.renderOrder = 10;  // over the model: the largest difference may be behind it
      m.visible = false;
      scene.add(m);
      return m;
    });
    this.overlay = new CompareOverlay(viewer);
    // Overlaid, B's marker is on A's canvas, where B is drawn.
    this.overlay.onChange = () => {
      (this.overlay.overlaid ? viewer.scene : this.scene).add(this.markers[1]);
      this.label();
    };
    // Levels linked by the share of vertices (default) or, for two hierarchies, by error.
    this.link = panelChoice('compare-link', 'Link by', { vertices: 'share of vertices', error: 'error' },
      'B\'s level: the same share of its vertices, or (two hierarchies) its coarsest level within A\'s error', () => this.sync({ level: true }));
    Object.assign((window.dynpm ??= {}), {
      setCompareLayout: (l) => (this.overlay.set(l), this.overlay.layout),
      setCompareLink: (l) => (this.link.set(l), this.sync({ level: true }), this.link.value),
    });
    this.buffers = {};  // positions, colours, triIndex, edgeIndex, scratch (draw_buffers.js)
    this.room = { vertices: 0, faces: 0 };
    this.mesh = this.nav = this.parts = this.fieldView = null;
    this.base0 = null;  // B's step-0 positions (deformation scale, displacement)
    this.shownKey = '';  // t and n of the unscaled positions in buffers.positions
    this.why = 'waiting for both files';  // why no difference is offered (null: it is)
    this.largest = null;  // {value, vertex, node}
    this.option = new Option('difference |p_A(t) − p_B(t)|', DIFFERENCE);
    this.option.disabled = true;
    viewer.ui.colour.add(this.option);
    if (layout !== null && layout !== undefined) {
      try {
        this.overlay.set(layout);
      } catch (e) {
        throw new Error(`?compareLayout=${layout}: ${e.message}`);
      }
    }
    this.fieldPairs = new Map();  // A's field k → B's field of the same name (field_difference.js)
    this.fieldDifferences = new Map();  // 'k aggregate' → the FieldDifference both canvases show
  }

  // For a field difference mode ('fielddiff:k'), FieldView's options to show it: the values (one
  // object for both canvases) and the diverging scheme; else nothing.
  fieldDifference(mode, aggregate) {
    const k = mode.startsWith(FIELD_DIFFERENCE) ? Number(mode.slice(FIELD_DIFFERENCE.length)) : -1;
    // (A refined selectively: its items are not B's level; A shows its own field k meanwhile.)
    if (!this.fieldPairs.has(k) || this.viewer.state.nav?.selective) return undefined;
    const key = `${k} ${aggregate}`, a = this.viewer.state.mesh;
    if (this.fieldDifferences.get(key)?.a.mesh !== a)  // (another member of A's family chosen)
      this.fieldDifferences.set(key, new FieldDifference(a, k, this.mesh, this.fieldPairs.get(k), aggregate));
    return { shown: this.fieldDifferences.get(key), scheme: 'diverging' };
  }

  // Starts B's decode (in a worker of its own unless ?worker=0); resolves when B is loaded.
  // From the base mesh on, this.mesh is the chosen variant's view of a family file. `memory`:
  // B's share of the page's budget (model_file.js): its worker stops at the levels whose values
  // fit it, and sync() asks for more when A's level links to a level of B not loaded yet.
  async load(worker, memory = Infinity) {
    const onNavigator = (nav) => ((this.nav = nav), this.onSplits());
    this.decoder = {};  // want(n): fetch B up to n vertices (worker_decoder.js)
    this.asked = 0;  // the most vertices asked of B's worker
    this.paused = false;  // B's worker stopped at its budget (until askFor())
    this.expected = Infinity;  // what B's worker loads before it pauses (the draw buffers' room)
    const decode = variantCallbacks(this.variant, {
      url: this.url, name: this.name,
      onHead: (mesh) => {
        this.mesh = mesh;
        if (worker) this.expected = verticesBeforePause(mesh.head, Infinity, memory);
      },
      onBase: (mesh) => this.onBase(mesh),
      onSplits: () => this.onSplits(),
      onNavigator,
      memory, control: this.decoder, onPaused: () => ((this.paused = true), this.label()),
    });
    await (worker ? decodeInWorker(decode) : decodeOnPage(decode));
    this.loaded();
  }

  // B in the first's own file (two members of one family, or a model beside itself): no fetch
  // and no decode of its own. The first's decode callbacks (after its variant's wrapping) are
  // returned wrapped, so that B's variant view follows the same decoded mesh; B's Navigator is
  // made on the page after the first's has come.
  alongside(callbacks) {
    const mine = variantCallbacks(this.variant, { onBase: (mesh) => this.onBase(mesh), onSplits: () => this.onSplits() });
    return {
      ...callbacks,
      onHead: (mesh) => (callbacks.onHead(mesh), (this.mesh = mesh)),
      onBase: (mesh) => (callbacks.onBase(mesh), mine.onBase(mesh)),
      onSplits: (mesh, first, n) => (callbacks.onSplits(mesh, first, n), mine.onSplits(mesh, first, n)),
      onNavigator: (nav) => {
        callbacks.onNavigator(nav);
        requestAnimationFrame(() => setTimeout(() => this.nav instanceof Navigator || ((this.nav = new Navigator(this.mesh)), this.onSplits())));
      },
    };
  }

  // B alongside the first (alongside()): loaded once the first's decode is; an error is the
  // first's, which the page shows.
  follow(decoding) {
    this.loading = decoding.then(() => this.loaded()).catch(() => {});
  }

  // B's mesh is whole: its Navigator (if not made yet) at B's linked level.
  loaded() {
    if (!this.mesh?.hasBase) throw new Error(`${this.name}: ends before the base mesh`);
    if (!(this.nav instanceof Navigator)) this.nav = new Navigator(this.mesh);
    this.onSplits();
  }

  onBase(mesh) {
    this.mesh = mesh;
    const { head: h } = mesh;
    const geometry = (this.geometry = new THREE.BufferGeometry());
    const edges = (this.edgeGeometry = new THREE.BufferGeometry());
    const box = new THREE.Box3(new THREE.Vector3(...h.bboxMin), new THREE.Vector3(...h.bboxMax));
    geometry.boundingSphere = edges.boundingSphere = box.getBoundingSphere(new THREE.Sphere());
    this.setMarkerRadius(geometry.boundingSphere.radius / 60);  // as the field marker's
    this.surface.geometry = geometry;
    this.edgeLines.geometry = edges;
    this.scene.add(this.surface, this.edgeLines);
    this.overlay.draw(geometry, edges);
    this.parts = new PartView(this.scene, mesh, this.surface.material, geometry.boundingSphere);
    this.nav = new BaseLevel(mesh);
    this.sync({ level: true });
  }

  onSplits() {
    if (this.nav) this.sync({ level: true });
  }

  // Whether |p_A − p_B| is offered: both files whole and one hierarchy (compare_math.js),
  // checked once both are in. Returns whether that changed.
  checkHierarchy() {
    const a = this.viewer.state.mesh, b = this.mesh;
    if (this.checked || !a?.complete || !b?.complete) return false;
    this.checked = true;
    this.why = hierarchyDifference(a, b, a.head.splitCount);
    this.option.disabled = this.why !== null;
    this.option.title = this.why ? `no difference fringe: ${this.why}` : '';
    // Option(text, value): the field's name from FDEF is text.
    if (this.why === null)
      for (const [k, j] of commonFields(a, b))
        this.fieldPairs.set(k, j), this.viewer.ui.colour.add(new Option(`${a.fields[k].name} A − B`, `${FIELD_DIFFERENCE}${k}`));
    return true;
  }

  // B's level, positions and colours after the first's changed: the linked level (the same
  // fraction), the same step clamped to B's, the first's colour mode and legend range.
  sync({ level = false } = {}) {
    const { state, deformation } = this.viewer;
    if (!this.nav || !state.nav) return;
    const nav = this.nav, mesh = this.mesh;
    const A = state.mesh.head;
    const n = !(nav instanceof Navigator) ? nav.vertexCount
      : this.linkedByError && Number.isFinite(state.nav.error) ? mesh.vertexCountForError(state.nav.error)
      : linkedVertexCount(state.nav.vertexCount, A.vertexCount, mesh.head, mesh.vertexCountLoaded);
    // B's level for the one asked of A (viewer.js's targetVertices: the slider, the API), fetched
    // if B's worker stopped before it; a level A reached by following its own file asks nothing,
    // so that B keeps to its share of the budget.
    if (state.targetVertices !== undefined)
      this.askFor(this.linkedByError ? (mesh.levelError(mesh.splitsLoaded) > state.nav.error ? Infinity : n)
        : linkedVertexCount(state.targetVertices, A.vertexCount, mesh.head, Infinity));
    if (nav.vertexCount !== n) (nav.setVertexCount(n), (level = true));
    if (level || !this.buffers.positions) this.drawLevel();  // (B's base may come before A's)
    const t = this.step();
    const p = this.positionsAt(t, n);
    const unscaled = deformation.scale === 1 ? p : Float32Array.from(p.subarray(0, 3 * n));
    if (deformation.scale !== 1) this.scale(p, n, deformation.scale);
    this.colour(unscaled, n);
    this.upload('position', n);
    const offered = this.checkHierarchy();
    this.label();
    if (offered && state.colour !== 'part') this.viewer.setColour(state.colour);
    this.viewer.requestRender();
  }

  // B's level linked to A's needs n vertices (Infinity: B's finest loaded is coarser than A's
  // error): a worker paused at B's budget fetches them.
  askFor(n) {
    const h = this.mesh.head, want = Math.min(n, h.vertexCount);
    if (this.mesh.splitsLoaded >= h.splitCount || want <= this.mesh.vertexCountLoaded || want <= this.asked || !this.decoder?.want) return;
    this.asked = want;
    this.paused = false;
    this.expected = Infinity;
    this.decoder.want(want);
  }

  // B at its coarsest level within A's error: asked for, and only between two hierarchies (one
  // hierarchy is compared vertex for vertex).
  get linkedByError() {
    return this.link.value === 'error' && this.why !== null;
  }

  step() {
    return Math.min(this.viewer.state.t, this.mesh.head.stepCount - 1);
  }

  // B's unscaled positions of vertices [0, n) at step t (kept while t and n stay).
  positionsAt(t, n) {
    const key = `${t} ${n}`;
    if (this.shownKey !== key) this.mesh.positionsAt(t, n, this.buffers.positions);
    this.shownKey = key;
    return this.buffers.positions;
  }

  scale(p, n, s) {
    this.extendBase0(n);
    const b = this.base0;
    for (let i = 0; i < 3 * n; i++) p[i] = b[i] + s * (p[i] - b[i]);
    this.shownKey = '';
  }

  extendBase0(n) {
    this.base0 ??= new Float32Array(3 * this.mesh.head.vertexCount);
    this.mesh.positionsAt(0, n, this.base0);
  }

  drawLevel() {
    const nav = this.nav;
    const grown = growDrawBuffers(this.buffers, this.room, nav.vertexCount, nav.faceCount, this.mesh.head, this.geometry, this.edgeGeometry, this.expected);
    if (grown) (this.buffers = grown), (this.shownKey = '');
    const { triIndex, edgeIndex } = this.buffers;
    uploadIndices(this.geometry, this.edgeGeometry, nav.faceCount, updateIndices(nav, triIndex, edgeIndex));
  }

  // The colours of the first's mode: parts; displacement, a field (B's of the same name) or
  // the difference in the first's legend range.
  colour(unscaled, n) {
    const { state, ui } = this.viewer;
    const { colours, scratch, positions } = this.buffers;
    const mode = state.colour;
    const difference = this.fieldDifference(mode, ui.aggregate.value);
    const fieldName = mode.startsWith('field:') ? state.mesh.fields[Number(mode.slice(6))].name : null;
    const k = difference ? this.fieldPairs.get(Number(mode.slice(FIELD_DIFFERENCE.length))) : fieldName === null ? -1 : this.mesh.fields.findIndex((f) => f.name === fieldName);
    this.note = fieldName !== null && k < 0 ? `has no field ${fieldName}` : '';
    if (k < 0) this.fieldView?.hide();
    if (mode === 'part' || !state.fringe || (fieldName !== null && k < 0)) {
      this.surface.visible = false;
      this.parts.drawLevel(this.nav);
      this.parts.vertexColours(this.nav, colours);
      this.parts.drawPositions(this.nav, positions);
    } else if (k >= 0) {
      this.parts.hide();
      this.fieldView ??= new FieldView(this.scene, this.mesh, this.surface, this.markers[0].scale.x);
      const options = { aggregate: ui.aggregate.value, range: 'all', min: state.fringe.lo, max: state.fringe.hi, bands: state.fringe.bands, scheme: ui.scheme.value, parts: this.parts, ...difference };
      // A difference is at A's step (its B side clamped inside): the same object on both canvases.
      this.surface.visible = this.fieldView.update(k, this.nav, difference ? state.t : this.step(), positions, options);
      fieldColoursAtVertices(this.fieldView, this.nav, colours);
    } else {
      this.parts.hide();
      this.fieldView?.hide();
      this.surface.visible = true;
      if (mode !== DIFFERENCE) {
        this.extendBase0(n);
        ProgressiveMesh.displacement(unscaled, this.base0, n, scratch);
      }
      for (let v = 0; v < n; v++) state.fringe.colour(scratch[v], colours, 3 * v);
    }
    for (const m of this.markers) m.visible = mode === DIFFERENCE && this.largest !== null;
    if (this.markers[1].visible) this.markers[1].position.fromArray(positions, 3 * this.largest.vertex);
    this.upload('color', n);
  }

  // |p_A − p_B| at the first's level and step into out, the markers at its largest; the first
  // passes its true positions (unscaled) and the drawn ones. Null when it is not offered.
  difference(unscaledA, drawnA, n, out) {
    if (this.why !== null || this.nav.vertexCount !== n) return (out.fill(0, 0, n), (this.largest = null));
    const largest = positionDifference(unscaledA, this.positionsAt(this.step(), n), n, this.buffers.scratch);
    out.set(this.buffers.scratch.subarray(0, n));
    this.largest = { ...largest, node: this.mesh.nodeId[largest.vertex] };
    this.markers[0].position.fromArray(drawnA, 3 * largest.vertex);
    this.markers[0].visible = largest.vertex >= 0;
    return this.largest;
  }

  // The markers' size with the model's (viewer.js's field marker radius).
  setMarkerRadius(r) {
    for (const m of this.markers) m.scale.setScalar(r);
  }

  // The legend's peak line in the difference mode (fringe.js's fringeLegend).
  peak() {
    const l = this.viewer.state.colour === DIFFERENCE ? this.largest : null;
    return l && { value: l.value, where: `node ${l.node} (vertex ${l.vertex})` };
  }

  label() {
    const { state } = this.viewer;
    // Until both are shown: B's worker may pause at its budget before A's first level is in.
    if (!this.nav || !state.nav) return;
    this.labels[0].textContent = `A: ${shownName(state.name, state.mesh)} — ${levelText(state.mesh, state.nav, state.t)}`;
    const why = this.why && this.viewer.state.mesh?.complete && this.mesh.complete ? `; no difference fringe: ${this.why}` : '';
    const clamped = state.t > this.mesh.head.stepCount - 1 ? ' (its last step)' : '';
    const where = (this.overlay.overlaid ? ', in magenta over A' : '') +
      (this.linkedByError ? ', linked by error' : '');
    this.labels[1].textContent = `B${where}: ${shownName(this.name, this.mesh)} — ${levelText(this.mesh, this.nav, this.step())}${clamped}${this.note ? `; ${this.note}` : ''}${why}`;
  }

  upload(name, n) {
    const a = this.geometry.attributes[name];
    if (n <= 0) return;
    a.addUpdateRange(0, 3 * n);
    a.needsUpdate = true;
  }

  // The left edge of the two canvases (CSS pixels): right of the panel when it is open, so that
  // it covers neither model, else the window's edge (style.css: --compare-left; A's label stays
  // right of the panel's box either way, --panel-right).
  left(panel) {
    const right = Math.ceil(panel.ui.panel.getBoundingClientRect().right);
    const left = panel.collapsed ? 0 : right + 10;
    document.body.style.setProperty('--compare-left', `${left}px`);
    document.body.style.setProperty('--panel-right', `${right}px`);
    return left;
  }

  // The height the status line's strip takes below the canvases (CSS pixels; style.css:
  // --compare-bottom): the line, one line high in compare, and its margins.
  bottom(stats) {
    const strip = stats.offsetHeight + 16;
    document.body.style.setProperty('--compare-bottom', `${strip}px`);
    return strip;
  }

  // The canvases that share the width: two side by side, one when B is drawn over A.
  columns() {
    return this.overlay.overlaid ? 1 : 2;
  }

  resize(w, h) {
    this.renderer.setSize(w, h, false);
  }

  render() {
    if (this.overlay.overlaid) return;  // B's canvas is hidden; A's draws B
    const camera = this.viewer.camera;
    this.light.position.copy(HEADLIGHT).applyMatrix4(camera.matrixWorld);
    this.edgeLines.visible = this.viewer.ui.edges.checked;  // the panel's check box
    this.renderer.render(this.scene, camera);
  }

  // For scripts and the browser test.
  describe() {
    const nav = this.nav;
    return {
      name: this.name,
      layout: this.overlay.layout,
      link: this.link.value,
      variant: this.mesh?.variant?.name ?? null,
      complete: Boolean(this.mesh?.complete),
      paused: Boolean(this.paused && !this.mesh?.complete),  // at B's share of the memory budget
      vertices: nav?.vertexCount ?? 0,
      loadedVertices: this.mesh?.vertexCountLoaded ?? 0,
      faces: nav?.faceCount ?? 0,
      navigator: nav instanceof Navigator,
      step: this.mesh ? this.step() : 0,
      stepCount: this.mesh?.head.stepCount ?? 0,
      sameHierarchy: this.why === null,
      why: this.why,
      largest: this.peak() && { ...this.largest, positionA: this.markers[0].position.toArray(), positionB: this.markers[1].position.toArray() },
      fieldDifferences: [...this.fieldPairs.keys()].map((k) => `${FIELD_DIFFERENCE}${k}`),
      fieldPeak: this.fieldView?.shown instanceof FieldDifference ? { ...this.fieldView.peak, position: this.fieldView.marker.position.toArray() } : null,
      labels: this.labels.map((l) => l.textContent),
    };
  }

  snapshot(size = 64) {
    return greySnapshot(this.renderer, this.scene, this.viewer.camera, size);
  }
}
