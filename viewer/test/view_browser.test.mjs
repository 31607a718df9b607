// The view's controls in Debian's headless Chromium (docs/viewer.md "States", "Orientation",
// "Deformation", "Images", "First moments", "Scripting API"): each through window.dynpm and
// through the visible control, on the multi-part model with named parts (the hat rail as six
// named Exodus blocks, scripts/sample/make_parts.py, 31 states, served throttled so that the
// first moments are seen) and on a one-state model (the sample's first frame: no time). The
// page's levels are compared with dpm.js run here; the edge colour rule is checked on every
// colour of the scales and every part colour the page gives.
//
// If Chromium cannot start, this fails: it never skips.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';
import * as THREE from 'three';

import { Navigator, readDpm } from '../src/dpm.js';
import { contrast, edgeColour } from '../src/edge_lines.js';
import { SCHEMES, schemeColour } from '../src/fringe.js';
import { upAxisOf } from '../src/orientation.js';
import { partColour } from '../src/part_view.js';
import { advance } from '../src/states.js';
import { openViewer, startServer } from './chromium.mjs';

const { DYNPM_CLI: cli, DYNPM_PARTS_DPM: dpm, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !dpm || !out) throw new Error('view_browser.test.mjs needs DYNPM_CLI, DYNPM_PARTS_DPM, DYNPM_TEST_OUT');
const dir = join(out, 'view-browser');
mkdirSync(dir, { recursive: true });

const servers = [];
let browser, page, url, mesh;
const consoleErrors = [];

before(async () => {
  ({ mesh } = readDpm(new Uint8Array(readFileSync(dpm)), dpm));
  assert.equal(mesh.partNames.size, 6, 'the model has six named parts');
  // About 6 s for the model: the first moments (loading screen, "…") last long enough to see.
  let server;
  ({ server, browser, page, url } = await openViewer(chromium, cli, dpm, { viewport: { width: 1100, height: 760 }, errors: consoleErrors,
    serverArgs: ['--throttle', '40'], ready: false, waitUntil: 'domcontentloaded' }));
  servers.push(server);
});

after(async () => {
  await browser?.close();
  for (const s of servers) s.kill('SIGTERM');
});

const api = (f, arg) => page.evaluate(f, arg);
const view = () => api(() => window.dynpm.view());
const snapshot = (p = page) => p.evaluate(() => window.dpmViewer.snapshot());
const difference = (a, b) => a.reduce((s, x, i) => s + Math.abs(x - b[i]), 0) / a.length;
const near = (a, b, eps = 1e-6) => a.every((x, i) => Math.abs(x - b[i]) <= eps);
const stepNow = async () => (await view()).step;
// The error a page-side call throws, as "Name: message" (null if none). Evaluated as a string:
// the page's CSP allows no eval of its own.
const thrown = (f) =>
  page.evaluate(`(() => { try { (${f.toString()})(); return null; } catch (e) { return e.name + ': ' + e.message; } })()`);

test('first moments: a loading screen and "…" until the model is loaded, then dynpm.ready', async () => {
  const early = await api(() => ({
    screen: !document.getElementById('loading-screen').hidden,
    text: document.getElementById('loading-screen').textContent,
    hasBase: Boolean(window.dpmViewer?.state().hasBase),
  }));
  assert.equal(early.hasBase, false, 'the test sees the page before its first picture');
  assert.equal(early.screen, true, 'the loading screen shows from the first paint');
  assert.match(early.text, /loading.*…/);
  await page.waitForFunction(() => window.dpmViewer?.state().hasBase, null, { timeout: 20000 });
  const base = await api(() => ({ screen: !document.getElementById('loading-screen').hidden, complete: window.dpmViewer.state().complete, stats: document.getElementById('stats').textContent }));
  assert.equal(base.screen, false, 'the loading screen goes with the first picture');
  assert.equal(base.complete, false, 'still loading');
  assert.match(base.stats, /…$/, 'the status line says it is still loading');
  await api(() => window.dynpm.ready.then(() => true));
  const s = await api(() => window.dpmViewer.state());
  assert.ok(s.complete && s.navigator && s.vertices === mesh.head.vertexCount, `ready when fully loaded: ${JSON.stringify(s)}`);
  assert.doesNotMatch(await page.locator('#stats').textContent(), /…/, 'the "…" ends when loading ends');
});

test('the error label gives its unit and what it measures', async () => {
  await api(() => window.dynpm.setLevel({ ratio: 0.05 }));
  const label = await page.locator('#resolution-label').textContent();
  assert.match(label, /error [\d.e+-]+ model units \([\d.e+-]+% of the box diagonal\): how far this level's surface may lie from the full mesh's, at any step/);
  await api(() => window.dynpm.setLevel({ ratio: 1 }));
});

