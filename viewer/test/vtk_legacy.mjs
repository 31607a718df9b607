// A reader of the legacy VTK files `dynpm extract` writes (src/io/vtk.cpp), ASCII or BINARY
// (big-endian, as the legacy format stores numbers): POINTS, POLYGONS, and the SCALARS arrays of
// POINT_DATA and CELL_DATA by name. For the golden test only; not a general VTK reader.

const SIZES = { float: 4, double: 8, int: 4 };

export function readVtkLegacy(buffer) {
  const bytes = new Uint8Array(buffer.buffer ?? buffer, buffer.byteOffset ?? 0, buffer.length);
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let at = 0;
  const line = () => {
    let end = bytes.indexOf(10, at);
    if (end < 0) end = bytes.length;
    const text = new TextDecoder().decode(bytes.subarray(at, end)).trim();
    at = end + 1;
    return text;
  };
  line(), line();
  const binary = line() === 'BINARY';
  let tokens = [];  // ASCII numbers not consumed yet
  const numbers = (n, type) => {
    const out = new Float64Array(n);
    if (binary) {
      for (let i = 0; i < n; i++, at += SIZES[type])
        out[i] = type === 'float' ? view.getFloat32(at) : type === 'double' ? view.getFloat64(at) : view.getInt32(at);
      if (bytes[at] === 10) at++;
      return out;
    }
    for (let i = 0; i < n; i++) {
      while (!tokens.length) tokens = line().split(/\s+/).filter(Boolean).reverse();
      // A float written as text is its shortest round-trip form: read it back as that float.
      out[i] = type === 'float' ? Math.fround(Number(tokens.pop())) : Number(tokens.pop());
    }
    return out;
  };
  const result = { points: null, polygons: [], pointData: {}, cellData: {} };
  let data = null;
  while (at < bytes.length) {
    const w = line().split(/\s+/);
    if (w[0] === 'POINTS') result.points = numbers(3 * Number(w[1]), w[2]);
    else if (w[0] === 'POLYGONS') {
      const flat = numbers(Number(w[2]), 'int');
      for (let i = 0; i < flat.length; i += flat[i] + 1) result.polygons.push(Array.from(flat.subarray(i + 1, i + 1 + flat[i])));
    } else if (w[0] === 'POINT_DATA') data = { map: result.pointData, n: Number(w[1]) };
    else if (w[0] === 'CELL_DATA') data = { map: result.cellData, n: Number(w[1]) };
    else if (w[0] === 'SCALARS') {
      line();  // LOOKUP_TABLE default
      data.map[w[1]] = { type: w[2], values: numbers(data.n, w[2]) };
    }
  }
  return result;
}
