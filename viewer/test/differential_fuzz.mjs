// Differential fuzzing of the two .dpm decoders: mutants of the corpus files, each changed in one
// or two chunks' payloads (a zstd frame inflated first and stored plain after, the sizes and the
// CRC-32 made right again, so that the payload checks are reached), several changes at once; the
// C++ reader (tests/dpm_verdicts, one process per round) and dpm.js must give every mutant the
// same verdict (verdicts.mjs: the same counts, fields, parts and selective meshes, or a refusal
// at the same byte). Run by hand for a while, and briefly by CTest with a fixed seed
// (docs/RELIABILITY.md "Differential fuzzing"):
//   node test/differential_fuzz.mjs --tool build/tests/dpm_verdicts [--seconds S | --rounds N]
//     [--seed K] [--batch B] [--out DIR] [FOLDER...]
// FOLDER: more files to mutate (every file in it, e.g. a fuzz_dpm corpus) besides fuzz/corpus/dpm,
// fuzz/regressions/dpm and tests/bad; three mutants in four are of files the C++ reader accepts.
// A mutant that gets different verdicts is kept in DIR and the script exits 1.
import { mkdirSync, readdirSync, readFileSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { parseArgs } from 'node:util';

import { chunkBytes } from './fields_fixture.mjs';
import { chunksOf, concat, jsVerdictOrCrash, same, toolVerdicts } from './verdicts.mjs';

const ROOT = new URL('../../', import.meta.url).pathname;
const { values: options, positionals: folders } = parseArgs({
  allowPositionals: true,
  options: {
    tool: { type: 'string' },
    seconds: { type: 'string', default: '0' },
    rounds: { type: 'string', default: '0' },
    seed: { type: 'string', default: '1' },
    batch: { type: 'string', default: '200' },
    out: { type: 'string', default: join(tmpdir(), 'dynpm-differential') },
  },
});
if (!options.tool) throw new Error('--tool PATH (tests/dpm_verdicts) is needed');

// mulberry32: a small seeded generator, so that a run is repeated exactly by its seed.
function generator(seed) {
  let a = seed >>> 0;
  return (n) => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = Math.imul(a ^ (a >>> 15), 1 | a);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return (((t ^ (t >>> 14)) >>> 0) / 4294967296) * n | 0;
  };
}

function filesIn(folder) {
  return readdirSync(folder).sort().map((f) => join(folder, f))
    .filter((path) => statSync(path).isFile() && !path.endsWith('.md') && !path.endsWith('.txt'))
    .map((path) => ({ name: path, bytes: new Uint8Array(readFileSync(path)) }))
    .filter((f) => f.bytes.length >= 12);
}

// One change to a payload: a bit, a byte, bytes inserted, cut or copied, a u32 made small.
function changed(payload, random) {
  const p = Array.from(payload);
  const at = random(p.length + 1);
  switch (random(6)) {
    case 0: if (at < p.length) p[at] ^= 1 << random(8); break;
    case 1: if (at < p.length) p[at] = [0, 0xff, random(256)][random(3)]; break;
    case 2: p.splice(at, 0, ...Array.from({ length: 1 + random(4) }, () => random(256))); break;
    case 3: p.splice(at, 1 + random(8)); break;
    case 4: {
      const from = random(p.length + 1), length = 1 + random(16);
      p.splice(at, 0, ...p.slice(from, from + length));
      break;
    }
    default: {
      const value = [0, 1, 2, random(256), 0xffffffff][random(5)];
      for (let k = 0; k < 4 && at + k < p.length; k++) p[at + k] = (value >>> (8 * k)) & 0xff;
    }
  }
  return Uint8Array.from(p);
}

function mutant(file, random) {
  const magic = file.bytes.subarray(0, 12);
  let chunks;
  try {
    chunks = chunksOf(file.bytes);  // a frame that does not inflate: the file is left out
  } catch {
    return null;
  }
  if (chunks.length === 0) return null;
  const edited = new Set([random(chunks.length), random(4) === 0 ? random(chunks.length) : -1]);
  const parts = chunks.map((c, k) => {
    let payload = c.payload;
    if (edited.has(k)) for (let n = 1 + random(4); n > 0; n--) payload = changed(payload, random);
    return chunkBytes(c.tag, payload);
  });
  return concat([magic, ...parts]);
}

const corpus = ['fuzz/corpus/dpm', 'fuzz/regressions/dpm', 'tests/bad']
  .flatMap((f) => filesIn(join(ROOT, f)))
  .concat(folders.flatMap(filesIn));
// Three mutants in four come from a file the C++ reader accepts (most of a fuzzer's corpus is
// refused files), the rest from any.
const probes = join(options.out, 'probe');
mkdirSync(probes, { recursive: true });
const probePaths = corpus.map((f, k) => (writeFileSync(join(probes, `${k}.dpm`), f.bytes), join(probes, `${k}.dpm`)));
const sources = toolVerdicts(options.tool, probePaths);  // one process for the whole corpus
rmSync(probes, { recursive: true, force: true });
const acceptedSources = corpus.filter((f, k) => sources[k].counts);
const random = generator(Number(options.seed));
const batch = Number(options.batch), rounds = Number(options.rounds);
const deadline = Date.now() + 1000 * Number(options.seconds);
const work = join(options.out, 'round');
let tried = 0, accepted = 0, differences = 0;
for (let round = 0; rounds ? round < rounds : Date.now() < deadline; round++) {
  rmSync(work, { recursive: true, force: true });
  mkdirSync(work, { recursive: true });
  const files = [];
  while (files.length < batch) {
    const pool = random(4) && acceptedSources.length ? acceptedSources : corpus;
    const source = pool[random(pool.length)];
    const bytes = mutant(source, random);
    if (bytes) files.push({ name: `${source.name} (round ${round}, mutant ${files.length})`, bytes, path: join(work, `${files.length}.dpm`) });
  }
  for (const f of files) writeFileSync(f.path, f.bytes);
  const verdicts = toolVerdicts(options.tool, files.map((f) => f.path));
  files.forEach((f, k) => {
    const js = jsVerdictOrCrash(f.bytes);
    if (verdicts[k].counts) accepted++;
    if (same(verdicts[k], js)) return;
    differences++;
    const kept = join(options.out, `different-${Number(options.seed)}-${round}-${k}.dpm`);
    writeFileSync(kept, f.bytes);
    console.log(`${f.name} → ${kept}\n  C++: ${JSON.stringify(verdicts[k])}\n  JS:  ${JSON.stringify(js)}`);
  });
  tried += files.length;
}
rmSync(work, { recursive: true, force: true });
console.log(`${tried} mutants of ${corpus.length} files (${acceptedSources.length} accepted), ` +
  `${accepted} mutants accepted by both, ${differences} with different verdicts`);
process.exit(differences ? 1 : 0);
