// The base mesh as the page first draws it, straight from BASE: what viewer.js reads of a
// Navigator (counts, errors, corners, the faces to write), without the Navigator's arrays for
// every face of the whole mesh, which take long to allocate and fill for a large model. The
// page draws this at once and makes the Navigator in a later task (docs/viewer.md "Loading").
export class BaseLevel {
  constructor(mesh) {
    const h = mesh.head;
    this.mesh = mesh;
    this.corners = mesh.baseCorners;  // 4 slots per base face, as Navigator.corners
    this.vertexCount = h.baseVertexCount;
    this.faceCount = h.baseFaceCount;
    this.quadCount = mesh.baseDegree.reduce((n, d) => n + (d === 4 ? 1 : 0), 0);
    this.triangleCount = this.faceCount - this.quadCount;
    this.error = h.baseError;
    this.level = 0;
    this.dirty = Uint32Array.from({ length: this.faceCount }, (_, f) => f);
  }
  fieldError(f) {
    return this.mesh.fields[f].levelError(0);
  }
  // Every base face once, then none.
  takeDirty() {
    const dirty = this.dirty;
    this.dirty = new Uint32Array(0);
    return dirty;
  }
  face(f) {
    return Array.from(this.corners.subarray(4 * f, 4 * f + (this.corners[4 * f + 3] < 0 ? 3 : 4)));
  }
  setVertexCount() {
    return 0;
  }
}
