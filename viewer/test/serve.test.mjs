// `dynpm serve DIR` (docs/batch.md "dynpm serve"): /index.json against `dynpm catalogue`, only
// .dpm files below DIR (escapes by '..', percent-encoding, symbolic links, other files and build
// temporaries refused), a file that appears is listed once complete, range requests of a model,
// thumbnails, the Host check and the page's policy. Plain sockets where fetch() would normalise
// the path ('..') or set the Host itself.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { copyFileSync, mkdirSync, readFileSync, renameSync, rmSync, symlinkSync, writeFileSync } from 'node:fs';
import { connect } from 'node:net';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { startServer } from './chromium.mjs';

const { DYNPM_CLI: cli, DYNPM_DPM: dpm, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !dpm || !out) throw new Error('serve.test.mjs needs DYNPM_CLI, DYNPM_DPM, DYNPM_TEST_OUT');
const base = join(out, 'serve');
const dir = join(base, 'catalogue');
const model = readFileSync(dpm);

async function startServe(folder) {
  const { server, url } = await startServer(cli, folder, [], 'serve');
  server.removeAllListeners('exit');
  return { server, url, port: Number(new URL(url).port) };
}

// One request on a fresh connection, the path sent as it is: { status, head, body }.
function raw(port, text) {
  return new Promise((resolve, reject) => {
    const socket = connect(port, '127.0.0.1');
    const chunks = [];
    socket.on('data', (d) => chunks.push(d));
    socket.on('error', reject);
    socket.on('close', () => {
      const all = Buffer.concat(chunks);
      const end = all.indexOf('\r\n\r\n');
      const head = all.subarray(0, end).toString('latin1');
      resolve({ status: Number(head.match(/^HTTP\/1\.1 (\d{3})/)?.[1] ?? 0), head, body: all.subarray(end + 4) });
    });
    socket.write(text);
  });
}
const get = (port, path, headers = '') => raw(port, `GET ${path} HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\n${headers}Connection: close\r\n\r\n`);
const index = async (port) => JSON.parse((await get(port, '/index.json')).body.toString('utf8'));

let served;
before(async () => {
  rmSync(base, { recursive: true, force: true });
  mkdirSync(join(dir, 'runs', 'deep'), { recursive: true });
  copyFileSync(dpm, join(dir, 'a.dpm'));
  copyFileSync(dpm, join(dir, 'runs', 'b 1.dpm'));  // a space: percent-encoded in its URL
  copyFileSync(dpm, join(dir, 'runs', 'deep', 'c.dpm'));
  copyFileSync(dpm, join(base, 'outside.dpm'));  // next to DIR, not below it
  writeFileSync(join(base, 'secret.txt'), 'secret\n');
  writeFileSync(join(dir, 'notes.txt'), 'not a model\n');
  copyFileSync(dpm, join(dir, 'd.dpm.tmp-1-0'));  // a build still writing
  symlinkSync(join(base, 'outside.dpm'), join(dir, 'link.dpm'));
  symlinkSync(base, join(dir, 'up'));  // a folder link out of DIR
  // Without a thumbnail: the page shows a placeholder, /thumb/ answers 404.
  assert.equal(spawnSync(cli, ['build', ...['--no-thumbnail', '-o', join(dir, 'plain.dpm')], join(out, '..', 'sample', 'hat-rail', 'frame_000.obj'), '--quiet']).status, 0);
  served = await startServe(dir);
});
after(() => served?.server.kill('SIGTERM'));

