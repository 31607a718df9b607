// Strings from a file are text in the page, never markup: a model whose field name, input file
// name and .dpm name are HTML that would run script, shown in Chromium; the Content-Security-
// Policy on every response; ?file= naming another origin refused (docs/viewer.md "Security").
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdirSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';

import { CHROMIUM_ARGS, startServer } from './chromium.mjs';

const { DYNPM_CLI: cli, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !out) throw new Error('security.test.mjs needs DYNPM_CLI, DYNPM_TEST_OUT');
const CHROMIUM = process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium';

// Each would set window.__pwned if it ever became an element.
const FIELD = '<img src=x onerror=window.__pwned=1>';
const INPUT = '<img src=y onerror=window.__pwned=2>';
const MODEL = '<img src=z onerror=window.__pwned=3>.dpm';

const xml = (s) => s.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;').replace(/"/g, '&quot;');

// A 4 × 4-point plate of 9 quads that bends over two steps, with one point field.
function vtu(step) {
  const points = [], values = [];
  for (let j = 0; j < 4; j++)
    for (let i = 0; i < 4; i++) {
      points.push(i, j, step * 0.1 * i * i);
      values.push(step + i + j);
    }
  const cells = [];
  for (let j = 0; j < 3; j++)
    for (let i = 0; i < 3; i++) cells.push(4 * j + i, 4 * j + i + 1, 4 * j + i + 5, 4 * j + i + 4);
  const offsets = Array.from({ length: 9 }, (_, c) => 4 * (c + 1));
  return `<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
<UnstructuredGrid><Piece NumberOfPoints="16" NumberOfCells="9">
<PointData><DataArray type="Float32" Name="${xml(FIELD)}" format="ascii">${values.join(' ')}</DataArray></PointData>
<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">${points.join(' ')}</DataArray></Points>
<Cells>
<DataArray type="Int32" Name="connectivity" format="ascii">${cells.join(' ')}</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">${offsets.join(' ')}</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">${Array(9).fill(9).join(' ')}</DataArray>
</Cells>
</Piece></UnstructuredGrid></VTKFile>
`;
}

const dir = join(out, 'security');
let server, url, browser, other, otherHits = 0;

before(async () => {
  rmSync(dir, { recursive: true, force: true });
  mkdirSync(dir, { recursive: true });
  for (const step of [0, 1, 2]) writeFileSync(join(dir, `${INPUT}_${step}.vtu`), vtu(step));
  const dpm = join(dir, MODEL);
  execFileSync(cli, ['build', join(dir, `${INPUT}_*.vtu`), '-o', dpm], { stdio: 'pipe' });
  ({ server, url } = await startServer(cli, dpm));
  server.removeAllListeners('exit');
  // Another origin (another port), which the page must never ask.
  other = createServer((req, res) => {
    otherHits++;
    res.writeHead(200, { 'Access-Control-Allow-Origin': '*' }).end(readFileSync(dpm));
  });
  await new Promise((resolve) => other.listen(0, '127.0.0.1', resolve));
  browser = await chromium.launch({ executablePath: CHROMIUM, headless: true, args: CHROMIUM_ARGS });
});

after(async () => {
  await browser?.close();
  other?.close();
  server?.kill('SIGTERM');
});

async function open(address) {
  const page = await browser.newPage({ viewport: { width: 800, height: 600 } });
  const requests = [], responses = [];
  page.on('request', (r) => requests.push(r.url()));
  page.on('response', (r) => responses.push(r));
  await page.goto(address);
  return { page, requests, responses };
}

test('names from the file are shown as text, and no script runs', async () => {
  const { page } = await open(url);
  await page.waitForFunction(() => window.dpmViewer?.state().complete, null, { timeout: 30000 });
  await page.locator('#colour').selectOption({ label: FIELD });
  await page.waitForTimeout(500);  // time for an <img> to fail and fire onerror
  assert.equal(await page.evaluate(() => window.__pwned), undefined, 'script from the file ran');
  assert.equal(await page.evaluate(() => document.querySelectorAll('img').length), 0);
  assert.ok((await page.locator('#legend').textContent()).includes(FIELD), 'the legend names the field');
  assert.equal(await page.locator('#title').textContent(), MODEL);
  assert.ok((await page.locator('#note').textContent()).includes(INPUT));
  await page.locator('#colour').selectOption('part');
  await page.waitForTimeout(200);
  assert.match(await page.locator('#part-list li').first().textContent(), /part \d+/);
  assert.equal(await page.locator('#part-list .swatch').count() > 0, true);
  assert.equal(await page.evaluate(() => window.__pwned), undefined);
  await page.close();
});

test('every response carries the Content-Security-Policy, also in the page as <meta>', async () => {
  const { page, responses } = await open(url);
  await page.waitForFunction(() => window.dpmViewer?.state().complete, null, { timeout: 30000 });
  assert.ok(responses.length >= 6, `${responses.length} responses`);
  let policy = null;
  for (const r of responses) {
    const csp = (await r.allHeaders())['content-security-policy'];
    assert.ok(csp, `no Content-Security-Policy on ${r.url()}`);
    assert.match(csp, /default-src 'self'/);
    assert.match(csp, /script-src 'self'(;|$)/);
    assert.doesNotMatch(csp, /unsafe/);
    policy ??= csp;
    assert.equal(csp, policy, 'one policy');
  }
  // The same policy in index.html for --export (a static server sends no header);
  // frame-ancestors is only valid in the header.
  const html = await (await fetch(url)).text();
  const meta = html.match(/<meta http-equiv="Content-Security-Policy" content="([^"]*)">/)?.[1];
  assert.equal(meta + "; frame-ancestors 'none'", policy);
  assert.doesNotMatch(html, /<script(?![^>]*\bsrc=)/, 'no inline script');
  await page.close();
});

test('?file= naming another origin is refused, and nothing leaves the origin', async () => {
  const port = other.address().port;
  const files = [`http://127.0.0.1:${port}/x.dpm`, `//127.0.0.1:${port}/x.dpm`, '//evil.example/x', 'data:,x'];
  for (const file of files) {
    const { page, requests } = await open(`${url}?file=${encodeURIComponent(file)}`);
    await page.waitForFunction(() => window.dpmViewer?.state().error, null, { timeout: 10000 });
    const { error, hasBase } = await page.evaluate(() => window.dpmViewer.state());
    assert.match(error, /not on this server/, file);
    assert.equal(hasBase, false);
    assert.ok(await page.locator('#error').isVisible());
    const origin = new URL(url).origin;
    assert.deepEqual(requests.filter((r) => !r.startsWith(origin)), [], file);
    await page.close();
  }
  assert.equal(otherHits, 0, 'the other origin was asked');
  // A file of this origin is fine.
  const { page } = await open(`${url}?file=model.dpm`);
  await page.waitForFunction(() => window.dpmViewer?.state().complete, null, { timeout: 30000 });
  assert.equal(await page.evaluate(() => window.dpmViewer.state().error), null);
  await page.close();
});

test("the page's own code builds no markup from strings", () => {
  const sources = ['index.html', ...readdirSync('src').filter((f) => f.endsWith('.js')).map((f) => `src/${f}`),
    ...readdirSync('src/dpm').map((f) => `src/dpm/${f}`)].map((f) => [f, readFileSync(f, 'utf8')]);
  for (const [file, text] of sources)
    assert.doesNotMatch(text, /\.(inner|outer)HTML\s*[+]?=|insertAdjacentHTML|document\.write|\bstyle="/, file);
});
