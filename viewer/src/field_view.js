// A result field on the model (docs/viewer.md "Fields"): nodal fields as smooth fringes on the
// shared mesh (each vertex's value as a texture coordinate into the legend's colours, so that
// band edges are sharp lines across faces, as in FE post-processors), element fields as flat ones
// (face_slots.js: each face its own slots, one colour), the values each vertex or face shows at a coarse level from ShownValues
// (max |value| or mean of what it stands for, so a peak is never hidden), and a marker at the
// peak. A field shows the values of the nearest whole step: never an interpolated value, so the
// peak on screen is a value of the file.
import * as THREE from 'three';

import { ShownValues } from './dpm.js';
import { faceSlotIndices, fillSlotColours, gatherSlotPositions } from './face_slots.js';
import { Fringe } from './fringe.js';

export class FieldView {
  // surface: the shared mesh (its geometry gets texture coordinates); radius: the marker's.
  constructor(scene, mesh, surface, radius) {
    this.mesh = mesh;
    const material = surface.material;
    this.shared = surface;
    this.sharedMaterial = material;
    this.uv = new Float32Array(2 * mesh.head.vertexCount);
    surface.geometry.setAttribute('uv', new THREE.BufferAttribute(this.uv, 2).setUsage(THREE.DynamicDrawUsage));
    this.texture = null;
    this.nodalMaterial = material.clone();
    this.nodalMaterial.vertexColors = false;
    const F = mesh.head.faceCount;
    this.slotPositions = new Float32Array(12 * F);
    this.slotColours = new Float32Array(12 * F);
    const g = (this.geometry = new THREE.BufferGeometry());
    g.setAttribute('position', new THREE.BufferAttribute(this.slotPositions, 3).setUsage(THREE.DynamicDrawUsage));
    g.setAttribute('color', new THREE.BufferAttribute(this.slotColours, 3).setUsage(THREE.DynamicDrawUsage));
    g.setIndex(new THREE.BufferAttribute(faceSlotIndices(F), 1));
    this.surface = new THREE.Mesh(g, material);
    this.surface.visible = false;
    this.marker = new THREE.Mesh(
      new THREE.SphereGeometry(radius, 16, 12),
      new THREE.MeshBasicMaterial({ color: 0xd0103a, depthTest: false, transparent: true, opacity: 0.9 }),
    );
    this.marker.renderOrder = 10;  // drawn over the model: the peak may be behind it
    this.marker.visible = false;
    scene.add(this.surface, this.marker);
    this.shown = null;
    this.fringe = null;
    this.peak = null;  // {item, value, where, position}
  }

  hide() {
    this.shared.material = this.sharedMaterial;
    this.surface.visible = false;
    this.marker.visible = false;
    this.shown = null;
  }

  // Field k at level nav.level and step round(t), with `options` {aggregate, range ('all' or
  // 'step'), min, max (null: automatic), bands, scheme, parts (a PartView: its hidden parts),
  // shown (values to show instead of field k's own: a FieldDifference, with its own range and
  // steps)}. Returns whether the shared surface is the one to show (nodal).
  update(k, nav, t, positions, options) {
    const { mesh } = this;
    const field = mesh.fields[k];
    const step = Math.min(Math.max(Math.round(t), 0), (options.shown?.stepCount ?? mesh.head.stepCount) - 1);
    let s = options.shown ?? this.shown;
    const Shown = nav.ShownValues ?? ShownValues;  // a selective navigator's own (refine_view.js)
    if (!options.shown && (!s || s.field !== field || s.mean !== (options.aggregate === 'mean') || s.constructor !== Shown))
      s = new Shown(mesh, field, options.aggregate, nav);
    this.shown = s;
    if (s.step !== step || s.splits !== mesh.splitsLoaded || !s.setLevel(nav.level)) s.set(step, nav.level);
    let [lo, hi] = s.range ?? (options.range === 'step' ? [s.stepMin, s.stepMax] : [field.min, field.max]);
    if (options.min !== null) lo = options.min;
    if (options.max !== null) hi = options.max;
    const fringe = (this.fringe = new Fringe({ lo, hi, bands: options.bands, scheme: options.scheme }));
    const F = nav.faceCount;
    if (field.perFace) {
      gatherSlotPositions(nav.corners, F, positions, this.slotPositions);
      options.parts?.collapseHidden(nav, this.slotPositions);  // hidden parts (part_view.js)
      fillSlotColours(fringe, s.values, F, this.slotColours);
      this.geometry.setDrawRange(0, 6 * F);
      for (const name of ['position', 'color']) {
        const a = this.geometry.attributes[name];
        a.clearUpdateRanges();
        a.addUpdateRange(0, 12 * F);
        a.needsUpdate = true;
      }
      this.shared.material = this.sharedMaterial;
    } else {
      this.nodalFringe(fringe, nav.vertexCount);
    }
    this.surface.visible = field.perFace;
    this.placeMarker(field, nav, positions);
    return !field.perFace;
  }