test('setLevel by vertices, ratio and error: the levels dpm.js gives', async () => {
  const h = mesh.head;
  const nav = new Navigator(mesh);
  const byVertices = await api(() => window.dynpm.setLevel({ vertices: 1000 }));
  nav.setVertexCount(1000);
  assert.deepEqual(byVertices, { vertices: 1000, error: nav.error });
  assert.match(await page.locator('#stats').textContent(), /vertices 1,000 /);
  const byRatio = await api(() => window.dynpm.setLevel({ ratio: 0.25 }));
  assert.equal(byRatio.vertices, Math.round(0.25 * h.vertexCount));
  assert.equal((await api(() => window.dynpm.setLevel({ ratio: 0 }))).vertices, h.baseVertexCount, 'ratio 0: the base mesh');
  // {error: e}: the coarsest level whose error is ≤ e, e from a middle level.
  nav.setVertexCount(800);
  const e = nav.error;
  const byError = await api((e) => window.dynpm.setLevel({ error: e }), e);
  assert.ok(byError.error <= e, `${byError.error} ≤ ${e}`);
  assert.ok(byError.vertices <= 800);
  nav.setVertexCount(byError.vertices - 1);
  assert.ok(nav.error > e, 'one split coarser, the error is above e');
  assert.match(await thrown(() => window.dynpm.setLevel({})), /TypeError: setLevel: \{vertices\}, \{ratio\} or \{error\}/);
  assert.match(await thrown(() => window.dynpm.setLevel({ ratio: 2 })), /RangeError: ratio 2: from 0 to 1/);
  assert.equal((await api(() => window.dynpm.setLevel({ ratio: 1 }))).vertices, h.vertexCount);
});

test('states: setStep, first / previous / next / last buttons and keys, the slider snaps', async () => {
  const last = mesh.head.stepCount - 1;
  assert.equal(await api(() => window.dynpm.setStep(3)), 3);
  assert.equal(await page.locator('#time').inputValue(), '3');
  assert.match(await page.locator('#time-label').textContent(), /^step 3\.00 \/ 30/);
  const at = {};
  for (const t of [2, 2.5, 3]) {
    await api((t) => window.dynpm.setStep(t), t);
    at[t] = await snapshot();
  }
  assert.ok(difference(at[2], at[2.5]) > 0.05 && difference(at[2.5], at[3]) > 0.05, 'a fractional step interpolates');
  assert.match(await thrown(() => window.dynpm.setStep(31)), /RangeError: step 31: from 0 to 30/);
  assert.match(await thrown(() => window.dynpm.setStep(-1)), /RangeError/);
  // From 2.5 the next state is 3, the previous 2.
  await api(() => window.dynpm.setStep(2.5));
  await page.locator('#state-next').click();
  assert.equal(await stepNow(), 3);
  await page.locator('#state-prev').click();
  assert.equal(await stepNow(), 2);
  await page.locator('#state-last').click();
  assert.equal(await stepNow(), last);
  await page.locator('#state-next').click();
  assert.equal(await stepNow(), last, 'no state after the last');
  await page.locator('#state-first').click();
  assert.equal(await stepNow(), 0);
  // Keys, also with the time slider focused (its own arrow keys would move by its step).
  await page.locator('#state-first').focus();
  for (const [key, expected] of [['ArrowRight', 1], ['ArrowRight', 2], ['End', last], ['ArrowLeft', last - 1], ['Home', 0]]) {
    await page.keyboard.press(key);
    assert.equal(await stepNow(), expected, key);
  }
  await page.locator('#time').focus();
  await page.keyboard.press('ArrowRight');
  assert.equal(await stepNow(), 1, 'ArrowRight on the slider: the next state');
  // The slider snaps to states; with "between states" ticked it stops between them.
  const box = await page.locator('#time').boundingBox();
  const clickAt = async (x) => {
    await page.mouse.click(box.x + 8 + (box.width - 16) * x, box.y + box.height / 2);
    return stepNow();
  };
  for (const x of [0.31, 0.517, 0.74]) assert.ok(Number.isInteger(await clickAt(x)), `snapped at ${x}`);
  await page.locator('#between-states').check();
  const free = [];
  for (const x of [0.31, 0.517, 0.74]) free.push(await clickAt(x));
  assert.ok(free.some((t) => !Number.isInteger(t)), `between states: ${free}`);
  await page.locator('#between-states').uncheck();
});