test('/index.json holds the entries dynpm catalogue writes, with thumbnails noted', async () => {
  const served_ = await index(served.port);
  const copy = join(base, 'copy');
  rmSync(copy, { recursive: true, force: true });
  spawnSync('cp', ['-a', dir, copy]);  // catalogue writes index.json into its folder: a copy keeps DIR as it was
  const r = spawnSync(cli, ['catalogue', copy, '--quiet']);
  assert.equal(r.status, 0, String(r.stderr));
  const written = JSON.parse(readFileSync(join(copy, 'index.json'), 'utf8'));
  assert.equal(served_.format, 'dynpm-catalogue');
  assert.deepEqual(served_.entries, written.entries);
  assert.deepEqual(served_.entries.map((e) => e.path), ['a.dpm', 'plain.dpm', 'runs/b 1.dpm', 'runs/deep/c.dpm']);
  assert.deepEqual(served_.entries.map((e) => e.thumbnail), [true, false, true, true]);
  assert.deepEqual(served_.problems, []);
});

test('models below DIR are served, with range requests', async () => {
  const { port } = served;
  for (const path of ['/files/a.dpm', '/files/runs/b%201.dpm', '/files/runs/deep/c.dpm']) {
    const r = await get(port, path);
    assert.equal(r.status, 200, path);
    assert.ok(r.body.equals(model), path);
  }
  const r = await get(port, '/files/runs/deep/c.dpm', 'Range: bytes=100-1099\r\n');
  assert.equal(r.status, 206);
  assert.match(r.head, new RegExp(`Content-Range: bytes 100-1099/${model.length}`));
  assert.ok(r.body.equals(model.subarray(100, 1100)));
  const past = await get(port, '/files/a.dpm', `Range: bytes=${model.length}-\r\n`);
  assert.equal(past.status, 416);
});

test('nothing but .dpm files below DIR: .., %2e%2e, symbolic links, other files, temporaries', async () => {
  const { port } = served;
  const refused = [
    '/files/../outside.dpm', '/files/%2e%2e/outside.dpm', '/files/%2E%2E%2Foutside.dpm', '/files/runs/..%2f..%2foutside.dpm',
    '/files/runs/%2e%2e/a.dpm', '/files/./a.dpm', '/files//a.dpm', '/files/%2fetc%2fpasswd', '/files/a.dpm%00', '/files/a.dpm%00.txt',
    '/files/runs%5c..%5c..%5coutside.dpm', '/files/%zz.dpm', '/files/a.dpm%2', '/files/link.dpm', '/files/up/outside.dpm',
    '/files/up/catalogue/a.dpm', '/files/notes.txt', '/files/d.dpm.tmp-1-0', '/files/missing.dpm', '/files/runs', '/files/',
    '/../secret.txt', '/%2e%2e/secret.txt', '/thumb/../outside.png', '/thumb/link.png', '/thumb/up/outside.png', '/thumb/plain.png',
  ];
  for (const path of refused) {
    const r = await get(port, path);
    assert.ok(r.status === 404 || r.status === 400, `${path}: ${r.status}`);
    assert.ok(!r.body.includes(model.subarray(0, 16)) && !r.body.includes('secret'), `${path} sent a file`);
  }
  const json = await index(port);
  assert.ok(!json.entries.some((e) => /link|tmp|up\//.test(e.path)), 'no link or temporary listed');
});

test('a file appears in the list once it is complete; a half-written one is not an entry', async () => {
  const { port } = served;
  // A build writes a temporary and renames it.
  writeFileSync(join(dir, 'e.dpm.tmp-4242-0'), model.subarray(0, 5000));
  assert.ok(!(await index(port)).entries.some((e) => e.path.startsWith('e.dpm')));
  copyFileSync(dpm, join(dir, 'e.dpm.tmp-4242-0'));
  renameSync(join(dir, 'e.dpm.tmp-4242-0'), join(dir, 'e.dpm'));
  let json = await index(port);
  assert.ok(json.entries.some((e) => e.path === 'e.dpm'), 'the renamed build is listed');
  // A copy still under way (no temporary name): a problem, not an entry, until it is whole.
  writeFileSync(join(dir, 'f.dpm'), model.subarray(0, 3000));
  json = await index(port);
  assert.ok(!json.entries.some((e) => e.path === 'f.dpm'));
  assert.ok(json.problems.some((p) => p.includes('f.dpm')), JSON.stringify(json.problems));
  writeFileSync(join(dir, 'f.dpm'), model);
  json = await index(port);
  assert.ok(json.entries.some((e) => e.path === 'f.dpm'), 'listed once complete');
  assert.ok(!json.problems.some((p) => p.includes('f.dpm')));
  rmSync(join(dir, 'e.dpm'));
  rmSync(join(dir, 'f.dpm'));
  json = await index(port);
  assert.ok(!json.entries.some((e) => e.path === 'e.dpm' || e.path === 'f.dpm'), 'removed files leave the list');
});

test('thumbnails: the PNG stored at build time, 404 without one', async () => {
  const { port } = served;
  const r = await get(port, '/thumb/runs/b%201.png');
  assert.equal(r.status, 200);
  assert.match(r.head, /Content-Type: image\/png/);
  assert.ok(r.body.subarray(0, 8).equals(Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a])));
  // The same bytes as `dynpm thumbnail -o` draws from the file.
  const png = join(base, 'b.png');
  assert.equal(spawnSync(cli, ['thumbnail', join(dir, 'a.dpm'), '-o', png, '--quiet']).status, 0);
  assert.ok(r.body.equals(readFileSync(png)));
  assert.equal((await get(port, '/thumb/plain.png')).status, 404);
});

