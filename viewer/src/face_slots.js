// Geometry for flat per-face fringes (element fields): every face has four vertex slots of its
// own, so a face is one colour with no blending into its neighbours, and a quad stays a quad
// (two triangles over its own four slots; a triangle repeats slot 0 in slot 3, which makes its
// second triangle empty). The index buffer never changes: a change of level or time rewrites the
// slots' positions (gathered from the shared vertex positions) and colours of the present faces.

// Index entries of faces [0, F): two triangles over slots 4f … 4f+3.
export function faceSlotIndices(F) {
  const index = new Uint32Array(6 * F);
  for (let f = 0, j = 0; f < F; f++, j += 6) {
    const s = 4 * f;
    index[j] = s, index[j + 1] = s + 1, index[j + 2] = s + 2;
    index[j + 3] = s, index[j + 4] = s + 2, index[j + 5] = s + 3;
  }
  return index;
}

// Slot positions of faces [0, F) from the vertex positions (3 per vertex).
export function gatherSlotPositions(corners, F, positions, out) {
  for (let f = 0; f < F; f++) {
    const c = 4 * f;
    for (let k = 0; k < 4; k++) {
      let v = corners[c + k];
      if (v < 0) v = corners[c];
      const i = 3 * v, o = 3 * (c + k);
      out[o] = positions[i], out[o + 1] = positions[i + 1], out[o + 2] = positions[i + 2];
    }
  }
}

// Slot colours of faces [0, F): face f's four slots take the colour of values[f].
export function fillSlotColours(fringe, values, F, out) {
  const rgb = [0, 0, 0];
  for (let f = 0; f < F; f++) {
    fringe.colour(values[f], rgb, 0);
    for (let k = 0, o = 12 * f; k < 4; k++, o += 3) (out[o] = rgb[0]), (out[o + 1] = rgb[1]), (out[o + 2] = rgb[2]);
  }
}
