// The page of `dynpm view`: streams a .dpm (src/dpm.js), shows the base mesh as soon as BASE has
// arrived and refines as SPLT chunks follow; time and resolution sliders, element edges, colour
// by part, displacement or a result field (field_view.js), stats. docs/viewer.md has the design and the measured numbers.
//
// GPU buffers grow with the loaded mesh (draw_buffers.js). Time changes rewrite only the position
// (and colour) prefix of the visible vertices; resolution changes rewrite only the index entries
// of the faces the splits touched (fixed slots per face, see writeFaceIndices in dpm.js).
//
// The bare imports ('three', …) are rewritten to vendor/ paths when the page is embedded
// (viewer/embed/): the page has no import map, an inline script its CSP would refuse.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

import { installApi } from './api.js';
import { BaseLevel } from './base_level.js';
import { compareFile, CompareView, DIFFERENCE } from './compare_view.js';
import { Deformation } from './deformation.js';
import { Navigator, ProgressiveMesh, updateIndices } from './dpm.js';
import { compileShaders, growDrawBuffers, uploadIndices } from './draw_buffers.js';
import { edgeMaterial, fieldColoursAtVertices } from './edge_lines.js';
import { installErrorLevel } from './error_level.js';
import { FieldView } from './field_view.js';
import { Images } from './images.js';
import { installInspect } from './inspect.js';
import { memoryUse } from './memory_use.js';
import { budgetedVertices, memoryBudget, modelFile, verticesBeforePause, wantedVertices } from './model_file.js';
import { grownBox, Orientation, upAxisOf } from './orientation.js';
import { Panel } from './panel.js';
import { addPartsApi, PartList } from './part_list.js';
import { PartView } from './part_view.js';
import { drawLabels } from './labels.js';
import { installRefine } from './refine_view.js';
import { scrub } from './scrub.js';
import { greySnapshot, pixels } from './snapshot.js';
import { States } from './states.js';
import { VariantList } from './variant_choice.js';
import { decodeInWorker, decodeOnPage } from './worker_decoder.js';
import { Fringe, fringeLegend, fringeOptions, int } from './fringe.js';

const $ = (id) => document.getElementById(id);
const ui = {
  title: $('title'),
  note: $('note'),
  time: $('time'),
  timeLabel: $('time-label'),
  resolution: $('resolution'),
  resolutionLabel: $('resolution-label'),
  edges: $('edges'),
  colour: $('colour'),
  legend: $('legend'),
  fringeControls: $('fringe-controls'),
  scheme: $('scheme'),
  bands: $('bands'),
  continuous: $('continuous'),
  aggregate: $('aggregate'),
  range: $('range'),
  rangeMin: $('range-min'),
  rangeMax: $('range-max'),
  reset: $('reset'),
  loadingBar: $('loading-bar'),
  stats: $('stats'),
  error: $('error'),
};

const state = {
  name: 'model.dpm',
  totalBytes: 0,
  bytesLoaded: 0,
  mesh: null,
  nav: null,
  t: 0,
  loading: true,  // the file is still arriving (the status line's "…")
  follow: true,  // keep the resolution at the finest level loaded while the file arrives
  colour: 'part',
  base0: null,  // positions at step 0 of the first base0Count vertices (displacement colours)
  base0Count: 0,
  ranges: new Map(),  // colour mode → [min, max] over every step
  decoder: {},  // want(vertices): the worker fetches more (worker_decoder.js)
  exporting: false,  // a picture or video is being made: no room left for the panel (dodgePanel())
};

// ---------------------------------------------------------------------------------------------
// three.js scene

// ?antialias=0 turns multisampling off (for software renderers, where it costs the most).
const params = new URLSearchParams(location.search);
const renderer = new THREE.WebGLRenderer({
  canvas: $('view'),
  antialias: params.get('antialias') !== '0',
});
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setClearColor(0xeef0f3);
const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(35, 1, 0.1, 1000);
scene.add(camera);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8890a0, 1.6));
const headlight = new THREE.DirectionalLight(0xffffff, 1.6);
headlight.position.set(0.3, 0.5, 1);  // in camera space: follows the view
camera.add(headlight);
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener('change', () => requestRender());