test('playback: speed, once, loop and bounce (API and controls); a pause lands on a state', async () => {
  const last = mesh.head.stepCount - 1;
  // The pure rule first.
  assert.deepEqual(advance(29, 1, 10, 0.3, 30, 'once'), { t: 30, direction: 1, ended: true });
  assert.deepEqual(advance(29, 1, 10, 0.3, 30, 'loop'), { t: 2, direction: 1, ended: false });
  assert.deepEqual(advance(29, 1, 10, 0.3, 30, 'bounce'), { t: 28, direction: -1, ended: false });
  assert.deepEqual(advance(1, -1, 10, 0.3, 30, 'bounce'), { t: 2, direction: 1, ended: false });
  // Once at 4×: the 4-second run in about 1 s, ending on the last state.
  await api(() => window.dynpm.setStep(0));
  const start = Date.now();
  await api(() => window.dynpm.play({ speed: 4, mode: 'once' }));
  await page.waitForFunction(() => !window.dynpm.view().playing, null, { timeout: 20000 });
  const seconds = (Date.now() - start) / 1000;
  assert.equal(await stepNow(), last);
  assert.ok(seconds > 0.6 && seconds < 4, `once at 4× took ${seconds} s`);
  // Bounce and loop through the controls: time samples show the turn and the wrap. Sampled until
  // they do (or 20 s): on a loaded machine the frames, and so the playback, come slower.
  const sample = async (seen) => {
    const ts = [];
    for (let end = Date.now() + 20000; Date.now() < end && !seen(ts); ) ts.push(await stepNow()), await page.waitForTimeout(40);
    return ts;
  };
  const turnsBack = (ts) => {
    const peak = ts.indexOf(Math.max(...ts));
    return ts[peak] > last - 5 && ts.slice(peak).some((t) => t < ts[peak] - 3);
  };
  const wraps = (ts) => ts.some((t) => t < 10);
  await page.locator('#play-speed').selectOption('4');
  await page.locator('#play-mode').selectOption('bounce');
  await page.locator('#state-first').click();
  await page.locator('#play').click();
  const bounce = await sample(turnsBack);
  assert.ok(turnsBack(bounce), `bounce turns back: ${bounce.map((t) => t.toFixed(1))}`);
  assert.ok(bounce.every((t) => t >= 0 && t <= last));
  await page.locator('#play').click();
  assert.ok(Number.isInteger(await stepNow()), 'a pause lands on a state');
  await page.locator('#play-mode').selectOption('loop');
  await page.locator('#state-last').click();
  await page.keyboard.press(' ');
  const loop = await sample(wraps);
  await page.keyboard.press(' ');
  assert.ok(wraps(loop), `loop wraps to the start: ${loop.map((t) => t.toFixed(1))}`);
  const v = await view();
  assert.deepEqual([v.playing, v.speed, v.mode], [false, 4, 'loop']);
  await page.locator('#play-speed').selectOption('1');
});

