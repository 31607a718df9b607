// The OBJ body `dynpm` writes (src/io/obj.cpp write_obj()), made here from dpm.js's arrays, so
// that a test can compare the two decoders' outputs byte for byte: `v x y z` with each float32
// as std::to_chars writes it (the shortest digits that read back to the same float, fixed or
// scientific, whichever is shorter, fixed on a tie), `g part_N` before each run of faces of a
// part when the model has other parts than 0, `f a b c [d]` 1-based. The '#' comments are left
// out (what they say differs between commands).

// std::to_chars(float) of x (a float32 value).
export function floatText(x) {
  if (x === 0) return Object.is(x, -0) ? '-0' : '0';
  let p = 1;
  while (Math.fround(Number(x.toPrecision(p))) !== x) p++;
  let [mantissa, exp] = x.toExponential(p - 1).split('e');
  // A tie (the exact value ends in 5 right after the p digits) goes to the even digit, as C++;
  // JavaScript rounds it away from zero.
  const exact = x.toExponential(Math.min(100, p + 60)).split('e')[0].replace(/[-.]/g, '');
  if (/^50*$/.test(exact.slice(p)) && Number(mantissa.at(-1)) % 2 === 1) {
    const down = exact.slice(0, p);
    mantissa = (x < 0 ? '-' : '') + down[0] + (p > 1 ? `.${down.slice(1)}` : '');
    if (mantissa.replace(/[-.]/g, '').length !== p) throw new Error(`floatText(${x}): a carry`);
  }
  const negative = mantissa.startsWith('-');
  const digits = mantissa.replace(/[-.]/g, '');
  const e = Number(exp);
  const sign = negative ? '-' : '';
  const scientific = `${sign}${digits[0]}${digits.length > 1 ? `.${digits.slice(1)}` : ''}e${e < 0 ? '-' : '+'}${String(Math.abs(e)).padStart(2, '0')}`;
  let fixed;
  if (e >= digits.length - 1) fixed = BigInt(x).toString();  // an integer: its exact digits, as C++
  else if (e >= 0) fixed = `${sign}${digits.slice(0, e + 1)}.${digits.slice(e + 1)}`;
  else fixed = `${sign}0.${'0'.repeat(-e - 1)}${digits}`;
  return fixed.length <= scientific.length ? fixed : scientific;
}

// positions: Float32Array, 3 per vertex in the output's order; faces: 4 slots per face (−1 in
// slot 3 of a triangle), output numbering; partIds: per face.
export function objBody(positions, faces, partIds) {
  const lines = [];
  for (let i = 0; i + 2 < positions.length; i += 3) lines.push(`v ${floatText(positions[i])} ${floatText(positions[i + 1])} ${floatText(positions[i + 2])}`);
  const groups = new Set(partIds).size > 1 || (partIds.length > 0 && partIds[0] !== 0);
  let part = null;
  for (let f = 0; f < partIds.length; f++) {
    if (groups && partIds[f] !== part) lines.push(`g part_${(part = partIds[f])}`);
    const c = Array.from(faces.subarray(4 * f, 4 * f + 4)).filter((v) => v >= 0);
    lines.push(`f ${c.map((v) => v + 1).join(' ')}`);
  }
  return lines.join('\n') + '\n';
}

// What a written OBJ holds beyond its comments.
export const withoutComments = (text) => text.split('\n').filter((l) => !l.startsWith('#')).join('\n');