let geometry = null;  // faces (two triangles per face slot)
let edgeGeometry = null;  // element edges (four segments per face slot)
// flatShading: normals from screen-space derivatives, so a time change needs no normal pass.
// Made, and their shaders compiled (load()), before the file arrives: a software renderer
// takes seconds to compile them, which would delay the first picture.
const surface = new THREE.Mesh(new THREE.BufferGeometry(), new THREE.MeshLambertMaterial({
  vertexColors: true, flatShading: true, side: THREE.DoubleSide,
  polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,  // faces behind their edges
}));
const edgeLines = new THREE.LineSegments(new THREE.BufferGeometry(), edgeMaterial());  // edge_lines.js
let positions = null;  // Float32Array(3 × vertex room)
let colours = null;  // Float32Array(3 × vertex room)
let triIndex = null;  // Uint32Array(6 × face room)
let edgeIndex = null;  // Uint32Array(8 × face room)
let scratch = null;  // Float32Array(vertex room): per-vertex scalar for colours
let fieldView = null, fieldMarkerRadius = 1;  // result fields (field_view.js), made when shown
let parts = null, partList = null;  // part colours and visibility (part_view.js), made at BASE
let compare = null;  // the second model, right of this one (compare_view.js), if any
const room = { vertices: 0, faces: 0 };  // what the draw buffers hold

function createGeometry(mesh) {
  geometry = new THREE.BufferGeometry();
  edgeGeometry = new THREE.BufferGeometry();
  const h = mesh.head;
  makeRoom(h.baseVertexCount, h.baseFaceCount, 4 * h.baseVertexCount + 4096, 4 * h.baseFaceCount + 4096);
  // The box holds every vertex at every step: set once, never recomputed from the buffers.
  const { bboxMin: lo, bboxMax: hi } = mesh.head;
  const box = new THREE.Box3(new THREE.Vector3(...lo), new THREE.Vector3(...hi));
  const sphere = box.getBoundingSphere(new THREE.Sphere());
  geometry.boundingSphere = sphere;
  edgeGeometry.boundingSphere = sphere;
  geometry.boundingBox = box;
  surface.geometry = geometry;
  edgeLines.geometry = edgeGeometry;
  edgeLines.visible = ui.edges.checked;
  scene.add(surface, edgeLines);
  fieldMarkerRadius = sphere.radius / 60;
}

function makeRoom(vertices, faces, ...atFirst) {
  const grown = growDrawBuffers({ positions, colours, triIndex, edgeIndex, scratch }, room, vertices, faces, state.mesh.head, geometry, edgeGeometry, state.expectedVertices, ...atFirst);
  if (grown) ({ positions, colours, triIndex, edgeIndex, scratch } = grown);
}

function resize() {
  const left = compare ? compare.left(panel) : 0;  // compare: what the panel leaves, halved side by side
  const w = (window.innerWidth - left) / (compare?.columns() ?? 1), h = window.innerHeight - (compare ? compare.bottom(ui.stats) : 0);
  renderer.setSize(w, h, false);
  compare?.resize(w, h);
  camera.aspect = w / h;
  dodgePanel();
}
window.addEventListener('resize', resize);

// The open panel floats over the canvas's left side: the picture's centre moves to the middle of
// what it leaves free (three's view offset; orientation.js fits the model into that part), so
// that a fitted model is not drawn under it. Not beside compare's canvases (they start right of
// the panel), in a window the panel would half cover, nor in a saved picture or video
// (images.js: `state.exporting`).
function dodgePanel() {
  const { x: w, y: h } = renderer.getSize(new THREE.Vector2());
  const right = compare || state.exporting || panel.collapsed ? 0 : panel.ui.panel.getBoundingClientRect().right;
  if (right > 0 && right < w / 2) camera.setViewOffset(w, h, -right / 2, 0, w, h);  // updates the projection
  else camera.clearViewOffset();
  requestRender();
}

let renderPending = false;
function requestRender() {
  if (renderPending) return;
  renderPending = true;
  requestAnimationFrame(frame);
}

function frame(now) {
  renderPending = false;
  states.tick(now);  // playback (states.js)
  renderNow();
}

