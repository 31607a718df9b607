// Picking, time histories, the section cut and measuring (issue 21 items 2, 3, 7, 8; docs/viewer.md
// "Picking, history, section, measure"), beside the page of viewer.js, which only calls
// installInspect(). A click (not a drag) on the model picks the ORIGINAL element and node under the
// cursor (pick.js) and adds them to the picks: markers follow them through time and levels, the
// panel lists the latest one's numbers and values, the plot draws a quantity for every pick over
// all steps, and the last two picks are measured. Everything follows the page at each render
// (the scene's onBeforeRender, chained): no other hook in viewer.js.
import * as THREE from 'three';

import { onCanvasClick } from './canvas_click.js';
import { HistoryPlot, SERIES_COLOURS, download, historyCsv } from './history_plot.js';
import { Ids, OriginalMesh, describePick, historyOf, rayCrossing, vertexAt } from './pick.js';
import { SectionCut } from './section_cut.js';
import { fmt } from './fringe.js';

const MAX_PICKS = 8;

const $ = (id) => document.getElementById(id);

// page: {renderer, scene, camera, surface, state (viewer.js's: mesh, nav, t), requestRender, done}.
export function installInspect(page) {
  const inspect = new Inspect(page);
  Object.assign((window.dynpm ??= {}), {
    pick: (x, y) => inspect.pick(x, y),
    history: (id, quantity) => inspect.history(id, quantity),
    // Beyond the list: what the panel does, for scripts and the tests.
    select: (x, y) => inspect.select(x, y),
    picks: () => inspect.picks.map((p) => inspect.describe(p)),
    clearPicks: () => inspect.clear(),
    // Where the node markers were drawn at the last render (world positions, as the GPU got them).
    markers: () => inspect.markers.children.filter((o) => o.isMesh).map((o) => new THREE.Vector3().setFromMatrixPosition(o.matrixWorld).toArray()),
    measure: () => inspect.measure(),
    setPlot: (quantity) => inspect.setPlot(quantity),
    historyCsv: () => inspect.csv(),
    setSection: (settings) => inspect.setSection(settings),
    section: () => inspect.sectionState(),
  });
  return inspect;
}

class Inspect {
  constructor(page) {
    Object.assign(this, page);
    this.ui = {
      info: $('pick-info'), plot: $('history-plot'), quantity: $('history-quantity'), csv: $('history-csv'),
      clear: $('pick-clear'), measure: $('measure-info'), section: $('section'), axis: $('section-axis'),
      position: $('section-position'), tilt: $('section-tilt'), turn: $('section-turn'), flip: $('section-flip'),
    };
    this.picks = [];  // {face, vertex} in the .dpm's numbering, of the finest loaded level
    this.original = null;
    this.ids = null;
    this.cut = null;
    // On the kept side of the section, and of a part that is shown (part_list.js).
    this.keep = (point, face) => (!this.cut || this.cut.keeps(point)) && !this.partHidden?.(face);
    this.plot = new HistoryPlot(this.ui.plot);
    this.markers = new THREE.Group();
    this.markers.renderOrder = 11;
    this.scene.add(this.markers);
    this.shownKey = '';
    const before = this.scene.onBeforeRender;
    this.scene.onBeforeRender = (...a) => (before.apply(this.scene, a), this.follow());
    this.listen();
  }

  get ready() {
    return Boolean(this.state.mesh?.hasBase && this.state.nav);
  }

  listen() {
    // Prevented: a click on the axis triad (orientation.js), not on the model.
    onCanvasClick(this.renderer.domElement, (x, y, e) => e.defaultPrevented || this.select(x, y));
    this.ui.clear.addEventListener('click', () => this.clear());
    this.ui.quantity.addEventListener('change', () => this.setPlot(this.ui.quantity.value));
    this.ui.csv.addEventListener('click', () => this.picks.length && download(this.csv(), `${this.state.name.replace(/\.dpm$/, '')}-${this.quantity()}.csv`));
    const { section, axis, position, tilt, turn, flip } = this.ui;
    const read = () => this.setSection({ enabled: section.checked, axis: axis.value, position: Number(position.value) / 100, tilt: Number(tilt.value), turn: Number(turn.value), flip: flip.checked });
    for (const input of [section, axis, flip]) input.addEventListener('change', read);
    for (const input of [position, tilt, turn]) input.addEventListener('input', read);
  }

  // ------------------------------------------------------------------------------------------
  // Picking

  // The page's deformation scale (deformation.js): the drawn positions are scaled about step 0.
  scale() {
    return this.deformation?.scale ?? 1;
  }

  // The ray through CSS pixel (x, y) of the canvas, and where it first meets the level on screen
  // (the drawn positions) on the kept side of the section, or null.
  screenHit(x, y) {
    const r = this.renderer.domElement.getBoundingClientRect();
    const raycaster = new THREE.Raycaster();
    raycaster.setFromCamera(new THREE.Vector2((2 * x) / r.width - 1, 1 - (2 * y) / r.height), this.camera);
    const origin = raycaster.ray.origin.toArray(), direction = raycaster.ray.direction.toArray();
    const hit = rayCrossing(this.state.nav, this.surface.geometry.attributes.position.array, origin, direction, this.keep);
    return hit && { origin, direction, distance: hit.s };
  }

