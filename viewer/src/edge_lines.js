// Element edges that read over every colour under them (docs/viewer.md "Rendering"): one fixed
// edge colour vanishes over one end of a colour scale (dark lines on viridis's dark purple or
// the rainbow's blue), so each edge vertex takes the surface's colour there, made darker over
// light colours and lighter over dark ones. The edges share the faces' colour attribute; in
// field modes (whose surfaces use a texture or per-face slots) the vertex colours are filled
// from the field's colours for the edges alone.
import * as THREE from 'three';

// Luminance of a linear RGB colour (the vertex colours are linear; the renderer writes sRGB).
const luminance = (r, g, b) => 0.2126 * r + 0.7152 * g + 0.0722 * b;
// Above this luminance an edge is the colour × DARKEN, below it the colour mixed LIGHTEN of
// the way to white: the two contrasts meet near 2.4 : 1 at the switch.
export const EDGE_SWITCH = 0.25, DARKEN = 0.3, LIGHTEN = 0.6;

// The edge colour over surface colour c (the shader's rule, for the tests).
export function edgeColour([r, g, b]) {
  if (luminance(r, g, b) > EDGE_SWITCH) return [r * DARKEN, g * DARKEN, b * DARKEN];
  return [r + (1 - r) * LIGHTEN, g + (1 - g) * LIGHTEN, b + (1 - b) * LIGHTEN];
}

// WCAG's contrast ratio of two linear colours.
export function contrast(a, b) {
  const [la, lb] = [luminance(...a), luminance(...b)];
  return (Math.max(la, lb) + 0.05) / (Math.min(la, lb) + 0.05);
}

export function edgeMaterial() {
  const material = new THREE.LineBasicMaterial({ vertexColors: true, transparent: true, opacity: 0.8 });
  material.onBeforeCompile = (shader) => {
    shader.vertexShader = shader.vertexShader.replace(
      '#include <color_vertex>',
      `#include <color_vertex>
      {
        float l = dot(vColor.rgb, vec3(0.2126, 0.7152, 0.0722));
        vColor.rgb = l > ${EDGE_SWITCH.toFixed(3)} ? vColor.rgb * ${DARKEN.toFixed(3)} : mix(vColor.rgb, vec3(1.0), ${LIGHTEN.toFixed(3)});
      }`,
    );
  };
  material.customProgramCacheKey = () => 'dynpm-contrast-edges';
  return material;
}

// The shown field's colours at the n vertices of the level (for the edges): a nodal field's
// vertex values, an element field's face colours (a vertex takes one face's that holds it).
export function fieldColoursAtVertices(fieldView, nav, colours) {
  const { fringe, shown } = fieldView;
  if (!shown.field.perFace) {
    for (let v = 0; v < nav.vertexCount; v++) fringe.colour(shown.values[v], colours, 3 * v);
    return;
  }
  const corners = nav.corners, slots = fieldView.slotColours;
  for (let f = 0; f < nav.faceCount; f++) {
    const d = corners[4 * f + 3] < 0 ? 3 : 4;
    for (let k = 0; k < d; k++) colours.set(slots.subarray(12 * f, 12 * f + 3), 3 * corners[4 * f + k]);
  }
}