function renderNow() {
  renderer.render(scene, camera);
  orientation.triad.render(renderer, camera);
  compare?.render();
}

// ---------------------------------------------------------------------------------------------
// Updates

// Vertices [first, end) of an attribute go up at the next render. Ranges add up until then
// (three clears them after uploading), so two updates between frames both arrive.
function upload(attribute, first = 0, end = state.nav.vertexCount) {
  if (end <= first) return;  // (needsUpdate without a range would upload the whole buffer)
  attribute.addUpdateRange(3 * first, 3 * (end - first));
  attribute.needsUpdate = true;
}
const uploadColours = (first, end) => upload(geometry.attributes.color, first, end);

// Positions (and displacement/field colours) of the visible vertices at state.t.
function updateTime({ render = true } = {}) {
  const { mesh, nav, t } = state;
  const n = nav.vertexCount;
  mesh.positionsAt(t, n, positions);
  deformation.update(positions, n, geometry);  // the deformation scale and the ghost
  // A finer level at the same t: only the new vertices' positions changed.
  upload(geometry.attributes.position, t === state.shownT ? Math.min(n, state.shownN) : 0, n);
  Object.assign(state, { shownT: t, shownN: n });
  if (state.colour !== 'part') updateScalarColours();
  else parts.drawPositions(nav, positions);
  updateLabels();
  compare?.sync();  // the same step and level on the second model
  if (render) requestRender();
}

// After a change of level: the index entries of the touched faces, and what depends on the
// level (part colours, counts).
function updateLevel() {
  const { nav } = state;
  makeRoom(nav.vertexCount, nav.faceCount);
  const touched = {}, changed = updateIndices(nav, triIndex, edgeIndex, touched);
  parts.mask(nav, touched.faces, triIndex, edgeIndex);  // hidden parts stay out
  uploadIndices(geometry, edgeGeometry, nav.faceCount, changed);
  if (state.colour === 'part') drawParts(nav);
  updateTime();
}

function setTime(t) {
  state.t = t;
  ui.time.value = String(t);
  if (!refine.timeChanged()) updateTime();  // a refinement that follows time redraws itself
}

// Splits applied or undone per task when the slider (or the arriving file) moves the level far:
// the rest follows in the next frames, so that no task of the page takes long.
const SPLITS_PER_STEP = 65536;

// The level with n vertices (n ≥ what is loaded: follow the file as it arrives); `now`: in one
// go (the tests' and benchmarks' entry), else in steps of SPLITS_PER_STEP, one a frame.
function setVertexCount(n, now = false) {
  state.follow = n >= state.mesh.vertexCountLoaded;
  // By ranges: more (the draw buffers grow by 4× again past what was expected).
  if (n > state.mesh.vertexCountLoaded && state.decoder.want) (state.loading = true), (state.budgetLimits = false), (state.expectedVertices = Infinity), state.decoder.want(n);
  state.targetVertices = n;
  ui.resolution.value = String(n);
  stepLevel(now);
}

function stepLevel(now = false) {
  const { nav, mesh } = state;
  if (refine.levelChanged(state.targetVertices, state.follow)) return;  // the level elsewhere
  const n = Math.max(mesh.head.baseVertexCount, Math.min(state.follow ? Infinity : state.targetVertices, mesh.vertexCountLoaded));
  const from = nav.vertexCount;
  nav.setVertexCount(now ? n : Math.max(from - SPLITS_PER_STEP, Math.min(n, from + SPLITS_PER_STEP)));
  if (state.follow) ui.resolution.value = String(nav.vertexCount);
  updateLevel();
  if (nav.vertexCount !== n && !state.levelPending) {
    state.levelPending = true;
    requestAnimationFrame(() => {
      state.levelPending = false;
      stepLevel();
    });
  }
}

// ---------------------------------------------------------------------------------------------
// Colours

// Each face on its part's slots; the element edges read the shared vertex colours, which take
// the part colours too (else they would keep the last scalar colouring's).
function drawParts(nav) {
  parts.drawLevel(nav);
  parts.vertexColours(nav, colours);
  uploadColours(0, nav.vertexCount);
}