test('orientation: the ±X/±Y/±Z and iso views, up axis, fit all, zoom toward the cursor', async () => {
  // Two vertices moving by `d` from the first state to the last, in a box.
  const moving = (d, bboxMax) => ({
    head: { stepCount: 2, baseVertexCount: 2, bboxMin: [0, 0, 0], bboxMax },
    positionsAt: (t, n, out) => (out.set(t ? [d[0], d[1], d[2], 1 + d[0], 1 + d[1], 1 + d[2]] : [0, 0, 0, 1, 1, 1]), out),
  });
  assert.equal(upAxisOf(moving([0, 3, -60], [60, 60, 250])), 'z', 'a column crushed along z (crashbox-s): z up');
  assert.equal(upAxisOf(moving([-300, 5, 6], [4000, 1800, 1400])), 'z', 'a car, moving along x: its box, z up');
  assert.equal(upAxisOf(moving([-300, 5, 6], [4000, 1400, 1800])), 'y', 'the same car y up');
  assert.equal(upAxisOf(mesh), 'y', 'the rail, bent upward along y: y up');
  // A real column crush (../shared/data, CalculiX): z up.
  const crashbox = join(dir, 'crashbox-s.dpm');
  execFileSync(cli, ['build', fileURLToPath(new URL('../../../shared/data/crashbox-s/obj/frame_*.obj', import.meta.url)), '-o', crashbox], { stdio: 'pipe' });
  assert.equal(upAxisOf(readDpm(new Uint8Array(readFileSync(crashbox)), crashbox).mesh), 'z', 'crashbox-s: z up');
  assert.equal(upAxisOf(mesh, 'z'), 'z', '?up=z');
  assert.equal((await view()).up, 'y');
  const expected = { '+x': [1, 0, 0], '-x': [-1, 0, 0], '+z': [0, 0, 1], '-z': [0, 0, -1] };
  for (const [name, look] of Object.entries(expected)) {
    await api((n) => window.dynpm.setView(n), name);
    const v = await view();
    assert.ok(near(v.look, look, 1e-6) && near(v.screenUp, [0, 1, 0], 1e-6), `${name}: ${JSON.stringify(v)}`);
  }
  // Along the up axis: north (−z for y up) at the top of the screen.
  for (const [name, look] of [['+y', [0, 1, 0]], ['-y', [0, -1, 0]]]) {
    await page.locator(`#orientation [data-view="${name}"]`).click();
    const v = await view();
    assert.ok(near(v.look, look, 1e-3) && near(v.screenUp, [0, 0, -1], 1e-3), `${name}: ${JSON.stringify(v)}`);
  }
  await page.locator('#orientation [data-view="iso"]').click();
  const s3 = 1 / Math.sqrt(3);
  assert.ok(near((await view()).look, [-s3, -s3, -s3], 1e-9));
  await page.locator('#up-axis').selectOption('z');
  let v = await view();
  assert.equal(v.up, 'z');
  assert.ok(near(v.look, [-s3, s3, -s3], 1e-9) && v.screenUp[2] > 0.5, `z up, iso: ${JSON.stringify(v)}`);
  await api(() => window.dynpm.setUp('y'));
  assert.match(await thrown(() => window.dynpm.setView('top')), /Error: view 'top': one of \+x, -x, \+y, -y, \+z, -z, iso, fit/);
  // Fit: the model fills the picture without leaving it; the wheel zooms in toward the cursor
  // (the orbit's centre moves toward it), Fit frames it again.
  const extent = async () => {
    const grey = await snapshot();
    let x0 = 64, x1 = -1, y0 = 64, y1 = -1;
    grey.forEach((g, i) => {
      if (Math.abs(g - grey[0]) < 2) return;
      const x = i % 64, y = Math.floor(i / 64);
      x0 = Math.min(x0, x), x1 = Math.max(x1, x), y0 = Math.min(y0, y), y1 = Math.max(y1, y);
    });
    return { x0, x1, y0, y1 };
  };
  await api(() => window.dynpm.setView('+x'));
  const canvas = page.locator('#view');
  const size = await canvas.boundingBox();
  // The open panel floats over the canvas's left side: the model is framed in what it leaves.
  const panelBox = await page.locator('#panel').boundingBox();
  const covered = (64 * (panelBox.x + panelBox.width - size.x)) / size.width;
  const fitted = await extent();
  assert.ok(fitted.x0 > covered - 1 && fitted.x1 < 63 && fitted.y0 > 0 && fitted.y1 < 63, `right of the panel (${covered} of 64): ${JSON.stringify(fitted)}`);
  assert.ok(fitted.x1 - fitted.x0 > 0.75 * (64 - covered), `fills the width the panel leaves: ${JSON.stringify(fitted)}`);
  // A saved picture has no panel over it: the model at its centre.
  const saved = await inScreenshot();
  assert.ok(Math.abs(saved.left - saved.right) < 0.05 && saved.left > 0, `the saved picture centres the model: ${JSON.stringify(saved)}`);
  const before = await view();
  await page.mouse.move(size.width * 0.8, size.height * 0.5);
  for (let i = 0; i < 5; i++) await page.mouse.wheel(0, -120), await page.waitForTimeout(30);
  const zoomed = await view();
  const toward = new THREE.Vector3(...zoomed.target).sub(new THREE.Vector3(...before.target));
  const right = new THREE.Vector3(...before.look).cross(new THREE.Vector3(...before.screenUp));
  assert.ok(toward.dot(right) > 1, `the centre moved right, toward the cursor: ${toward.toArray()}`);
  const far = new THREE.Vector3(...before.camera).distanceTo(new THREE.Vector3(...before.target));
  const close = new THREE.Vector3(...zoomed.camera).distanceTo(new THREE.Vector3(...zoomed.target));
  assert.ok(close < 0.8 * far, `zoomed in: ${far} → ${close}`);
  await page.locator('#orientation [data-view="fit"]').click();
  const again = await extent();
  assert.ok(again.x1 - again.x0 > 0.75 * (64 - covered) && again.x0 > covered - 1 && again.x1 < 63, `fit again: ${JSON.stringify(again)}`);
  await page.screenshot({ path: join(dir, 'view-orientation.png') });
});

