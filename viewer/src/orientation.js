// Where the camera looks from (docs/viewer.md "Orientation"): the standard views along ±X, ±Y,
// ±Z and an isometric one, fit all, which axis is up (y or z: chosen from the model, with a
// toggle), the wheel zooming toward the cursor, and the axis triad drawn in the corner of the
// canvas (so that it is in saved images and recordings too); a click on one of its axes looks
// along that axis (again: the other way).
import * as THREE from 'three';

import { onCanvasClick } from './canvas_click.js';

const $ = (id) => document.getElementById(id);

// A view name → the direction the camera looks along (as ParaView's "+X" … buttons: '-z' looks
// down from above on a z-up model).
const AXES = { x: 0, y: 1, z: 2 };
export const VIEW_NAMES = ['+x', '-x', '+y', '-y', '+z', '-z', 'iso', 'fit'];

// The up axis a model probably has (a .dpm records none), y or z: the one it moves along most
// from its first state to its last (mean |Δ| over the base mesh's vertices), if at least twice
// as much as along the other (a column crushed from above, a rail bent upward); else the one its
// box is thinner along (vehicles, rails and boxes lie flat). ?up=y|z overrides.
export function upAxisOf(mesh, param = null) {
  if (param === 'y' || param === 'z') return param;
  const h = mesh.head;
  const n = h.baseVertexCount;
  if (h.stepCount > 1 && n > 0) {
    const first = mesh.positionsAt(0, n, new Float32Array(3 * n));
    const last = mesh.positionsAt(h.stepCount - 1, n, new Float32Array(3 * n));
    const moved = [0, 0, 0];
    for (let i = 0; i < 3 * n; i++) moved[i % 3] += Math.abs(last[i] - first[i]);
    if (moved[2] >= 2 * moved[1] && moved[2] > 0) return 'z';
    if (moved[1] >= 2 * moved[2] && moved[1] > 0) return 'y';
  }
  const extent = (c) => h.bboxMax[c] - h.bboxMin[c];
  return extent(2) < extent(1) ? 'z' : 'y';
}

// Fit all: `box` (the file's, over every step) grown to hold the first n points of `positions`
// (what is shown now: a deformation scale above 1 takes the model out of the file's box).
export function grownBox(box, positions, n) {
  const grown = box.clone();
  const p = new THREE.Vector3();
  for (let i = 0; i < 3 * n; i += 3) grown.expandByPoint(p.fromArray(positions, i));
  return grown;
}

// The share of the canvas's width that the open panel leaves (1 without it): viewer.js's view
// offset puts the picture's centre in the middle of that part, which is then the centred window
// as wide as it (Fit frames the model there; the view refine asks for it).
export function besidePanel(camera) {
  const view = camera.view?.enabled ? camera.view : null;
  return view ? (view.fullWidth + 2 * view.offsetX) / view.fullWidth : 1;
}

export class Orientation {
  // viewer: {camera, controls, renderer, requestRender(), fitBox(): THREE.Box3 to fit}.
  constructor(viewer) {
    this.viewer = viewer;
    viewer.controls.zoomToCursor = true;
    this.up = 'y';
    this.ui = { up: $('up-axis'), views: document.querySelectorAll('#orientation [data-view]') };
    for (const b of this.ui.views) b.addEventListener('click', () => this.setView(b.dataset.view));
    this.ui.up.addEventListener('change', () => this.setUp(this.ui.up.value));
    this.triad = new Triad();
    this.listen(viewer.canvas);
  }

  // A click (not a drag) on an arrow of the triad: the view along that axis, or, when already
  // looking along it, the other way. It marks the event handled (preventDefault) so that the
  // pick on pointerup (inspect.js) leaves it alone.
  listen(canvas) {
    onCanvasClick(canvas, (x, y, e) => {
      const axis = this.triad.axisAt(x, y, canvas.clientWidth, canvas.clientHeight);
      if (!axis) return;
      e.preventDefault();
      const along = this.describe().look[AXES[axis]] > 0.99;
      this.setView(`${along ? '-' : '+'}${axis}`);
    });
  }

  // The unit vector of the up axis, and "north": screen-up in views along the up axis.
  frame() {
    const up = new THREE.Vector3().setComponent(AXES[this.up], 1);
    const north = this.up === 'z' ? new THREE.Vector3(0, 1, 0) : new THREE.Vector3(0, 0, -1);
    return { up, north };
  }

  setUp(axis) {
    if (axis !== 'y' && axis !== 'z') throw new Error(`up axis '${axis}': y or z`);
    this.up = axis;
    this.ui.up.value = axis;
    const { camera, controls } = this.viewer;
    camera.up.copy(this.frame().up);
    // OrbitControls keeps the rotation from camera.up to +y made at its construction, with no
    // setter: remade here so that orbiting turns about the new up axis.
    controls._quat.setFromUnitVectors(camera.up, new THREE.Vector3(0, 1, 0));
    controls._quatInverse.copy(controls._quat).invert();
    this.setView('iso');
  }

  // One of VIEW_NAMES; the camera then shows the whole model ('fit' keeps the direction).
  setView(name) {
    if (!VIEW_NAMES.includes(name)) throw new Error(`view '${name}': one of ${VIEW_NAMES.join(', ')}`);
    const { camera, controls } = this.viewer;
    const { up, north } = this.frame();
    let from;  // from the target toward the camera
    if (name === 'fit') {
      from = camera.position.clone().sub(controls.target);
    } else if (name === 'iso') {
      from = this.up === 'z' ? new THREE.Vector3(1, -1, 1) : new THREE.Vector3(1, 1, 1);
    } else {
      const look = new THREE.Vector3().setComponent(AXES[name[1]], name[0] === '+' ? 1 : -1);
      from = look.clone().negate();
      // Along the up axis: a hair off it on the side that puts "north" at the top of the screen
      // (orbit controls cannot look exactly along their up axis).
      if (Math.abs(look.dot(up)) > 0.5) from.addScaledVector(north, 1e-4 * Math.sign(look.dot(up)));
    }
    if (from.lengthSq() === 0) from.set(1, 1, 1);
    this.fit(from.normalize());
  }