test('the page at /, the viewer at /view; the Host check and the policy of dynpm view', async () => {
  const { port } = served;
  const page = await get(port, '/');
  assert.equal(page.status, 200);
  assert.match(page.body.toString(), /src\/catalogue\.js/);
  const viewer = await get(port, '/view?model=/files/a.dpm');
  assert.equal(viewer.status, 200);
  assert.match(viewer.body.toString(), /src\/viewer\.js/);
  for (const r of [page, viewer, await get(port, '/index.json'), await get(port, '/files/a.dpm')]) {
    assert.match(r.head, /Content-Security-Policy: default-src 'self'; script-src 'self';/);
    assert.match(r.head, /X-Content-Type-Options: nosniff/);
  }
  // The page's <meta> policy is the header's, less frame-ancestors (as index.html's).
  const header = page.head.match(/Content-Security-Policy: (.*)/)[1].trim();
  const meta = page.body.toString().match(/http-equiv="Content-Security-Policy" content="([^"]*)"/)[1];
  assert.equal(`${meta}; frame-ancestors 'none'`, header);
  assert.doesNotMatch(readFileSync('src/catalogue.js', 'utf8'), /innerHTML|outerHTML|insertAdjacentHTML|document\.write/);
  for (const host of ['evil.example', `evil.example:${port}`, '127.0.0.1:1']) {
    const r = await raw(port, `GET /index.json HTTP/1.1\r\nHost: ${host}\r\nConnection: close\r\n\r\n`);
    assert.equal(r.status, 403, host);
  }
  const flood = await raw(port, 'GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n' + 'X-Flood: 1\r\n'.repeat(200) + '\r\n');
  assert.equal(flood.status, 431);
  const post = await raw(port, `POST /index.json HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\nConnection: close\r\n\r\n`);
  assert.equal(post.status, 405);
});

test('bad usage: no folder, a file, a taken port', () => {
  const none = spawnSync(cli, ['serve', join(base, 'missing')]);
  assert.equal(none.status, 1);
  assert.match(String(none.stderr), /missing: no such folder/);
  assert.equal(spawnSync(cli, ['serve', join(dir, 'a.dpm')]).status, 1);
  assert.equal(spawnSync(cli, ['serve', dir, '--port', 'x']).status, 2);
  const taken = spawnSync(cli, ['serve', dir, '--port', String(served.port)]);
  assert.equal(taken.status, 1);
  assert.match(String(taken.stderr), /in use/);
});