// Parts shown or hidden (part_list.js): every present face's index entries, then the colours.
function partsChanged() {
  const { nav } = state;
  parts.mask(nav, null, triIndex, edgeIndex);
  for (const [g, per] of [[geometry, 6], [edgeGeometry, 8]])
    g.index.addUpdateRange(0, per * nav.faceCount), (g.index.needsUpdate = true);
  setColour(state.colour);
}

// The field shown ('field:k', or compare's A − B of it, 'fielddiff:k'), or −1.
function fieldIndex() {
  const m = /^field(?:diff)?:(\d+)$/.exec(state.colour);
  return m ? Number(m[1]) : -1;
}

// Displacement or a field, as colours of the visible vertices (or faces); then the legend.
function updateScalarColours() {
  const { nav } = state;
  const n = nav.vertexCount;
  const options = fringeOptions(ui);
  const k = fieldIndex();
  let smooth = true;
  if (k >= 0) {
    // Made on first use: its per-face buffers cost nothing to a model shown without fields.
    fieldView ??= new FieldView(scene, state.mesh, surface, fieldMarkerRadius);
    smooth = fieldView.update(k, nav, state.t, positions, { ...options, parts, ...compare?.fieldDifference(state.colour, options.aggregate) });
    state.fringe = fieldView.fringe;
    fieldColoursAtVertices(fieldView, nav, colours);  // for the edges
  } else if (state.colour === DIFFERENCE) {
    // |p_A − p_B| at this step and level; the legend's range is this step's (compare_view.js).
    const largest = compare.difference(deformation.unscaled(positions, n), positions, n, scratch);
    const fringe = (state.fringe = new Fringe({ ...options, lo: options.min ?? 0, hi: options.max ?? largest?.value ?? 0 }));
    for (let v = 0; v < n; v++) fringe.colour(scratch[v], colours, 3 * v);
    fieldView?.hide();
  } else {
    extendBase0();
    ProgressiveMesh.displacement(deformation.unscaled(positions, n), state.base0, n, scratch);
    let [lo, hi] = scalarRange();
    if (options.range === 'step') [lo, hi] = [0, scratch.subarray(0, n).reduce((a, x) => Math.max(a, x), 0)];
    const fringe = (state.fringe = new Fringe({ lo: options.min ?? lo, hi: options.max ?? hi, ...options }));
    for (let v = 0; v < n; v++) fringe.colour(scratch[v], colours, 3 * v);
    fieldView?.hide();
  }
  surface.visible = smooth;
  uploadColours();
  drawLegend();
}

// The displacement's range over every step of the loaded vertices, so that it stays put while
// time changes; recomputed as vertices arrive.
function scalarRange() {
  const key = state.colour;
  let range = state.ranges.get(key);
  if (range) return range;
  const { mesh } = state;
  const n = mesh.vertexCountLoaded;
  extendBase0();
  const p = new Float32Array(3 * n);
  const d = new Float32Array(n);
  let hi = 0;
  for (let t = 0; t < mesh.head.stepCount; t++) {
    ProgressiveMesh.displacement(mesh.positionsAt(t, n, p), state.base0, n, d);
    for (let v = 0; v < n; v++) if (d[v] > hi) hi = d[v];
  }
  range = [0, hi];
  state.ranges.set(key, range);
  return range;
}

// Names in the legend come from the file: they go in as text nodes, never as markup
// (Element.append turns strings into Text; the page has no innerHTML at all).
function drawLegend() {
  const { mesh } = state;
  ui.fringeControls.hidden = state.colour === 'part';
  if (state.colour === 'part') return ui.legend.replaceChildren();  // the part list says it
  if (!state.fringe) return;
  const k = fieldIndex();
  const field = k >= 0 ? mesh.fields[k] : null;
  const title = field ? `${field.name}${state.colour.startsWith('fielddiff:') ? ' A − B' : ''} (${field.perFace ? 'element' : 'node'}, step ${fieldView.shown.step})` : state.colour === DIFFERENCE ? 'difference |p_A(t) − p_B(t)|' : 'displacement';
  const peak = field ? fieldView.peak : compare?.peak();
  ui.legend.replaceChildren(...fringeLegend(state.fringe, { title, unit: field?.unit ?? '', peak }));
  Object.assign(ui.legend.dataset, { bands: String(state.fringe.bands), min: String(state.fringe.lo), max: String(state.fringe.hi) });
}

