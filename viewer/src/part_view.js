// Parts on the model (docs/viewer.md "Parts"): one flat, saturated colour per part with a hard
// edge at the part line — every face has four vertex slots of its own (face_slots.js, as the
// element fringes), so no vertex blends two parts — and parts shown or hidden. A hidden part's
// faces leave every index buffer (the shared surface's, the element edges', the part slots'),
// so it is neither drawn nor hit by a ray. Names come from the file's PART chunk (dpm/parts.js);
// parts without one go by their id.
import * as THREE from 'three';

import { writeFaceIndices } from './dpm.js';
import { gatherSlotPositions } from './face_slots.js';

// The k-th part (ascending id): hues spaced by the golden angle, so that parts next in the list
// differ clearly whatever their ids (ids 102 and 301 could fall on one hue); high saturation at
// mid lightness, so that a part reads as one colour under the lights.
export function partColour(k) {
  return new THREE.Color().setHSL((0.58 + k * 0.618033988749895) % 1, 0.9, 0.5);
}

export class PartView {
  // material: the shared surface's (vertex colours, flat shading); sphere: the model's bounds.
  constructor(scene, mesh, material, sphere) {
    this.mesh = mesh;
    this.hidden = new Set();
    this.colours = new Map();  // id → Float32Array rgb
    this.rank = new Map();  // id → its colour's index: ascending id at BASE, then as parts arrive
    for (const id of this.ids()) this.rank.set(id, this.rank.size);
    this.room = 0;  // faces the slot buffers hold
    this.geometry = new THREE.BufferGeometry();
    this.geometry.boundingSphere = sphere;
    this.surface = new THREE.Mesh(this.geometry, material);
    this.surface.visible = false;
    scene.add(this.surface);
  }

  // Every part of the loaded file, ascending: those PART names and those the loaded faces use.
  ids() {
    const { mesh } = this;
    const loaded = mesh.faceCountAt[mesh.splitsLoaded] ?? mesh.head.baseFaceCount;
    const ids = new Set(mesh.partNames.keys());
    for (const id of mesh.partId.subarray(0, loaded)) ids.add(id);
    return [...ids].sort((a, b) => a - b);
  }

  list() {
    return this.ids().map((id) => ({ id, name: this.mesh.partNames.get(id) ?? null, visible: !this.hidden.has(id) }));
  }

  // Shows (hides) the parts `ids`; returns whether anything changed.
  setVisible(ids, visible) {
    const changed = ids.filter((id) => this.hidden.has(id) === visible);
    for (const id of changed) visible ? this.hidden.delete(id) : this.hidden.add(id);
    return changed.length > 0;
  }

  colour(id) {
    let c = this.colours.get(id);
    if (!c) {
      if (!this.rank.has(id)) this.rank.set(id, this.rank.size);
      this.colours.set(id, (c = Float32Array.from(partColour(this.rank.get(id)).toArray())));
    }
    return c;
  }

  // The CSS colour of part id's swatch.
  colourStyle(id) {
    return new THREE.Color(...this.colour(id)).getStyle();
  }

  // The shared index entries of `faces` (all present faces when null): a hidden part's face as
  // an empty triangle pair and zero-length edges, the others as writeFaceIndices() makes them.
  mask(nav, faces, tri, edges) {
    if (faces ? this.hidden.size === 0 : this.hidden.size === 0 && !this.wasMasked) return;
    if (!faces) this.wasMasked = this.hidden.size > 0;
    const F = nav.faceCount, part = this.mesh.partId, corners = nav.corners;
    const n = faces ? faces.length : F;
    for (let i = 0; i < n; i++) {
      const f = faces ? faces[i] : i;
      if (f >= F) continue;
      if (!this.hidden.has(part[f])) {
        if (!faces) writeFaceIndices(nav, f, tri, edges);
        continue;
      }
      tri.fill(corners[4 * f], 6 * f, 6 * f + 6);
      edges.fill(corners[4 * f], 8 * f, 8 * f + 8);
    }
  }

