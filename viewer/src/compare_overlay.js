// How the two models of a comparison are laid out (docs/viewer.md "Compare", Layout): side by
// side on two canvases, or overlaid — B drawn on A's canvas, in one colour that neither fringe
// scheme holds, as its element edges alone or as a translucent surface with its edges, at B's
// linked level and step. Overlaid, A keeps its colours (parts, a fringe, the difference), and
// where the two shapes part the magenta lines or skin stand off A's surface. The overlay draws
// B's own geometry (the same buffers B's canvas draws; three uploads them to A's context too).
import * as THREE from 'three';

import { panelChoice } from './panel.js';

export const LAYOUTS = {
  side: 'side by side',
  edges: 'overlaid: B\'s edges',
  surface: 'overlaid: B translucent',
};
export const OVERLAY_COLOUR = 0xd020d0;  // magenta: in neither viridis nor rainbow

export class CompareOverlay {
  // viewer: {scene, requestRender, resize} (viewer.js). onChange (if set) hears of every change.
  constructor(viewer) {
    this.viewer = viewer;
    this.surface = new THREE.Mesh(new THREE.BufferGeometry(), new THREE.MeshLambertMaterial({
      color: OVERLAY_COLOUR, flatShading: true, side: THREE.DoubleSide,
      transparent: true, opacity: 0.35, depthWrite: false,  // A shows through B's skin
    }));
    this.edges = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: OVERLAY_COLOUR }));
    // After A's own edges: where B's edge lies on A's, B's colour is seen.
    this.edges.renderOrder = 2;
    this.surface.renderOrder = 3;
    for (const o of [this.edges, this.surface]) (o.visible = false), viewer.scene.add(o);
    this.layout = 'side';
    this.select = panelChoice('compare-layout', 'Layout', LAYOUTS, 'B beside A, or drawn over A in magenta', (l) => this.set(l)).select;
  }

  get overlaid() {
    return this.layout !== 'side';
  }

  // B's geometry (at its base mesh): the overlay draws it.
  draw(geometry, edgeGeometry) {
    this.surface.geometry = geometry;
    this.edges.geometry = edgeGeometry;
  }

  // One of LAYOUTS' keys; anything else is refused with the list.
  set(layout) {
    if (!Object.hasOwn(LAYOUTS, layout))
      throw new RangeError(`layout ${JSON.stringify(String(layout))}: one of ${Object.keys(LAYOUTS).join(', ')}`);
    this.layout = this.select.value = layout;
    this.edges.visible = this.overlaid;
    this.surface.visible = layout === 'surface';
    document.body.classList.toggle('compare-overlay', this.overlaid);
    this.onChange?.();
    this.viewer.resize();
    this.viewer.requestRender();
  }
}