function setColour(mode) {
  state.colour = mode;
  ui.colour.value = mode;
  if (mode === 'part') {
    fieldView?.hide();
    surface.visible = false;  // each face on its own slots (part_view.js)
    drawParts(state.nav);
    parts.drawPositions(state.nav, positions);
  } else {
    parts.hide();
    updateScalarColours();
  }
  drawLegend();
  updateLabels();
  compare?.sync();
  requestRender();
}

// ---------------------------------------------------------------------------------------------
// Labels (labels.js): the time and resolution labels and the status line

function updateLabels() {
  drawLabels(state, ui, refine, fieldIndex());
}

function showError(e) {
  console.error(e);
  ui.error.hidden = false;
  ui.error.textContent = String(e.message ?? e);
  panel.loaded();
}

// ---------------------------------------------------------------------------------------------
// Loading

function onHead(mesh) {
  timing.head = performance.now();
  state.mesh = mesh;
  const h = mesh.head;
  ui.time.max = String(h.stepCount - 1);
  ui.resolution.min = String(h.baseVertexCount);
  ui.resolution.max = String(h.vertexCount);
  // Whether the worker stops at the memory budget's levels (model_file.js), for the label.
  state.budgetLimits = state.worker && wantedVertices(params) === Infinity && budgetedVertices(h, state.memoryBudget) < h.vertexCount;
  // What the worker loads before it pauses (the draw buffers grow to it, not past it).
  state.expectedVertices = state.worker ? verticesBeforePause(h, wantedVertices(params), state.memoryBudget) : Infinity;
  ui.note.textContent = h.note;
  createGeometry(mesh);
  states.onHead(h);  // a one-state model: no time controls, no displacement, no deformation
  deformation.onHead(h);
}

function onBase(mesh) {
  timing.base = performance.now();
  variants.onBase(mesh);  // a family file's member (variant_choice.js)
  // Option(text, value): the field's name from FDEF is text.
  for (let f = 0; f < mesh.fields.length; f++) ui.colour.add(new Option(mesh.fields[f].name, `field:${f}`));
  // Drawn at once from BASE; the Navigator (arrays for every face of the whole mesh) comes
  // from the worker, or is made here after the frame that shows the base (?worker=0).
  state.nav = new BaseLevel(mesh);
  parts = new PartView(scene, mesh, surface.material, geometry.boundingSphere);
  surface.visible = state.colour !== 'part';
  updateLevel();
  partList = new PartList(parts, partsChanged);
  orientation.setUp(upAxisOf(mesh, params.get('up')));  // and the iso view
  drawLegend();
  panel.loaded();
  timing.baseDone = performance.now();
  timing.baseBytes = state.bytesLoaded;  // what had arrived when the base was drawn
  if (!state.worker) requestAnimationFrame(() => setTimeout(() => onNavigator(new Navigator(mesh))));
}

// From the next frame on: the base is shown first, whatever arrives meanwhile.
function onNavigator(nav) {
  timing.navigator = performance.now();
  requestAnimationFrame(() => setTimeout(() => ((state.nav = nav), stepLevel())));
}

function onSplits(mesh) {
  state.ranges.clear();  // more vertices: the legend's range may grow
  if (!(state.nav instanceof Navigator)) return;  // stepLevel() follows once it is made
  if (state.follow) stepLevel();
  else updateLabels();
  partList.refresh();  // parts whose first faces came with these splits
  if (state.colour !== 'part') updateScalarColours();
}

// Made when displacement is first shown, not for every model.
function extendBase0() {
  const { mesh } = state;
  const n = mesh.vertexCountLoaded;
  if (n <= state.base0Count) return;
  if (!state.base0) state.base0 = new Float32Array(3 * mesh.head.vertexCount);
  mesh.positionsAt(0, n, state.base0);
  state.base0Count = n;
}

