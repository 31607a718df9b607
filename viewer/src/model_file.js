// Which file the page shows, and its name: `dpm.json` (written by `dynpm view` and --export),
// else model.dpm; `?model=` (the catalogue's links, `dynpm serve`) or `?file=` overrides both,
// but only with a file of the page's own origin.
import { HEAD_FLAG_LOSSLESS } from './dpm/progressive_mesh.js';
import { withChunkMargin } from './dpm/file.js';
import { positionBytes } from './dpm/step_positions.js';

export async function modelFile(params) {
  const model = params.get('model');
  if (model) {
    const url = sameOrigin('model', model);
    return { file: model, name: decodeURIComponent(url.pathname.split('/').pop()) };
  }
  let file = 'model.dpm';
  let name = file;
  let settings = null;  // dpm.json, which may name a second model (compare_view.js)
  try {
    const config = await fetch('dpm.json');
    if (config.ok) {
      const c = (settings = await config.json());
      file = c.file ?? file;
      name = c.name ?? file;
    }
  } catch {
    // No dpm.json (a folder served by hand): the default name.
  }
  const query = params.get('file');
  if (query) {
    sameOrigin('file', query);
    file = name = query;
  }
  return { file, name, config: settings };
}

// ?file= and ?model= name a file of this server only: a link must not make the page fetch from
// (or announce itself to) another origin. The CSP's connect-src 'self' refuses it as well.
function sameOrigin(param, value) {
  const url = new URL(value, location.href);
  if (url.origin !== location.origin) throw new Error(`?${param}=${value}: not on this server (${location.origin})`);
  return url;
}

// ?vertices=N: the page fetches (by ranges) only the levels up to N vertices at first.
export function wantedVertices(params) {
  const n = Number(params.get('vertices') ?? Infinity);
  return n >= 0 ? n : Infinity;
}

// Without ?vertices=N the page loads at first the levels whose arrays fit ?memory=MiB (default
// 1 GiB): a vertex's positions at every step take positionBytes() (about 2 bytes a step, packed:
// dpm/step_positions.js; 12 in a lossless file), each field's value 2 a step (4 in a lossless
// file; dpm/fields.js valueArrayType(): a field quantized finer than 1/16383 of its range, which
// HEAD does not tell, also takes 4; a face field is counted as a node field: a quad mesh has
// about as many faces as vertices), and what does not depend on the steps STEP_FREE_BYTES. The
// slider's far end asks for the rest.
const DEFAULT_MEMORY_MIB = 1024;
// A loaded vertex's share of the arrays that do not depend on the steps: on the 1 M × 25 crash
// box's page 184 MiB (draw buffers 79, split records 45, navigator 34, ids 26: docs/viewer.md
// "Memory"), about 193 bytes a vertex.
const STEP_FREE_BYTES = 200;
export function memoryBudget(params) {
  const mib = Number(params.get('memory') ?? DEFAULT_MEMORY_MIB);
  return (mib > 0 ? mib : DEFAULT_MEMORY_MIB) * 2 ** 20;
}
// `later`: the bytes a vertex's packed steps and escaped positions take, as measured on the
// vertices loaded so far (StepPositions.laterBytes()), instead of positionBytes()'s allowance.
export function budgetedVertices(head, budget, later = undefined) {
  const perValue = head.flags & HEAD_FLAG_LOSSLESS ? 4 : 2;
  const steps = positionBytes(head.stepCount, (head.flags & HEAD_FLAG_LOSSLESS) !== 0, later) + perValue * head.fieldCount * head.stepCount;
  const perVertex = steps + STEP_FREE_BYTES;
  return Math.max(head.baseVertexCount, Math.floor(budget / perVertex));
}

// What a worker that means to load `vertices` (?vertices=N; Infinity: what `memory` holds) has
// loaded when it pauses, with the chunk that crosses them; Infinity if it loads the whole model.
// The draw buffers grow to it, not past it.
export function verticesBeforePause(head, vertices, memory) {
  const n = vertices < Infinity ? vertices : budgetedVertices(head, memory);
  return n < head.vertexCount ? withChunkMargin(n) : Infinity;
}

// The budget's vertex count again once an eighth of `target` is loaded, with the packed steps
// and escaped positions measured on the loaded vertices (StepPositions.laterBytes()) instead of
// the allowance: a model whose motion changes much from step to step packs into more bits and
// escapes more. Lowered, never raised (the page's draw buffers took room for the first count).
// The decode worker asks after each chunk.
export function remeasuredBudget(head, budget, target, positions, loaded) {
  if (8 * loaded < target) return target;
  return Math.min(target, budgetedVertices(head, budget, positions.laterBytes() / loaded));
}
