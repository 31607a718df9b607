// The split dependencies (dpm/split_dependencies.js) derived by the decode worker and moved to
// the page (docs/viewer.md "Dependencies from the worker"): deriving them replays every split,
// which on a crash box took the page's main thread a quarter of a second at the first refine.
// The worker derives them as the splits arrive and sends what a refinement reads — the CSR, the
// mesh the derived splits left, each face's last writer and creator — as typed arrays whose
// buffers are transferred. The page's copy is a snapshot: it does not derive further (the worker
// sends a newer one when more splits have come).
import { SplitDependencies } from './dpm/split_dependencies.js';

// Worker: the arrays a refinement reads, and the buffers to transfer. `last`: the worker derives
// no more, so its own arrays go (else copies, and it goes on deriving).
export function dependencyParts(deps, last = false) {
  const own = (a, n = a.length) => (last && n === a.length ? a : a.slice(0, n));
  const parts = {
    derived: deps.derived,
    maxCount: deps.maxCount,
    depStart: own(deps.depStart),
    deps: own(deps.deps.data, deps.deps.length),
    corners: own(deps.corners),
    lastWriter: own(deps.lastWriter),
    faceSplit: own(deps.faceSplit),
  };
  const transfer = [parts.depStart, parts.deps, parts.corners, parts.lastWriter, parts.faceSplit].map((a) => a.buffer);
  return { parts, transfer: [...new Set(transfer)].filter((b) => b instanceof ArrayBuffer) };
}

// Page: the dependencies over the page's mesh, derived as far as `parts.derived`.
export function movedDependencies(parts, mesh) {
  const deps = Object.create(SplitDependencies.prototype);
  const { deps: list, ...arrays } = parts;
  Object.assign(deps, arrays, { mesh, deps: { data: list, length: list.length } });
  deps.update = () => deps;  // a snapshot: the worker derives, the page never replays
  return deps;
}