// dynpm.screenshot() read on the page: the colour of CSS pixel `point` ([x, y]), or without one
// how far what is not background (above the triad) lies from the left and right edges, in
// fractions of the width.
const inScreenshot = (point = null) =>
  page.evaluate(async (point) => {
    const image = new Image();
    image.src = window.dynpm.screenshot();
    await image.decode();
    const c = document.createElement('canvas');
    [c.width, c.height] = [image.width, image.height];
    const g = c.getContext('2d');
    g.drawImage(image, 0, 0);
    if (point) return [...g.getImageData(Math.round(point[0] * devicePixelRatio), Math.round(point[1] * devicePixelRatio), 1, 1).data];
    const { data } = g.getImageData(0, 0, c.width, Math.floor(c.height * 0.8));
    let x0 = c.width, x1 = -1;
    for (let i = 0; i < data.length; i += 4)
      if (Math.abs(data[i] - data[0]) + Math.abs(data[i + 1] - data[1]) + Math.abs(data[i + 2] - data[2]) > 6) {
        const x = (i / 4) % c.width;
        x0 = Math.min(x0, x), x1 = Math.max(x1, x);
      }
    return { left: x0 / c.width, right: 1 - x1 / c.width };
  }, point);
const pixelAt = (x, y) => inScreenshot([x, y]);

test('keys f (fit) and r (reset: iso), the Reset view button, ?up=z in the address', async () => {
  const s3 = 1 / Math.sqrt(3);
  await api(() => window.dynpm.setView('+z'));
  await api(() => document.activeElement?.blur());  // keys to the page, not to a control
  await page.keyboard.press('r');
  assert.ok(near((await view()).look, [-s3, -s3, -s3], 1e-9), 'r: the iso view');
  const canvas = await page.locator('#view').boundingBox();
  await page.mouse.move(canvas.width * 0.8, canvas.height * 0.5);
  for (let i = 0; i < 3; i++) await page.mouse.wheel(0, -120), await page.waitForTimeout(30);
  const zoomed = await view();
  await page.keyboard.press('f');
  const fitted = await view();
  assert.ok(near(fitted.look, zoomed.look, 1e-6), 'f keeps the direction');
  const distance = (v) => new THREE.Vector3(...v.camera).distanceTo(new THREE.Vector3(...v.target));
  assert.ok(distance(fitted) > distance(zoomed), 'f: the whole model again');
  await api(() => window.dynpm.setView('-x'));
  await page.locator('#reset').click();
  assert.ok(near((await view()).look, [-s3, -s3, -s3], 1e-9), 'Reset view: iso');
  const zUp = await browser.newPage({ viewport: { width: 900, height: 700 } });
  await zUp.goto(`${url}?up=z`);
  await zUp.evaluate(() => window.dynpm.ready.then(() => true));
  const v = await zUp.evaluate(() => window.dynpm.view());
  assert.equal(v.up, 'z');
  assert.equal(await zUp.locator('#up-axis').inputValue(), 'z');
  assert.ok(near(v.look, [-s3, s3, -s3], 1e-9) && v.screenUp[2] > 0.5, `?up=z: z up, iso: ${JSON.stringify(v)}`);
  await zUp.close();
});

test('the axis triad: a click on an axis looks along it, a second click the other way', async () => {
  const { width, height } = await page.locator('#view').boundingBox();
  // Where the triad draws axis c's arrow head (orientation.js: 90 px in the bottom-right corner,
  // 6 px from the right, 34 from the bottom, an orthographic view of ±1.25 turned as the camera).
  const head = async (c) => {
    const v = await view();
    const up = new THREE.Vector3(...v.screenUp), right = new THREE.Vector3(...v.look).cross(up);
    const tip = new THREE.Vector3().setComponent(c, 0.82), px = 90 / 2.5;
    return [width - 96 + (tip.dot(right) + 1.25) * px, height - 124 + (1.25 - tip.dot(up)) * px];
  };
  const RED = [0xd0, 0x30, 0x2a], GREEN = [0x2f, 0x9a, 0x3a], BLUE = [0x2d, 0x62, 0xc8];
  await api(() => window.dynpm.setView('iso'));
  await api(() => window.dynpm.clearPicks());
  for (const [c, name, colour] of [[0, 'x', RED], [1, 'y', GREEN], [2, 'z', BLUE]]) {
    await api(() => window.dynpm.setView('iso'));
    const [x, y] = await head(c);
    const drawn = await pixelAt(x, y);
    assert.ok(drawn.slice(0, 3).every((v, i) => Math.abs(v - colour[i]) < 60), `the ${name} arrow is drawn at (${x}, ${y}): ${drawn}`);
    await page.mouse.click(x, y);
    const along = await view();
    const look = [0, 0, 0].map((_, i) => (i === c ? 1 : 0));
    assert.ok(near(along.look, look, 1e-3), `a click on ${name}: looks along +${name}: ${along.look}`);
    // The triad answers clicks where it was last drawn: wait for the frame that turns it.
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    await page.mouse.click(...(await head(c)));
    assert.ok(near((await view()).look, look.map((v) => -v), 1e-3), `a second click: along -${name}`);
  }
  assert.deepEqual(await api(() => window.dynpm.picks()), [], 'a click on the triad picks nothing');
  // The model, not the triad: a click beside it is left to picking and orbiting.
  const before = await view();
  await page.mouse.click(width - 200, height - 80);
  assert.deepEqual((await view()).look, before.look);
});