  // A nodal field: the legend's colours as a texture (one texel a band, nearest: sharp band
  // edges; 256 texels, linear, when continuous), each vertex its value's place in the range.
  nodalFringe(fringe, n) {
    const texels = fringe.bands || 256;
    const key = `${texels} ${fringe.stops.flat().join()}`;
    if (this.textureKey !== key) {
      const rgba = new Uint8Array(4 * texels);
      const c = [0, 0, 0];
      for (let i = 0; i < texels; i++) {
        fringe.colour(fringe.lo + ((i + 0.5) / texels) * (fringe.hi - fringe.lo), c, 0);
        if (!(fringe.hi > fringe.lo)) fringe.colour(fringe.lo, c, 0);
        rgba.set([c[0] * 255, c[1] * 255, c[2] * 255, 255], 4 * i);
      }
      this.texture?.dispose();
      this.texture = new THREE.DataTexture(rgba, texels, 1);
      const filter = fringe.bands ? THREE.NearestFilter : THREE.LinearFilter;
      Object.assign(this.texture, { magFilter: filter, minFilter: filter, needsUpdate: true });
      this.nodalMaterial.map = this.texture;
      this.nodalMaterial.needsUpdate = true;
      this.textureKey = key;
    }
    const { lo, hi } = fringe;
    const scale = hi > lo ? 1 / (hi - lo) : 0;
    const values = this.shown.values, uv = this.uv;
    for (let v = 0; v < n; v++) {
      const x = (values[v] - lo) * scale;
      uv[2 * v] = x < 0 ? 0 : x > 1 ? 1 : x;
      uv[2 * v + 1] = 0.5;
    }
    const a = this.shared.geometry.attributes.uv;
    a.clearUpdateRanges();
    a.addUpdateRange(0, 2 * n);
    a.needsUpdate = true;
    this.shared.material = this.nodalMaterial;
  }

  // The marker at the present vertex (face centroid) of largest |shown value|.
  placeMarker(field, nav, positions) {
    const s = this.shown;
    const item = s.peak();
    this.marker.visible = item >= 0;
    if (item < 0) return (this.peak = null);
    const p = [0, 0, 0];
    const corners = field.perFace ? nav.face(item) : [item];
    for (const v of corners) for (let c = 0; c < 3; c++) p[c] += positions[3 * v + c] / corners.length;
    this.marker.position.set(...p);
    const where = field.perFace ? `element ${this.mesh.elementId[item]}` : `node ${this.mesh.nodeId[item]}`;
    this.peak = { item, value: s.values[item], where, position: p };
  }

  // What is shown, for the browser test: the field's shown values and, for an element field, each
  // present face's four slot colours.
  describe(nav) {
    const s = this.shown;
    const n = s.itemCount(nav.level);
    return {
      field: this.mesh.fields.indexOf(s.field),
      perFace: s.field.perFace,
      step: s.step,
      level: s.level,
      aggregate: s.mean ? 'mean' : 'max',
      bands: this.fringe.bands,
      lo: this.fringe.lo,
      hi: this.fringe.hi,
      values: Array.from(s.values.subarray(0, n)),
      slotColours: s.field.perFace ? Array.from(this.slotColours.subarray(0, 12 * n)) : null,
      uv: s.field.perFace ? null : Array.from(this.uv.subarray(0, 2 * n)),
      peak: this.peak,
    };
  }
}