  // {face, vertex} of the original mesh under (x, y), or null.
  originalAt(x, y) {
    if (!this.ready) return null;
    const hit = this.screenHit(x, y);
    if (!hit) return null;
    this.original ??= new OriginalMesh(this.state.mesh);
    return this.original.pick(this.state.t, hit.origin, hit.direction, hit.distance, this.keep, this.state.nav, this.scale());
  }

  pick(x, y) {
    const o = this.originalAt(x, y);
    return o && this.describe(o);
  }

  // Picks as a click does: the item joins the picks (markers, panel, plot, measure).
  select(x, y) {
    const o = this.originalAt(x, y);
    if (!o) return null;
    this.picks = [...this.picks.filter((p) => p.vertex !== o.vertex), o].slice(-MAX_PICKS);
    this.refresh();
    return this.describe(o);
  }

  clear() {
    this.picks = [];
    this.refresh();
  }

  describe(o) {
    return describePick(this.state.mesh, o.face, o.vertex, this.state.t);
  }

  // ------------------------------------------------------------------------------------------
  // Histories and measuring

  // One value per step of node `id` (the file's node number) or, for an element field, element
  // `id`: 'displacement', 'distance' is not one node's, or a field's name.
  history(id, quantity) {
    const { mesh } = this.state;
    this.ids ??= new Ids(mesh);
    if (quantity === 'distance') throw new Error('a distance is of two nodes: measure() gives it for the last two picks');
    const field = mesh.fields.find((f) => f.name === quantity);
    const item = field?.perFace ? this.ids.faceOfElement(id) : this.ids.vertexOfNode(id);
    if (item < 0) throw new Error(`no ${field?.perFace ? 'element' : 'node'} ${id} in the loaded model`);
    return Array.from(historyOf(mesh, item, quantity));
  }

  quantity() {
    return this.ui.quantity.value;
  }

  setPlot(quantity) {
    if (![...this.ui.quantity.options].some((o) => o.value === quantity)) throw new Error(`cannot plot "${quantity}"`);
    this.ui.quantity.value = quantity;
    this.refresh();
  }

  // The plotted series: per pick (its node, or its element for an element field), or the
  // distance of the last two picks.
  series() {
    const { mesh } = this.state;
    const q = this.quantity();
    if (q === 'distance') {
      const m = this.measure();
      return m ? [{ label: `distance node ${m.nodes[0]} – node ${m.nodes[1]}`, values: m.history }] : [];
    }
    const field = mesh.fields.find((f) => f.name === q);
    return this.picks.map((p) => ({
      label: field?.perFace ? `element ${mesh.elementId[p.face]}` : `node ${mesh.nodeId[p.vertex]}`,
      values: historyOf(mesh, field?.perFace ? p.face : p.vertex, q),
    }));
  }

  csv() {
    return historyCsv(this.series(), Array.from(this.state.mesh.head.times));
  }

  // Distance of the last two picked nodes now, at step 0 and at every step, or null.
  measure() {
    if (this.picks.length < 2) return null;
    const { mesh, t } = this.state;
    const [a, b] = this.picks.slice(-2).map((p) => p.vertex);
    const pa = vertexAt(mesh, a, t), pb = vertexAt(mesh, b, t);
    const history = Array.from(historyOf(mesh, a, 'distance', b));
    const now = Math.hypot(...pa.map((x, c) => x - pb[c]));
    return { nodes: [mesh.nodeId[a], mesh.nodeId[b]], distance: now, initial: history[0], change: now - history[0], history };
  }

  // ------------------------------------------------------------------------------------------
  // Section

  setSection(settings) {
    if (!this.ready) return this.sectionState();
    if (!this.cut) {
      const { bboxMin, bboxMax } = this.state.mesh.head;
      this.cut = new SectionCut(this.scene, this.renderer, new THREE.Box3(new THREE.Vector3(...bboxMin), new THREE.Vector3(...bboxMax)));
    }
    this.cut.set(settings);
    const s = this.cut.settings, ui = this.ui;
    ui.section.checked = s.enabled, ui.axis.value = s.axis, ui.flip.checked = s.flip;
    ui.position.value = String(100 * s.position), ui.tilt.value = String(s.tilt), ui.turn.value = String(s.turn);
    this.requestRender();
    return this.sectionState();
  }

  sectionState() {
    const c = this.cut;
    if (!c) return { enabled: false };
    this.follow();
    return { ...c.settings, normal: c.plane.normal.toArray(), constant: c.plane.constant, segments: c.segmentCount, outline: Array.from(c.outline.geometry.attributes.position.array.subarray(0, 6 * c.segmentCount)) };
  }

  // ------------------------------------------------------------------------------------------
  // What follows time and level: markers, panel, plot cursor, outline (at each render).