test('deformation scale ×0 … ×10 and the undeformed ghost (API and controls)', async () => {
  await api(() => window.dynpm.setView('iso'));
  await api(() => window.dynpm.setStep(0));
  const undeformed = await snapshot();
  await api(() => window.dynpm.setStep(30));
  const deformed = await snapshot();
  await api(() => window.dynpm.setDeformationScale(0));
  assert.ok(difference(await snapshot(), undeformed) < 1e-3, '×0 at the last state: the first state');
  assert.equal(await page.locator('#deform-scale-label').textContent(), '×0 (undeformed)');
  await page.locator('#deform-scale').fill('10');
  assert.equal((await view()).scale, 10);
  const tenfold = await snapshot();
  assert.ok(difference(tenfold, deformed) > 0.5, '×10 differs from ×1');
  // Displacement colours keep the true displacement: the range of this step is the same.
  await page.locator('#colour').selectOption('displacement');
  await page.locator('#range').selectOption('step');
  const max10 = Number(await page.locator('#legend').getAttribute('data-max'));
  await page.locator('#deform-scale').fill('1');
  const max1 = Number(await page.locator('#legend').getAttribute('data-max'));
  assert.ok(max1 > 100 && max10 === max1, `this step's max displacement ${max1} at ×1, ${max10} at ×10`);
  assert.ok(difference(await snapshot(), deformed) > 0.2, 'colours back');
  await page.locator('#range').selectOption('all');
  await page.locator('#colour').selectOption('part');
  assert.ok(difference(await snapshot(), deformed) < 1e-3, 'back at ×1');
  assert.match(await thrown(() => window.dynpm.setDeformationScale(11)), /RangeError: deformation scale 11: from 0 to 10/);
  // The ghost: the first state drawn faintly, at every level.
  await page.locator('#ghost').check();
  assert.equal((await view()).ghost, true);
  const ghost = await snapshot();
  assert.ok(difference(ghost, deformed) > 0.3, 'the ghost shows');
  await api(() => window.dynpm.setLevel({ ratio: 0.1 }));
  const coarseGhost = await snapshot();
  await api(() => window.dynpm.setGhost(false));
  const coarse = await snapshot();
  assert.ok(difference(coarseGhost, coarse) > 0.3, 'the ghost at a coarse level');
  await api(() => window.dynpm.setGhost(true));
  await api(() => window.dynpm.setLevel({ ratio: 1 }));
  assert.ok(difference(await snapshot(), ghost) < 1e-3, 'the same ghost back at full resolution');
  await page.screenshot({ path: join(dir, 'view-ghost.png') });
  await api(() => window.dynpm.setGhost(false));
});

// The PNG data URL's size and the pixels of its bottom-right corner (the axis triad) by colour.
async function pngFacts(dataUrl) {
  return page.evaluate(async (src) => {
    const image = new Image();
    image.src = src;
    await image.decode();
    const c = document.createElement('canvas');
    c.width = image.width, c.height = image.height;
    const g = c.getContext('2d');
    g.drawImage(image, 0, 0);
    const side = Math.round(110 * devicePixelRatio);
    const px = g.getImageData(c.width - side, c.height - side - Math.round(30 * devicePixelRatio), side, side).data;
    const count = { red: 0, green: 0, blue: 0 };
    for (let i = 0; i < px.length; i += 4) {
      const [r, gr, b] = [px[i], px[i + 1], px[i + 2]];
      if (r > 150 && gr < 90 && b < 90) count.red++;
      if (gr > 110 && r < 90 && b < 110) count.green++;
      if (b > 150 && r < 90 && gr < 140) count.blue++;
    }
    const canvas = document.getElementById('view');
    return { width: image.width, height: image.height, canvas: [canvas.width, canvas.height], count };
  }, dataUrl);
}