  // Frames the box of viewer.fitBox() from direction `from`: the camera as close as it can be
  // with every corner of the box inside the picture.
  fit(from) {
    const { camera, controls } = this.viewer;
    const box = this.viewer.fitBox();
    const center = box.getCenter(new THREE.Vector3());
    camera.position.copy(center).add(from);
    camera.lookAt(center);
    camera.updateMatrixWorld();
    const [right, up, back] = [0, 1, 2].map((c) => new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, c));
    const tanV = Math.tan(THREE.MathUtils.degToRad(camera.fov / 2));
    const tanH = tanV * camera.aspect * besidePanel(camera);
    let distance = 0, depth = 0;
    const p = new THREE.Vector3();
    for (let corner = 0; corner < 8; corner++) {
      p.set(corner & 1 ? box.max.x : box.min.x, corner & 2 ? box.max.y : box.min.y, corner & 4 ? box.max.z : box.min.z).sub(center);
      const toward = p.dot(back);  // toward the camera: nearer, so it needs more distance
      distance = Math.max(distance, Math.abs(p.dot(right)) / tanH + toward, Math.abs(p.dot(up)) / tanV + toward);
      depth = Math.max(depth, Math.abs(toward));
    }
    distance = Math.max(distance * 1.04, 1e-9);  // a small margin
    controls.target.copy(center);
    camera.position.copy(center).addScaledVector(from, distance);
    camera.near = distance / 100;
    camera.far = (distance + depth) * 10;
    camera.updateProjectionMatrix();
    controls.update();
    this.viewer.requestRender();
  }

  // The up axis, the view direction and screen-up (unit), the orbit's centre and the camera.
  describe() {
    const { camera, controls } = this.viewer;
    const look = controls.target.clone().sub(camera.position).normalize();
    const screenUp = new THREE.Vector3(0, 1, 0).applyQuaternion(camera.quaternion);
    return { up: this.up, look: look.toArray(), screenUp: screenUp.toArray(), target: controls.target.toArray(), camera: camera.position.toArray() };
  }
}

// The axis triad: three arrows (x red, y green, z blue, labelled) turned as the camera is,
// drawn last in the bottom-right corner over the picture.
class Triad {
  constructor() {
    this.scene = new THREE.Scene();
    this.camera = new THREE.OrthographicCamera(-1.25, 1.25, 1.25, -1.25, 0.1, 10);
    this.camera.position.set(0, 0, 5);
    this.group = new THREE.Group();
    const colours = [0xd0302a, 0x2f9a3a, 0x2d62c8];
    ['X', 'Y', 'Z'].forEach((label, c) => {
      const material = new THREE.MeshBasicMaterial({ color: colours[c] });
      const shaft = new THREE.Mesh(new THREE.CylinderGeometry(0.05, 0.05, 0.7, 8), material);
      const head = new THREE.Mesh(new THREE.ConeGeometry(0.13, 0.25, 12), material);
      shaft.position.y = 0.35;
      head.position.y = 0.82;
      const arrow = new THREE.Group().add(shaft, head);
      // Cylinders stand along +y: turned onto axis c.
      arrow.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), new THREE.Vector3().setComponent(c, 1));
      const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: letter(label, colours[c]), depthTest: false }));
      sprite.position.setComponent(c, 1.1);
      sprite.scale.setScalar(0.38);
      this.group.add(arrow, sprite);
    });
    this.scene.add(this.group);
    this.size = 90;  // CSS pixels
    this.margin = { right: 6, bottom: 34 };
    this.viewport = new THREE.Vector4();
  }

  // The axis ('x', 'y' or 'z') whose arrow head or letter is nearest CSS pixel (x, y) of a canvas
  // of width × height, within 15 px; null elsewhere. The arrows as last drawn.
  axisAt(x, y, width, height) {
    const left = width - this.size - this.margin.right, top = height - this.margin.bottom - this.size;
    const toPixels = this.size / (this.camera.right - this.camera.left);
    let best = null, nearest = 15;
    for (const [axis, c] of Object.entries(AXES))
      for (const along of [0.82, 1.1]) {  // the cone's middle, the letter
        const p = new THREE.Vector3().setComponent(c, along).applyQuaternion(this.group.quaternion);
        const d = Math.hypot(left + (p.x - this.camera.left) * toPixels - x, top + (this.camera.top - p.y) * toPixels - y);
        if (d < nearest) (nearest = d), (best = axis);
      }
    return best;
  }

  render(renderer, camera) {
    this.group.quaternion.copy(camera.quaternion).invert();
    const width = renderer.domElement.clientWidth;
    renderer.getViewport(this.viewport);
    renderer.autoClear = false;
    renderer.clearDepth();
    renderer.setViewport(width - this.size - this.margin.right, this.margin.bottom, this.size, this.size);
    renderer.render(this.scene, this.camera);
    renderer.setViewport(this.viewport);
    renderer.autoClear = true;
  }
}

// A letter as a sprite's texture (a canvas of the page: no image file to serve).
function letter(text, colour) {
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = 64;
  const g = canvas.getContext('2d');
  g.font = 'bold 44px system-ui, sans-serif';
  g.textAlign = 'center';
  g.textBaseline = 'middle';
  g.fillStyle = `#${colour.toString(16).padStart(6, '0')}`;
  g.fillText(text, 32, 34);
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  return texture;
}
