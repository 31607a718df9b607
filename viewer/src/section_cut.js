// The section cut (docs/viewer.md "Picking, history, section, measure"): one plane clips
// everything drawn (the renderer's global clipping planes: the surface, its edges, the field
// views), and the outline where it cuts the faces on screen is drawn on the plane, with the
// plane's frame. The plane: a normal from an axis turned by two angles, through a point at a
// fraction of the model's box along it.
import * as THREE from 'three';

// Where the plane cuts faces [0, F) (corners: 4 slots per face, −1 in slot 3 of a triangle) at
// flat positions p: 2 points per segment into out (grown as needed); returns {out, count} with
// count the number of floats written. A face whose corners lie on both sides gives one segment
// per pair of crossings (two for a convex face); faces for which skip(f) holds (a hidden part's)
// give none.
export function cutSegments(plane, corners, F, p, out = new Float32Array(3 * 512), skip = null) {
  const { x: nx, y: ny, z: nz } = plane.normal;
  const w = plane.constant;
  let count = 0;
  const side = [0, 0, 0, 0];
  const crossing = [];
  for (let f = 0; f < F; f++) {
    if (skip?.(f)) continue;
    const c = 4 * f;
    const d = corners[c + 3] < 0 ? 3 : 4;
    let below = 0;
    for (let i = 0; i < d; i++) {
      const v = 3 * corners[c + i];
      side[i] = nx * p[v] + ny * p[v + 1] + nz * p[v + 2] + w;
      if (side[i] < 0) below++;
    }
    if (below === 0 || below === d) continue;
    crossing.length = 0;
    for (let i = 0; i < d; i++) {
      const j = (i + 1) % d;
      if (side[i] < 0 === side[j] < 0) continue;
      const a = side[i] / (side[i] - side[j]);
      const u = 3 * corners[c + i], v = 3 * corners[c + j];
      for (let k = 0; k < 3; k++) crossing.push(p[u + k] + (p[v + k] - p[u + k]) * a);
    }
    if (count + crossing.length > out.length) {
      const grown = new Float32Array(2 * out.length + crossing.length);
      grown.set(out.subarray(0, count));
      out = grown;
    }
    out.set(crossing, count);
    count += crossing.length - (crossing.length % 6);
  }
  return { out, count };
}

export class SectionCut {
  // box: the model's THREE.Box3 over every step.
  constructor(scene, renderer, box) {
    this.renderer = renderer;
    this.box = box;
    this.plane = new THREE.Plane(new THREE.Vector3(1, 0, 0), 0);
    this.settings = { enabled: false, axis: 'x', position: 0.5, tilt: 0, turn: 0, flip: false };
    this.positions = new Float32Array(3 * 512);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(this.positions, 3));
    this.outline = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: 0xc2185b }));
    this.outline.frustumCulled = false;
    this.outline.renderOrder = 5;
    this.frame = new THREE.LineLoop(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xc2185b, transparent: true, opacity: 0.35 }));
    this.frame.frustumCulled = false;
    this.outline.visible = this.frame.visible = false;
    scene.add(this.outline, this.frame);
    this.key = '';
    this.segmentCount = 0;
  }

  // Any of {enabled, axis ('x'|'y'|'z'), position (0…1 across the box), tilt, turn (degrees),
  // flip}: the part of the model on the plane's negative side is cut away.
  set(changes) {
    Object.assign(this.settings, changes);
    const s = this.settings;
    const axis = new THREE.Vector3(s.axis === 'x' ? 1 : 0, s.axis === 'y' ? 1 : 0, s.axis === 'z' ? 1 : 0);
    // Turned about the two other axes, in order: tilt about the next, turn about the one after.
    const next = new THREE.Vector3(axis.z, axis.x, axis.y), after = new THREE.Vector3(axis.y, axis.z, axis.x);
    const normal = axis.clone()
      .applyAxisAngle(next, THREE.MathUtils.degToRad(s.tilt))
      .applyAxisAngle(after, THREE.MathUtils.degToRad(s.turn));
    if (s.flip) normal.negate();
    const lo = this.box.min.dot(axis), hi = this.box.max.dot(axis);
    const point = this.box.getCenter(new THREE.Vector3());
    point.addScaledVector(axis, lo + (hi - lo) * s.position - point.dot(axis));
    this.plane.setFromNormalAndCoplanarPoint(normal, point);
    this.renderer.clippingPlanes = s.enabled ? [this.plane] : [];
    this.outline.visible = this.frame.visible = s.enabled;
    this.placeFrame(point, normal);
    this.key = '';
  }

  // Points on the kept side are shown (and picked).
  keeps(point) {
    return !this.settings.enabled || this.plane.distanceToPoint(new THREE.Vector3(...point)) >= -this.slack();
  }

  // How far outline and frame stand off the plane, so that its own clipping keeps them.
  slack() {
    return 1e-5 * this.box.getSize(new THREE.Vector3()).length();
  }

  // The outline of the level on screen (nav) at flat positions p, leaving out the faces for
  // which skip(f) holds (hidden parts), redone when the plane, the level, the positions or the
  // faces drawn changed (`version`: of the position and index buffers).
  update(nav, p, version, skip = null) {
    if (!this.settings.enabled || !nav) return;
    const key = `${nav.level ?? 0} ${nav.faceCount} ${version} ${this.plane.normal.toArray()} ${this.plane.constant}`;
    if (key === this.key) return;
    this.key = key;
    const { out, count } = cutSegments(this.plane, nav.corners, nav.faceCount, p, this.positions, skip);
    const n = this.plane.normal, e = 2 * this.slack();  // just on the kept side
    for (let i = 0; i < count; i += 3) (out[i] += n.x * e), (out[i + 1] += n.y * e), (out[i + 2] += n.z * e);
    const g = this.outline.geometry;
    if (out !== this.positions) {
      this.positions = out;
      g.setAttribute('position', new THREE.BufferAttribute(out, 3));
    } else {
      g.attributes.position.needsUpdate = true;
    }
    g.setDrawRange(0, count / 3);
    this.segmentCount = count / 6;
  }

  // A square around the model in the plane, to show where it is when it cuts nothing.
  placeFrame(point, normal) {
    const size = this.box.getSize(new THREE.Vector3()).length() * 0.45;
    const u = new THREE.Vector3().crossVectors(normal, Math.abs(normal.x) < 0.9 ? new THREE.Vector3(1, 0, 0) : new THREE.Vector3(0, 1, 0)).normalize();
    const v = new THREE.Vector3().crossVectors(normal, u);
    const centre = point.clone().addScaledVector(normal, 2 * this.slack());
    const corners = [[1, 1], [-1, 1], [-1, -1], [1, -1]].map(([a, b]) => centre.clone().addScaledVector(u, a * size).addScaledVector(v, b * size));
    this.frame.geometry.setFromPoints(corners);
  }
}