  // Slot buffers for at least F faces (grown by doubling: the level grows as the file arrives).
  makeRoom(F) {
    if (F <= this.room) return;
    this.room = Math.max(F, 2 * this.room, 1024);
    const g = this.geometry;
    this.slotPositions = new Float32Array(12 * this.room);
    this.slotColours = new Float32Array(12 * this.room);
    this.index = new Uint32Array(6 * this.room);
    g.dispose();  // the GPU buffers of the old size
    g.setAttribute('position', new THREE.BufferAttribute(this.slotPositions, 3).setUsage(THREE.DynamicDrawUsage));
    g.setAttribute('color', new THREE.BufferAttribute(this.slotColours, 3).setUsage(THREE.DynamicDrawUsage));
    g.setIndex(new THREE.BufferAttribute(this.index, 1).setUsage(THREE.DynamicDrawUsage));
  }

  // The present faces of shown parts, each its part's colour on its own four slots.
  drawLevel(nav) {
    const F = nav.faceCount, part = this.mesh.partId;
    this.makeRoom(F);
    const { slotColours: rgb, index } = this;
    let j = 0;
    for (let f = 0; f < F; f++) {
      const id = part[f];
      if (this.hidden.has(id)) continue;
      const c = this.colour(id);
      for (let o = 12 * f; o < 12 * f + 12; o += 3) (rgb[o] = c[0]), (rgb[o + 1] = c[1]), (rgb[o + 2] = c[2]);
      const s = 4 * f;
      index[j] = s, index[j + 1] = s + 1, index[j + 2] = s + 2;
      index[j + 3] = s, index[j + 4] = s + 2, index[j + 5] = s + 3;
      j += 6;
    }
    this.geometry.setDrawRange(0, j);
    this.upload('color', 12 * F);
    this.upload(null, j);
    this.surface.visible = true;
  }

  // The shared vertex colours, which the element edges read (edge_lines.js): each vertex takes
  // the colour of a face that holds it, so that the edges contrast with the part under them.
  vertexColours(nav, colours) {
    const part = this.mesh.partId, k = nav.corners;
    for (let f = 0; f < nav.faceCount; f++) {
      const c = this.colour(part[f]);
      for (let i = 4 * f; i < 4 * f + 4; i++) if (k[i] >= 0) colours.set(c, 3 * k[i]);
    }
  }

  // The slots' positions at the current step.
  drawPositions(nav, positions) {
    const F = nav.faceCount;
    this.makeRoom(F);
    gatherSlotPositions(nav.corners, F, positions, this.slotPositions);
    this.upload('position', 12 * F);
  }

  // Hidden parts' faces in an element fringe's slots (field_view.js): all four slots on the
  // first, an empty face.
  collapseHidden(nav, slotPositions) {
    if (this.hidden.size === 0) return;
    const part = this.mesh.partId;
    for (let f = 0; f < nav.faceCount; f++) {
      if (!this.hidden.has(part[f])) continue;
      const o = 12 * f;
      for (let k = 3; k < 12; k++) slotPositions[o + k] = slotPositions[o + (k % 3)];
    }
  }

  hide() {
    this.surface.visible = false;
  }

  // What is drawn, for the browser test: the faces drawn (in index order) and every present
  // face's four slot colours.
  describe(nav) {
    const drawn = [];
    for (let j = 0; j < this.geometry.drawRange.count; j += 6) drawn.push(this.index[j] / 4);
    return { faces: nav.faceCount, drawn, slotColours: Array.from(this.slotColours.subarray(0, 12 * nav.faceCount)) };
  }

  upload(name, count) {
    const a = name ? this.geometry.attributes[name] : this.geometry.index;
    if (count === 0) return;
    a.clearUpdateRanges();
    a.addUpdateRange(0, count);
    a.needsUpdate = true;
  }
}