async function load() {
  resize();  // before the file: sizing the canvas costs a software renderer much
  compileShaders(renderer, scene, camera, [surface, edgeLines]);
  const { file, name, config } = await modelFile(params);
  const other = compareFile(params, config);  // ?compare= or `dynpm view A B`: side by side
  if (other) (compare = new CompareView(viewer, other, { antialias: params.get('antialias') !== '0' })), resize();
  state.name = name;
  ui.title.textContent = state.name;
  panel.loading(`loading ${state.name}…`);
  document.title = `${state.name} — dynpm view`;
  const onProgress = (received) => {
    state.bytesLoaded = received;
    if (state.totalBytes) ui.loadingBar.style.width = `${(100 * received) / state.totalBytes}%`;
  };
  // The decode runs in a worker (worker_decoder.js); ?worker=0 keeps it here, for comparison.
  state.worker = params.get('worker') !== '0';
  const url = new URL(file, location.href).href;
  const alongside = compare?.url === url;  // two members of this file: one fetch, one decode
  // The memory budget (model_file.js); a second file takes half of it.
  state.memoryShared = Boolean(compare && !alongside);
  state.memoryBudget = memoryBudget(params) / (state.memoryShared ? 2 : 1);
  if (state.memoryShared) compare.loading = compare.load(state.worker, state.memoryBudget).catch(showError);  // its own worker
  const onStart = (total, shared = false, rangeRequests = false, positionsWorker = false) => Object.assign(state, { totalBytes: total, sharedMemory: shared, rangeRequests, positionsWorker });
  let decode = variants.callbacks({ url, name: state.name, onHead, onBase, onSplits, onStart, onProgress, onNavigator });
  if (alongside) decode = compare.alongside(decode);
  const onFirstBytes = (at) => (timing.firstByte = at);
  const onDecoded = (at) => (timing.decoded = at);  // the worker's last chunk, in the page's clock
  // Fetched by ranges up to ?vertices=N (model_file.js); the slider asks for more.
  const onDependencies = (deps) => refine.dependenciesReady(deps);
  const positionsWorker = params.get('positionsWorker') !== '0';  // 0: positions in the decode worker itself
  const worker = { ...decode, onDependencies, onFirstBytes, onDecoded, positionsWorker, vertices: wantedVertices(params), memory: state.memoryBudget, control: state.decoder, onPaused: () => ((state.loading = false), state.nav && updateLabels()) };
  const decoding = state.worker ? decodeInWorker(worker) : decodeOnPage(decode);
  if (alongside) compare.follow(decoding);
  const decoder = await decoding;
  if (!decoder.mesh?.hasBase) throw new Error(`${state.name}: ends before the base mesh`);
  if (!decoder.complete) showError(`${state.name}: the file ends early (no END chunk): showing the ${int(decoder.mesh.vertexCountLoaded)} vertices it holds`);
  state.ranges.clear();
  state.loading = false;
  if (state.colour !== 'part') setColour(state.colour);
  updateLabels();
  ui.loadingBar.style.width = '100%';
  compare?.sync();
  requestRender();
}

// ---------------------------------------------------------------------------------------------
// Controls

ui.time.addEventListener('input', () => {
  if (state.mesh?.hasBase) setTime(Number(ui.time.value));
});
ui.resolution.addEventListener('input', () => {
  if (state.nav) setVertexCount(Number(ui.resolution.value));
});
ui.edges.addEventListener('change', () => {
  if (edgeLines) edgeLines.visible = ui.edges.checked;
  requestRender();
});
ui.colour.addEventListener('change', () => {
  if (state.nav) setColour(ui.colour.value);
});
for (const input of [ui.scheme, ui.bands, ui.continuous, ui.aggregate, ui.range, ui.rangeMin, ui.rangeMax])
  input.addEventListener(input.tagName === 'SELECT' || input.type === 'checkbox' ? 'change' : 'input', () => {
    if (state.nav && state.colour !== 'part') setColour(state.colour);
  });
ui.reset.addEventListener('click', () => geometry && orientation.setView('iso'));
window.addEventListener('keydown', (e) => {
  if (e.target instanceof HTMLInputElement && e.target.type !== 'range') return;
  if (e.key === 'r') geometry && orientation.setView('iso');
  if (e.key === 'f') geometry && orientation.setView('fit');
});

