// The variants of a family file (docs/FORMAT.md "Variants: VARI"), with the checks the C++ reader
// makes (src/progressive/variants_chunk.cpp), in the same order, and one variant's view of the
// decoded mesh. mesh.variants: [{ name, source, times: Float64Array, steps: Uint32Array }].
import { cleanPartName } from './parts.js';

// The smallest variant: a name and a source of one byte, one step (time and stored step).
const MIN_VARIANT_BYTES = 2 + 1 + 2 + 1 + 4 + 8 + 4;

function text(r) {
  const n = r.u16();
  r.need(n);
  const bytes = r.bytes.subarray(r.pos, r.pos + n);
  r.pos += n;
  return bytes;
}

// VARI: fills mesh.variants (HEAD's step count bounds the stored steps).
export function parseVariants(r, mesh) {
  const count = r.u32();
  if (count === 0 || count > Math.floor(r.remaining() / MIN_VARIANT_BYTES))
    r.fail(`the variant count ${count} is not valid`);
  const stored = mesh.head.stepCount;
  const used = new Uint8Array(stored);
  const variants = [];
  for (let k = 0; k < count; k++) {
    const name = cleanPartName(text(r));
    const source = cleanPartName(text(r));
    const steps = r.u32();
    if (name === null || source === null)
      r.fail(`variant ${k}: its name and source are not 1 to 255 bytes of UTF-8 without control characters or blanks at their ends`);
    const earlier = variants.findIndex((v) => v.name === name);
    if (earlier >= 0) r.fail(`variant ${k}: the name is variant ${earlier}'s`);
    if (steps === 0 || steps > Math.floor(r.remaining() / 12)) r.fail(`variant ${k}: the step count is not valid`);
    const times = new Float64Array(steps);
    for (let t = 0; t < steps; t++) times[t] = r.f64();
    if (!times.every(Number.isFinite)) r.fail(`variant ${k}: a step's time is not finite`);
    const map = new Uint32Array(steps);
    for (let t = 0; t < steps; t++) {
      map[t] = r.u32();
      if (map[t] >= stored) r.fail(`variant ${k}: stored step ${map[t]} is past the file's ${stored} steps`);
      used[map[t]] = 1;
    }
    variants.push({ name, source, times, steps: map });
  }
  if (r.remaining() !== 0) r.fail(`${r.remaining()} bytes left over at the end of VARI`);
  const unused = used.indexOf(0);
  if (unused >= 0) r.fail(`stored step ${unused} belongs to no variant`);
  mesh.variants = variants;
}

// The variant `which` names (its name, or its index from 0 as a number or a string of digits),
// or an Error listing the variants.
export function findVariant(mesh, which) {
  const list = mesh.variants ?? [];
  const byName = list.findIndex((v) => v.name === String(which));
  if (byName >= 0) return byName;
  if (/^[0-9]+$/.test(String(which)) && Number(which) < list.length) return Number(which);
  const names = list.map((v, k) => `${k} ${v.name}`).join(', ');
  throw new Error(list.length ? `no variant '${which}' (the variants: ${names})` : 'the model is not a family file');
}

// The mesh as variant `index` shows it: an object whose prototype is the decoded mesh (so every
// split the decoder adds is seen), with the variant's steps — its positions and field values are
// the stored steps' arrays, shared, not copied — its times and key steps. The C++ reader's
// select_variant() (src/progressive/variants_chunk.cpp).
export function variantView(mesh, index) {
  const v = mesh.variants[index];
  const view = Object.create(mesh);
  const steps = Array.from(v.steps);
  // Positions through the stored steps; field values read through, as a step's array is made
  // anew when it needs more room (makeRoom()).
  view.storedStep = (t) => steps[t];
  view.fields = mesh.fields.map((f) => Object.create(f, { q: { get: () => steps.map((s) => f.q[s]) } }));
  const keySteps = [];
  steps.forEach((s, t) => mesh.head.keySteps.includes(s) && keySteps.push(t));
  view.head = { ...mesh.head, stepCount: steps.length, times: v.times, keySteps };
  view.variant = { index, name: v.name, count: mesh.variants.length };
  return view;
}