  follow() {
    if (!this.ready) return;
    const { state } = this;
    if (!this.populated) {
      // Option(text, value): a field's name from FDEF is text.
      for (const f of state.mesh.fields) this.ui.quantity.add(new Option(`${f.name} (${f.perFace ? 'element' : 'node'})`, f.name));
      this.populated = true;
    }
    const geometry = this.surface.geometry, position = geometry.attributes.position;
    // The index buffer changes when a part is shown or hidden (its faces leave it).
    this.cut?.update(state.nav, position.array, `${position.version} ${geometry.index.version}`, this.partHidden);
    this.plot.mark(state.t);
    const key = `${state.t} ${this.scale()} ${this.picks.length} ${this.picks.at(-1)?.vertex}`;
    if (key === this.shownKey) return;
    this.shownKey = key;
    this.placeMarkers();
    this.showInfo();
  }

  // Another variant of a family file (variant_choice.js): its own positions and values.
  meshChanged() {
    this.original = null;
    this.refresh();
  }

  refresh() {
    this.shownKey = '';
    const series = this.series();
    this.plot.draw(series, Array.from(this.state.mesh.head.times), this.quantity());
    this.plot.mark(this.state.t);
    this.ui.plot.hidden = series.length === 0;
    this.ui.csv.disabled = series.length === 0;
    this.requestRender();
  }

  // A sphere at each picked node, the latest's element outlined, at their original positions.
  placeMarkers() {
    const { mesh, t } = this.state;
    const h = mesh.head;
    const radius = Math.hypot(...h.bboxMax.map((x, c) => x - h.bboxMin[c])) / 160;
    for (const o of this.markers.children) o.geometry.dispose(), o.material.dispose();
    this.markers.clear();
    const s = this.scale();  // markers sit where the page draws their nodes
    this.picks.forEach((p, i) => {
      const colour = SERIES_COLOURS[i % SERIES_COLOURS.length];
      const dot = new THREE.Mesh(new THREE.SphereGeometry(radius, 12, 8), new THREE.MeshBasicMaterial({ color: colour, depthTest: false, transparent: true }));
      dot.position.set(...vertexAt(mesh, p.vertex, t, undefined, s));
      dot.renderOrder = 11;
      this.markers.add(dot);
    });
    const last = this.picks.at(-1);
    if (last) {
      const corners = this.original.level(t, this.state.nav).nav.face(last.face);
      const points = corners.map((v) => new THREE.Vector3(...vertexAt(mesh, v, t, undefined, s)));
      const loop = new THREE.LineLoop(new THREE.BufferGeometry().setFromPoints(points), new THREE.LineBasicMaterial({ color: 0xffd400, depthTest: false, transparent: true }));
      loop.renderOrder = 12;  // over the dots
      this.markers.add(loop);
    }
    const m = this.measure();
    if (m) {
      const [a, b] = this.picks.slice(-2).map((p) => new THREE.Vector3(...vertexAt(mesh, p.vertex, t, undefined, s)));
      const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([a, b]), new THREE.LineDashedMaterial({ color: 0x202124, depthTest: false, transparent: true, dashSize: radius, gapSize: radius / 2 }));
      line.computeLineDistances();
      line.renderOrder = 11;
      this.markers.add(line);
    }
    this.markers.updateMatrixWorld(true);  // placed in onBeforeRender, after the scene's update
  }

  // The panel: the latest pick's numbers and values (text nodes: names come from the file).
  showInfo() {
    const last = this.picks.at(-1);
    const row = (name, value) => {
      const dt = document.createElement('dt'), dd = document.createElement('dd');
      dt.textContent = name;
      dd.textContent = value;
      return [dt, dd];
    };
    if (!last) {
      this.ui.info.replaceChildren('click the model to pick an element and node');
      this.ui.measure.replaceChildren('pick two nodes to measure their distance');
      return;
    }
    const d = this.describe(last);
    const list = document.createElement('dl');
    const part = document.createElement('span');
    part.id = 'pick-part-name';  // the name from the file, as text
    part.textContent = d.partName ?? '';
    const partRow = row('part', `${d.part} `);
    partRow[1].append(part);
    list.append(
      ...row('node', `${d.node} (vertex ${d.vertex})`), ...row('element', String(d.element)), ...partRow,
      ...row('position', d.position.map((x) => fmt(x)).join(', ')), ...row('displacement', fmt(d.displacement)),
      ...Object.entries(d.values).flatMap(([name, v]) => row(`${name} (step ${d.step})`, fmt(v))),
    );
    this.ui.info.replaceChildren(list);
    const m = this.measure();
    this.ui.measure.replaceChildren(m
      ? `node ${m.nodes[0]} – node ${m.nodes[1]}: ${fmt(m.distance)} (step 0: ${fmt(m.initial)}, change ${fmt(m.change)})`
      : 'pick two nodes to measure their distance');
    Object.assign(this.ui.measure.dataset, m ? { distance: String(m.distance) } : {});
  }
}
