// The parts' names of a .dpm (docs/FORMAT.md "Part names: PART"), with the checks the C++ reader
// makes (src/progressive/part_names_chunk.cpp), in the same order: names are untrusted text the
// page shows (as text nodes only). mesh.partNames: a Map from part id to name, ascending id.

const MAX_NAME_BYTES = 255;
// The smallest entry: an id and a name of one byte.
const MIN_ENTRY_BYTES = 4 + 2 + 1;
// C0, DEL and C1 control characters.
const CONTROL = /[\u0000-\u001f\u007f-\u009f]/u;

// A name as FORMAT.md allows it, or null: 1 … 255 bytes of UTF-8 (no overlong forms, no
// surrogates), no control character, no space at either end.
export function cleanPartName(bytes) {
  if (bytes.length === 0 || bytes.length > MAX_NAME_BYTES) return null;
  if (bytes[0] === 0x20 || bytes[bytes.length - 1] === 0x20) return null;
  let name;
  try {
    name = new TextDecoder('utf-8', { fatal: true, ignoreBOM: true }).decode(bytes);
  } catch {
    return null;
  }
  return CONTROL.test(name) ? null : name;
}

// PART: fills mesh.partNames.
export function parsePartNames(r, mesh) {
  const count = r.u32();
  if (count === 0 || count > Math.floor(r.remaining() / MIN_ENTRY_BYTES))
    r.fail(`the part count ${count} is not valid`);
  const names = new Map();
  let last = -Infinity;
  for (let k = 0; k < count; k++) {
    const id = r.i32();
    const n = r.u16();
    r.need(n);
    const bytes = r.bytes.subarray(r.pos, r.pos + n);
    r.pos += n;
    if (id <= last) r.fail(`part ${id} is not after part ${last} (ascending ids)`);
    const name = cleanPartName(bytes);
    if (name === null) r.fail(`the name of part ${id} is not 1 to 255 bytes of UTF-8 without control characters or blanks at its ends`);
    names.set(id, name);
    last = id;
  }
  if (r.remaining() !== 0) r.fail(`${r.remaining()} bytes left over at the end of PART`);
  mesh.partNames = names;
}
