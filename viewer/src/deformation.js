// The deformation scale and the undeformed ghost (docs/viewer.md "Deformation"): the shown
// positions are p(0) + s · (p(t) − p(0)) for s from 0 (undeformed) to 10 (small motions made
// visible), and the ghost is the mesh at step 0 drawn faintly over it, at the same level (it
// shares the faces' index buffer). Displacement colours keep the true |p(t) − p(0)|.
import * as THREE from 'three';

const $ = (id) => document.getElementById(id);
export const MAX_SCALE = 10;

export class Deformation {
  // viewer: {state, scene, extendBase0(), redraw(): positions again at state.t}.
  constructor(viewer) {
    this.viewer = viewer;
    this.scale = 1;
    this.ui = { section: $('deformation'), scale: $('deform-scale'), label: $('deform-scale-label'), ghost: $('ghost') };
    this.ui.scale.max = String(MAX_SCALE);
    this.ui.scale.addEventListener('input', () => this.setScale(Number(this.ui.scale.value)));
    this.ui.ghost.addEventListener('change', () => this.setGhost(this.ui.ghost.checked));
    this.ghostGeometry = new THREE.BufferGeometry();
    this.ghost = new THREE.Mesh(this.ghostGeometry, new THREE.MeshBasicMaterial({
      color: 0x7d8796, transparent: true, opacity: 0.28, depthWrite: false, side: THREE.DoubleSide,
    }));
    this.ghost.frustumCulled = false;  // its box is the file's, as the model's
    this.ghost.renderOrder = 1;  // after the opaque model
    this.ghost.visible = false;
    this.ghostVertices = 0;  // step-0 positions uploaded
    this.trueScratch = null;
    viewer.scene.add(this.ghost);
    this.showLabel();
  }

  onHead(head) {
    this.ui.section.hidden = head.stepCount < 2;  // nothing moves
  }

  setScale(s) {
    if (!(s >= 0 && s <= MAX_SCALE)) throw new RangeError(`deformation scale ${s}: from 0 to ${MAX_SCALE}`);
    this.scale = s;
    this.ui.scale.value = String(s);
    this.showLabel();
    if (this.viewer.state.nav) this.viewer.redraw();
  }

  setGhost(on) {
    this.ghost.visible = Boolean(on);
    this.ui.ghost.checked = this.ghost.visible;
    if (this.viewer.state.nav) this.viewer.redraw();
  }

  showLabel() {
    this.ui.label.textContent = this.scale === 0 ? '×0 (undeformed)' : `×${this.scale.toFixed(1)}`;
  }

  // Called after the positions of the n visible vertices at state.t were written (viewer.js):
  // scales them about step 0 and keeps the ghost on the faces of the level shown.
  update(positions, n, geometry) {
    const { state } = this.viewer;
    const s = this.scale;
    if (s !== 1 || this.ghost.visible) this.viewer.extendBase0();
    if (s !== 1) {
      const b = state.base0;
      for (let i = 0; i < 3 * n; i++) positions[i] = b[i] + s * (positions[i] - b[i]);
    }
    if (this.ghost.visible) this.updateGhost(geometry);
  }

  updateGhost(geometry) {
    const { state } = this.viewer;
    const g = this.ghostGeometry;
    if (g.attributes.position?.array !== state.base0) {
      g.setAttribute('position', new THREE.BufferAttribute(state.base0, 3));
      this.ghostVertices = 0;
    }
    if (this.ghostVertices !== state.base0Count) {
      const a = g.attributes.position;
      a.addUpdateRange(3 * this.ghostVertices, 3 * (state.base0Count - this.ghostVertices));
      a.needsUpdate = true;
      this.ghostVertices = state.base0Count;
    }
    if (g.index !== geometry.index) g.setIndex(geometry.index);  // shared: one upload serves both
    g.setDrawRange(geometry.drawRange.start, geometry.drawRange.count);
  }

  // The true positions at state.t (the shown ones unless scaled), for displacement colours.
  unscaled(positions, n) {
    if (this.scale === 1) return positions;
    const { mesh, t } = this.viewer.state;
    this.trueScratch ??= new Float32Array(3 * mesh.head.vertexCount);
    return mesh.positionsAt(t, n, this.trueScratch);
  }
}
