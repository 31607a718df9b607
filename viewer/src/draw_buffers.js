// The page's draw buffers (viewer.js): positions and colours per vertex, triangle and edge
// index entries per face (fixed slots, draw_indices.js), a scalar per vertex. Sized for the
// loaded mesh and grown by 4× (up to the whole mesh) as it refines, so that the first picture
// uploads the base mesh's size, not the whole mesh's. Growing copies what is in, and the next
// render uploads the new arrays.
import * as THREE from 'three';

// Grows `buffers` ({positions, colours, triIndex, edgeIndex, scratch}, null at first) to hold at
// least `vertices` and `faces` of a mesh of `head`'s size, and sets them on the geometries;
// `room` ({vertices, faces}) is updated. Returns the new buffers, or null if they had room.
// `expected`: the vertices the page means to load (?vertices=N or the memory budget's, with the
// chunk that crosses them, Infinity once it asks for more): growing by 4× stops there, or at
// what is needed when the chunk that crossed it was longer (1.7 M of a 5 M model took room for
// 3.9 M before: arrays, and their copies on the GPU).
// The first call (no room yet) may ask for more than it needs (`firstVertices`, `firstFaces`), as
// far as expected.
export function growDrawBuffers(buffers, room, vertices, faces, head, geometry, edgeGeometry, expected = Infinity,
  firstVertices = vertices, firstFaces = faces) {
  if (vertices <= room.vertices && faces <= room.faces) return null;
  // Faces in proportion, with a quarter more (a coarse level has more faces a vertex).
  const expectedFaces = expected === Infinity ? Infinity : Math.ceil((1.25 * expected * head.faceCount) / head.vertexCount);
  const grow = (need, had, all, cap, first) => Math.min(all, Math.max(need, Math.min(had ? 4 * had : first, cap)));
  const V = vertices <= room.vertices ? room.vertices : grow(vertices, room.vertices, head.vertexCount, expected, firstVertices);
  const F = faces <= room.faces ? room.faces : grow(faces, room.faces, head.faceCount, expectedFaces, firstFaces);
  const grown = (old, Type, n) => {
    const a = new Type(n);
    if (old) a.set(old.subarray(0, Math.min(old.length, n)));
    return a;
  };
  const b = {
    positions: grown(buffers.positions, Float32Array, 3 * V),
    colours: grown(buffers.colours, Float32Array, 3 * V),
    triIndex: grown(buffers.triIndex, Uint32Array, 6 * F),
    edgeIndex: grown(buffers.edgeIndex, Uint32Array, 8 * F),
    scratch: grown(buffers.scratch, Float32Array, V),
  };
  Object.assign(room, { vertices: V, faces: F });
  geometry.dispose();  // frees the GPU buffers; the next render uploads the new arrays
  edgeGeometry.dispose();
  const dynamic = (array, size) => new THREE.BufferAttribute(array, size).setUsage(THREE.DynamicDrawUsage);
  const position = dynamic(b.positions, 3);
  geometry.setAttribute('position', position);
  const colour = dynamic(b.colours, 3);
  geometry.setAttribute('color', colour);
  geometry.setIndex(dynamic(b.triIndex, 1));
  edgeGeometry.setAttribute('position', position);  // shared: one upload serves both
  edgeGeometry.setAttribute('color', colour);  // the edges' colours follow the faces' (edge_lines.js)
  edgeGeometry.setIndex(dynamic(b.edgeIndex, 1));
  return b;
}

// After a change of level to F faces: the draw ranges, and the index entries [lo, hi) of the
// faces that changed (`changed`, from updateIndices; null: none) go up at the next render.
export function uploadIndices(geometry, edgeGeometry, F, changed) {
  geometry.setDrawRange(0, 6 * F);
  edgeGeometry.setDrawRange(0, 8 * F);
  if (!changed) return;
  const [lo, hi] = changed;
  for (const [g, per] of [[geometry, 6], [edgeGeometry, 8]]) {
    g.index.addUpdateRange(per * lo, per * (hi - lo));
    g.index.needsUpdate = true;
  }
}

// Compiles the shaders of `objects` (their materials) at start-up, on a one-triangle geometry
// that their real geometry replaces later.
export function compileShaders(renderer, scene, camera, objects) {
  for (const { geometry } of objects) {
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(9), 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(9), 3));
    geometry.setIndex([0, 1, 2]);
  }
  // Drawn once (a degenerate triangle): a program's first use waits for its link, which a
  // software renderer takes most of a second for, and the canvas's buffers are made.
  scene.add(...objects);
  renderer.render(scene, camera);
  scene.remove(...objects);
}
