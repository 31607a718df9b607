// The two decoders on the same request, byte for byte (docs/viewer.md "Selective refinement",
// "Output order"): `dynpm extract M.dpm --step T --refine … --elsewhere … -o out.obj` against the
// OBJ body made here from SelectiveNavigator.activeMesh() (obj_text.mjs writes what
// src/io/obj.cpp writes), on CalculiX crash boxes built lossless. A request without targets is a
// level, which `extract --vertices N` gives in the same order.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { test } from 'node:test';

import { elsewhereLevel, parseElsewhere, parseRequest, requestedSplits, wantedSet } from '../src/dpm/refine_targets.js';
import { SelectiveNavigator } from '../src/dpm/selective_navigator.js';
import { SplitDependencies } from '../src/dpm/split_dependencies.js';
import { ViewWorker, viewRequest } from '../src/moved_spheres.js';
import { objBody, withoutComments } from './obj_text.mjs';
import { cli, crashbox, crashboxDpm } from './selective_fixture.mjs';

const out = join(process.env.DYNPM_TEST_OUT ?? tmpdir(), 'refine-conformance');
mkdirSync(out, { recursive: true });

const models = new Map();
function model(name) {
  if (!models.has(name)) {
    const mesh = crashbox(name);
    models.set(name, { mesh, deps: new SplitDependencies(mesh).update(), file: crashboxDpm(name) });
  }
  return models.get(name);
}

// The OBJ body dpm.js gives for a request at whole step t: through requestedSplits() and the
// navigator's closure, or (`page`) as the page moves its front, through wantedSet() with the
// view requests' splits `views` made elsewhere (its spheres worker).
function jsObj({ mesh, deps }, requests, elsewhere, t, { page = false, views = null } = {}) {
  const nav = new SelectiveNavigator(mesh, deps);
  const level = elsewhereLevel(mesh, parseElsewhere(elsewhere));
  const wanted = page ? wantedSet(mesh, deps, requests, t, level, views) : nav.wanted(level, requestedSplits(mesh, deps, requests, t, level));
  nav.setTarget(wanted, level);
  const { vertices, faces, faceIds } = nav.activeMesh();
  const all = mesh.positionsAt(t, mesh.head.vertexCount, new Float32Array(3 * mesh.head.vertexCount));
  const positions = new Float32Array(3 * vertices.length);
  vertices.forEach((v, k) => positions.set(all.subarray(3 * v, 3 * v + 3), 3 * k));
  return objBody(positions, faces, Array.from(faceIds, (f) => mesh.partId[f]));
}

// The view requests' splits as the page has them from its worker (moved_spheres.js): the
// request and the answer cloned as postMessage clones them.
function viewSplitsFromWorker({ mesh, deps }, requests, t) {
  const views = requests.map((r) => parseRequest(r)).filter((r) => r.kind === 'view');
  const { message, transfer } = viewRequest(mesh, deps.derived, t, views, true);
  const { answer, transfer: back } = new ViewWorker().answer(structuredClone(message, { transfer }));
  return { splits: structuredClone(answer, { transfer: back }).splits };
}

function cliObj({ file }, args, name) {
  const path = join(out, name);
  execFileSync(cli, ['extract', file, ...args, '-o', path], { stdio: 'pipe' });
  return withoutComments(readFileSync(path, 'utf8'));
}

test('a level (no targets): extract --vertices N gives the same bytes (the part group line too)', () => {
  for (const [name, steps] of [['crashbox-mixed-5k', [0, 20, 40]], ['crashbox-fields', [0, 14]]]) {
  const m = model(name);
  const h = m.mesh.head;
  for (const n of [h.baseVertexCount, Math.round(0.37 * h.vertexCount), h.vertexCount - 1])
    for (const t of steps) {
      const js = jsObj(m, [], String(n), t);
      assert.ok(js.split('\n').length > n, 'the body has the vertices and faces');
      assert.equal(cliObj(m, ['--vertices', String(n), '--step', String(t)], `${name}_level_${n}_${t}.obj`), js, `${name}: ${n} vertices at step ${t}`);
    }
  }
});

const REQUESTS = [
  ['crashbox-mixed-5k', ['box:-40,-60,150,10,60,260'], '5%', [0, 20, 40]],
  ['crashbox-mixed-5k', ['sphere:0,0,220,25', 'moved:>20'], '2000', [10, 40]],
  ['crashbox-mixed-5k', ['part:0'], 'error:1', [0]],
  ['crashbox-fields', ['field:PEEQ>0.05'], '5%', [4, 14]],
  ['crashbox-fields', ['field:S_MISES<1', 'box:-50,-40,80,0,40,170'], '20%', [0, 14]],
  // A camera (docs/selective.md "View-dependent"): spheres, frustum, screen error, and the
  // budget's order by decreasing error, the same on both sides (both budgets bind under the
  // default rule, the face creators: 1872 → 1200 vertices, 3655 → 3406).
  ['crashbox-mixed-5k', ['view:EYE=150,40,300;AT=0,0,180;UP=0,0,1;FOV=35;W=900;H=700;PX=1'], '5%', [0, 40]],
  ['crashbox-mixed-5k', ['view:EYE=20,10,330;AT=0,0,150;UP=0,1,0;FOV=50;H=1080;PX=0.5;BUDGET=1200'], '2%', [20]],
  ['crashbox-fields', ['field:PEEQ>0.05', 'view:EYE=-120,0,140;AT=0,0,140;FOV=35;W=1600;H=900;PX=0.2;BUDGET=3400'], '5%', [14]],
];

for (const [name, requests, elsewhere, steps] of REQUESTS)
  test(`${name}: ${requests.join(' ')} --elsewhere ${elsewhere}: the same bytes as extract --refine`, () => {
    const m = model(name);
    for (const t of steps) {
      const args = [...requests.flatMap((r) => ['--refine', r]), '--elsewhere', elsewhere, '--step', String(t)];
      const file = `${name}_${requests.join('_').replace(/[^\w.-]/g, '_')}_${t}.obj`;
      const cpp = cliObj(m, args, file);
      assert.equal(cpp, jsObj(m, requests, elsewhere, t), `step ${t}`);
      // As the page does it: closed once (wantedSet()), and a view's splits from its worker
      // (the spheres and the screen errors made there) give the same bytes.
      assert.equal(cpp, jsObj(m, requests, elsewhere, t, { page: true }), `step ${t}, closed once`);
      if (requests.some((r) => r.startsWith('view:')))
        assert.equal(cpp, jsObj(m, requests, elsewhere, t, { page: true, views: viewSplitsFromWorker(m, requests, t) }), `step ${t}, the worker's view splits`);
    }
  });