// The view's parts (states.js, orientation.js, deformation.js, images.js, panel.js) and the
// scripting API (api.js) see the page through `viewer`.
const redraw = () => ((state.shownT = NaN), updateTime());
const fitBox = () => grownBox(geometry.boundingBox, positions, state.nav?.vertexCount ?? 0);
const viewer = { state, ui, scene, camera, controls, canvas: renderer.domElement, requestRender, renderNow, resize, dodgePanel, setTime, setVertexCount, setColour, extendBase0, redraw, fitBox, updateLevel, partView: () => parts };
const panel = new Panel();
panel.onToggle = () => (compare ? resize() : dodgePanel());  // compare's canvases move beside it
const states = (viewer.states = new States(viewer));
const orientation = (viewer.orientation = new Orientation(viewer));
const deformation = (viewer.deformation = new Deformation(viewer));
viewer.images = new Images(viewer);
const refine = installRefine(viewer);  // selective refinement (refine_view.js)
installErrorLevel(viewer);  // the panel's "max error" box (error_level.js)
// A family file's members (variant_choice.js); the field view and picking then read the new one.
const variants = new VariantList(viewer, params.get('variant'), (mesh) => ((fieldView && (fieldView.mesh = mesh)), inspect.meshChanged()));

// For the browser tests and benchmarks: the state, the picture (snapshot.js), page times of the
// first bytes (worker; else the fetch's responseStart), HEAD, BASE and the base mesh made.
const timing = { firstByte: undefined, head: undefined, base: undefined, baseDone: undefined, baseBytes: undefined };
const loading = load();
const done = loading.catch(showError);
installApi({ ...viewer, loading });
const partHidden = (f) => Boolean(parts?.hidden.has(state.mesh.partId[f]));
const inspect = installInspect({ renderer, scene, camera, surface, state, requestRender, deformation, partHidden });
addPartsApi(() => partList);
window.dpmViewer = {
  done,
  timing,
  state: () => ({
    hasBase: Boolean(state.nav),
    navigator: state.nav instanceof Navigator,
    rangeRequests: Boolean(state.rangeRequests),
    worker: Boolean(state.worker),
    sharedMemory: Boolean(state.sharedMemory),
    positionsWorker: Boolean(state.positionsWorker),  // the positions decoded on a second worker
    complete: Boolean(state.mesh?.complete),
    paused: Boolean(state.nav && !state.loading && !state.mesh?.complete),  // ?vertices=N, the budget
    vertices: state.nav?.vertexCount ?? 0,
    faces: state.nav?.faceCount ?? 0,
    triangles: state.nav?.triangleCount ?? 0,
    quads: state.nav?.quadCount ?? 0,
    loadedVertices: state.mesh?.vertexCountLoaded ?? 0,
    t: state.t,
    bytesLoaded: state.bytesLoaded,
    error: ui.error.hidden ? null : ui.error.textContent,
  }),
  memory: () => memoryUse(state.mesh, state.nav, { positions, colours, triIndex, edgeIndex, scratch }, { base0: state.base0 }),
  fringe: () => (fieldView?.shown ? fieldView.describe(state.nav) : null),
  partSlots: () => parts?.describe(state.nav),
  // done: both files in and the page's load ended (its last compare.sync() checks the hierarchy).
  compare: () => compare && { ...compare.describe(), done: Promise.all([compare.loading, done]).then(() => true) },
  compareSnapshot: (size = 64) => compare.snapshot(size),
  snapshot: (size = 64) => greySnapshot(renderer, scene, camera, size),
  pixels: () => pixels(renderer, scene, camera),
  // Sets the resolution as the slider does and renders; returns the milliseconds taken by the
  // page's JS (navigator, index and position buffers) and in all, with the upload and one frame
  // (the refine measurement of docs/viewer.md).
  setVertexCount(n) {
    const start = performance.now();
    setVertexCount(n, true);
    const js = performance.now() - start;
    renderer.render(scene, camera);
    renderer.getContext().finish();
    return { js, total: performance.now() - start };
  },
  // Scrubs time over `frames` animation frames, as a dragged slider does (scrub.js).
  scrub: (frames = 120) => scrub({ state, ui, renderer, scene, camera, updateTime }, frames),
};