test('images: PNG of the view (with the axis triad) and the animation as WebM', async () => {
  await api(() => window.dynpm.setStep(30));
  const dataUrl = await api(() => window.dynpm.screenshot());
  assert.match(dataUrl, /^data:image\/png;base64,/);
  const png = Buffer.from(dataUrl.split(',')[1], 'base64');
  assert.deepEqual([...png.subarray(0, 8)], [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);
  const facts = await pngFacts(dataUrl);
  assert.deepEqual([facts.width, facts.height], facts.canvas);
  for (const [colour, n] of Object.entries(facts.count)) assert.ok(n > 20, `the triad's ${colour} axis: ${n} pixels`);
  const [download] = await Promise.all([page.waitForEvent('download'), page.locator('#save-png').click()]);
  assert.equal(download.suggestedFilename(), 'rail-parts-step30.png');
  const saved = readFileSync(await download.path());
  assert.deepEqual([...saved.subarray(0, 4)], [0x89, 0x50, 0x4e, 0x47]);
  // WebM: an EBML header, a WebM doc type, some frames.
  await page.locator('#play-speed').selectOption('4');
  const webm = await api(async () => {
    const blob = await window.dynpm.record();
    return { type: blob.type, bytes: Array.from(new Uint8Array(await blob.arrayBuffer())) };
  });
  const bytes = Buffer.from(webm.bytes);
  assert.equal(webm.type, 'video/webm');
  assert.deepEqual([...bytes.subarray(0, 4)], [0x1a, 0x45, 0xdf, 0xa3], 'EBML magic');
  assert.ok(bytes.includes(Buffer.from('webm')) && bytes.length > 2000, `${bytes.length} bytes`);
  assert.equal(await stepNow(), 30, 'recorded to the last state');
  // Frame by frame: slow where the machine is loaded (SwiftShader draws every frame).
  const [video] = await Promise.all([page.waitForEvent('download', { timeout: 150000 }), page.locator('#record-webm').click()]);
  assert.equal(video.suggestedFilename(), 'rail-parts.webm');
  const file = readFileSync(await video.path());
  assert.deepEqual([...file.subarray(0, 4)], [0x1a, 0x45, 0xdf, 0xa3]);
  assert.ok(file.length > 2000, `a second recording has frames too: ${file.length} bytes`);
  execFileSync('cp', [await video.path(), join(dir, 'rail-parts.webm')]);
  assert.equal((await view()).mode, 'loop', 'the play mode the user had');
  // Stop ends a recording early: the video so far, at the state shown (slowly, to be early).
  await page.locator('#play-speed').selectOption('0.25');
  const [early] = await Promise.all([
    page.waitForEvent('download', { timeout: 150000 }),
    (async () => {
      await page.locator('#record-webm').click();
      await page.waitForFunction(() => window.dynpm.view().step >= 3, null, { timeout: 60000 });
      assert.equal(await page.locator('#record-webm').textContent(), '■ Stop');
      // Forced: while frames are drawn one by one, playwright's wait for a still button (two
      // animation frames alike) timed out here.
      await page.locator('#record-webm').click({ force: true });
    })(),
  ]);
  const stoppedAt = await stepNow();
  assert.ok(stoppedAt >= 3 && stoppedAt < 30, `stopped at step ${stoppedAt}`);
  const part = readFileSync(await early.path());
  assert.deepEqual([...part.subarray(0, 4)], [0x1a, 0x45, 0xdf, 0xa3], 'a video until Stop');
  assert.match(await page.locator('#record-webm').textContent(), /Record WebM/);
  await page.locator('#play-speed').selectOption('1');
  // Here the page draws about one frame a second for a few seconds after a recording (the
  // software encoder catching up on a loaded machine): the clicks that follow wait for the
  // frames to come back (playwright waits for a button to stay still over two frames).
  await page.waitForFunction(
    () => new Promise((resolve) => {
      let n = 0;
      const start = performance.now();
      const count = () => (++n, performance.now() - start < 500 ? requestAnimationFrame(count) : resolve(n >= 10));
      requestAnimationFrame(count);
    }),
    null,
    { timeout: 60000 },
  );
});

test('details: select labels not cut off, edges that read over every colour of the scales', async () => {
  await page.locator('#colour').selectOption('displacement');
  const cut = await api(() => {
    const g = document.createElement('canvas').getContext('2d');
    const out = [];
    for (const s of document.querySelectorAll('#panel select')) {
      if (!s.offsetParent) continue;  // hidden
      g.font = getComputedStyle(s).font;
      const widest = Math.max(...[...s.options].map((o) => g.measureText(o.text).width));
      // Chrome gives a select 20 px beside its longest option (arrow and padding).
      if (widest + 20 > s.clientWidth + 0.5) out.push(`${s.id}: ${widest} px of text in ${s.clientWidth}`);
    }
    return out;
  });
  assert.deepEqual(cut, []);
  await page.locator('#colour').selectOption('part');
  // Every colour of both schemes and the part hues: at least 2.4 : 1 against its edge (the old
  // fixed edge, #1b2330 at 55 %, fell to 1.0 : 1 over viridis's dark purple).
  const colours = [];
  for (const stops of Object.values(SCHEMES))
    for (let i = 0; i <= 100; i++) {
      const c = [0, 0, 0];
      schemeColour(stops, i / 100, c, 0);
      colours.push(c);
    }
  for (let k = 0; k < 64; k++) colours.push(partColour(k).toArray());
  // The part colours on the canvas are those (the model's six, in its list's order).
  const shown = await api(() => window.dpmViewer.partSlots());
  const drawnColours = new Set(shown.drawn.map((f) => shown.slotColours.slice(12 * f, 12 * f + 3).join()));
  assert.deepEqual(drawnColours, new Set([0, 1, 2, 3, 4, 5].map((k) => [...new Float32Array(partColour(k).toArray())].join())));
  const worst = Math.min(...colours.map((c) => contrast(c, edgeColour(c))));
  assert.ok(worst >= 2.4, `worst contrast ${worst}`);
  const old = (c) => c.map((x, i) => 0.45 * x + 0.55 * [0x1b, 0x23, 0x30][i] / 255);
  assert.ok(Math.min(...colours.map((c) => contrast(c, old(c)))) < 1.1, 'the rule this replaces fails');
  assert.deepEqual(consoleErrors, []);
});

test('the panel collapses, and starts collapsed in a small window', async () => {
  const toggle = page.locator('#panel-toggle');
  assert.equal(await toggle.getAttribute('aria-expanded'), 'true');
  await toggle.click();
  const collapsed = await page.locator('#panel').boundingBox();
  assert.ok(collapsed.width < 60 && collapsed.height < 60, `collapsed: ${JSON.stringify(collapsed)}`);
  assert.equal(await page.locator('#time').isVisible(), false);
  await toggle.click();
  assert.equal(await page.locator('#time').isVisible(), true);
  // Taller than the window, the open panel scrolls and ends above the status line, which would
  // otherwise cover its last rows.
  const [panel, stats] = [await page.locator('#panel').boundingBox(), await page.locator('#stats').boundingBox()];
  assert.ok(panel.y + panel.height <= stats.y, `the panel (${panel.y}…${panel.y + panel.height}) ends above the status line (${stats.y})`);
  const small = await browser.newPage({ viewport: { width: 560, height: 420 } });
  await small.goto(url);
  await small.evaluate(() => window.dynpm.ready.then(() => true));
  const box = await small.locator('#panel').boundingBox();
  assert.ok(box.width < 60 && box.height < 60, `a small window starts collapsed: ${JSON.stringify(box)}`);
  await small.locator('#panel-toggle').click();
  const open = await small.locator('#panel').boundingBox();
  assert.ok(open.y + open.height <= 420, `the open panel stays inside the window (it scrolls): ${JSON.stringify(open)}`);
  await small.close();
});

test('a one-state model: no time controls, no displacement colouring, no deformation', async () => {
  // The sample's first frame alone (the fixture built the sample's .dpm from build/…/sample/).
  const one = join(dir, 'one-state.dpm');
  execFileSync(cli, ['build', join(out, '..', 'sample', 'hat-rail', 'frame_000.obj'), '-o', one], { stdio: 'pipe' });
  const served = await startServer(cli, one);
  servers.push(served.server);
  const p = await browser.newPage({ viewport: { width: 900, height: 700 } });
  const errors = [];
  p.on('pageerror', (e) => errors.push(String(e)));
  await p.goto(served.url);
  await p.evaluate(() => window.dynpm.ready.then(() => true));
  for (const id of ['#time-section', '#states', '#deformation']) assert.equal(await p.locator(id).isVisible(), false, id);
  assert.deepEqual(await p.locator('#colour option').evaluateAll((os) => os.map((o) => o.value)), ['part']);
  assert.doesNotMatch(await p.locator('#stats').textContent(), /step|time/, 'no step or time in the status line');
  assert.equal(await p.evaluate(() => window.dynpm.setStep(0)), 0);
  const error = await p.evaluate(() => {
    try {
      window.dynpm.setStep(1);
    } catch (e) {
      return e.message;
    }
  });
  assert.equal(error, 'step 1: from 0 to 0');
  // Keys do nothing to time; views and images still work.
  await p.keyboard.press('End');
  assert.equal(await p.evaluate(() => window.dynpm.view().step), 0);
  await p.evaluate(() => window.dynpm.setView('-z'));
  assert.match(await p.evaluate(() => window.dynpm.screenshot()), /^data:image\/png;base64,/);
  await p.screenshot({ path: join(dir, 'one-state.png') });
  assert.deepEqual(errors, []);
  await p.close();
});
