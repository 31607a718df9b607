// `dynpm view`'s HTTP server against the loads and requests of issue 16 (docs/viewer.md
// "Security and limits"): many parallel fetches, slow clients, a flood of header lines, a
// foreign Host, a range past the end, and the model file rebuilt while it is being served.
// Plain sockets where a browser's fetch cannot say what the test needs (Host, slow bytes).
import assert from 'node:assert/strict';
import { copyFileSync, mkdirSync, openSync, readFileSync, renameSync, rmSync, statSync, ftruncateSync, closeSync, writeFileSync } from 'node:fs';
import { connect } from 'node:net';
import { join } from 'node:path';
import { after, test } from 'node:test';

import { startServer } from './chromium.mjs';

const { DYNPM_CLI: cli, DYNPM_DPM: dpm, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !dpm || !out) throw new Error('server.test.mjs needs DYNPM_CLI, DYNPM_DPM, DYNPM_TEST_OUT');
const dir = join(out, 'server');
rmSync(dir, { recursive: true, force: true });
mkdirSync(dir, { recursive: true });
const model = readFileSync(dpm);

const servers = [];
after(() => servers.forEach((s) => s.kill('SIGTERM')));

async function start(file, extra = []) {
  const { server, url } = await startServer(cli, file, extra);
  server.removeAllListeners('exit');
  servers.push(server);
  return { server, url, port: Number(new URL(url).port) };
}

// Sends `text` on a fresh connection and collects everything until the server closes it:
// { status, head, body } (status 0 when nothing came back), or { error } on a reset.
function raw(port, text, { timeout = 5000 } = {}) {
  return new Promise((resolve) => {
    const socket = connect(port, '127.0.0.1');
    const chunks = [];
    let error = null;
    const timer = setTimeout(() => socket.destroy(new Error('timeout')), timeout);
    socket.on('data', (d) => chunks.push(d));
    socket.on('error', (e) => (error = e));
    socket.on('close', () => {
      clearTimeout(timer);
      const all = Buffer.concat(chunks);
      const end = all.indexOf('\r\n\r\n');
      const head = end < 0 ? all.toString('latin1') : all.subarray(0, end).toString('latin1');
      const status = Number(head.match(/^HTTP\/1\.[01] (\d{3})/)?.[1] ?? 0);
      resolve({ status, head, body: end < 0 ? Buffer.alloc(0) : all.subarray(end + 4), error });
    });
    socket.write(text);
  });
}
const get = (port, path, headers = '') =>
  raw(port, `GET ${path} HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\n${headers}Connection: close\r\n\r\n`);

function rssKiB(pid, field = 'VmRSS') {
  const m = readFileSync(`/proc/${pid}/status`, 'utf8').match(new RegExp(`${field}:\\s+(\\d+) kB`));
  return Number(m[1]);
}

test('200 parallel fetches of the model all get the whole file', async () => {
  const { url } = await start(dpm);
  const results = await Promise.all(
    Array.from({ length: 200 }, async () => {
      const r = await fetch(url + 'model.dpm');
      return { status: r.status, body: Buffer.from(await r.arrayBuffer()) };
    }),
  );
  for (const r of results) {
    assert.equal(r.status, 200);
    assert.ok(r.body.equals(model), `a body of ${r.body.length} bytes, expected ${model.length}`);
  }
});

test('12 slow clients do not hold up a normal fetch (answered within 1 s)', async () => {
  const { url, port } = await start(dpm);
  const slow = Array.from({ length: 12 }, () => {
    const s = connect(port, '127.0.0.1');
    s.on('error', () => {});
    s.write(`GET / HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\n`);
    const timer = setInterval(() => s.write('X'), 1000);
    return { s, timer };
  });
  try {
    await new Promise((r) => setTimeout(r, 1500));
    for (let i = 0; i < 3; i++) {
      const begin = performance.now();
      const r = await fetch(url + 'model.dpm', { signal: AbortSignal.timeout(1000) });
      const body = Buffer.from(await r.arrayBuffer());
      const ms = performance.now() - begin;
      assert.equal(r.status, 200);
      assert.ok(body.equals(model));
      assert.ok(ms < 1000, `fetch took ${ms.toFixed(0)} ms`);
      console.log(`with 12 slow clients: a fetch of the model in ${ms.toFixed(0)} ms`);
    }
  } finally {
    for (const { s, timer } of slow) clearInterval(timer), s.destroy();
  }
});

test('300 idle connections (more than the server keeps) do not lock out a fetch', async () => {
  const { url, port } = await start(dpm);
  const idle = await Promise.all(
    Array.from({ length: 300 }, () => new Promise((resolve) => {
      const s = connect(port, '127.0.0.1', () => resolve(s));
      s.on('error', () => {});
    })),
  );
  try {
    await new Promise((r) => setTimeout(r, 300));
    const r = await fetch(url + 'model.dpm', { signal: AbortSignal.timeout(1000) });
    assert.equal(r.status, 200);
    assert.ok(Buffer.from(await r.arrayBuffer()).equals(model));
  } finally {
    idle.forEach((s) => s.destroy());
  }
});

test('200,000 header lines are refused without the server growing', async () => {
  const { server, port } = await start(dpm);
  await get(port, '/');  // settle the first-request allocations
  const before = rssKiB(server.pid);
  const flood = `GET / HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\n` + 'X-Flood: 1\r\n'.repeat(200000) + '\r\n';
  const r = await raw(port, flood, { timeout: 20000 });
  const grown = rssKiB(server.pid, 'VmHWM') - before;
  console.log(`200,000 header lines: answered ${r.status || 'nothing (closed)'}, peak RSS +${grown} KiB`);
  assert.ok(r.status === 431 || r.status === 0, `answered ${r.status}`);
  assert.ok(grown < 4096, `peak RSS grew by ${grown} KiB`);
  assert.equal((await get(port, '/dpm.json')).status, 200, 'still serving');
});

test('a Host other than 127.0.0.1, localhost or [::1] on our port is refused', async () => {
  const { port } = await start(dpm);
  for (const host of [`evil.example:${port}`, 'evil.example', `127.0.0.1:${port + 1}`, `localhost.evil.example:${port}`]) {
    const r = await raw(port, `GET /model.dpm HTTP/1.1\r\nHost: ${host}\r\nConnection: close\r\n\r\n`);
    assert.ok(r.status === 403 || r.status === 400, `Host ${host}: ${r.status}`);
    assert.ok(r.body.length < 200, 'no model bytes');
  }
  const missing = await raw(port, 'GET / HTTP/1.1\r\nConnection: close\r\n\r\n');
  assert.equal(missing.status, 400, 'no Host');
  for (const host of [`127.0.0.1:${port}`, `localhost:${port}`, `[::1]:${port}`]) {
    const r = await raw(port, `GET /model.dpm HTTP/1.1\r\nHost: ${host}\r\nConnection: close\r\n\r\n`);
    assert.equal(r.status, 200, `Host ${host}`);
    assert.ok(r.body.equals(model));
  }
});

test('ranges: inside the file 206, past the end 416', async () => {
  const { port } = await start(dpm);
  const n = model.length;
  const part = await get(port, '/model.dpm', 'Range: bytes=8-15\r\n');
  assert.equal(part.status, 206);
  assert.match(part.head, new RegExp(`content-range: bytes 8-15/${n}`, 'i'));
  assert.ok(part.body.equals(model.subarray(8, 16)));
  const tail = await get(port, '/model.dpm', 'Range: bytes=-4\r\n');
  assert.equal(tail.status, 206);
  assert.ok(tail.body.equals(model.subarray(n - 4)));
  for (const range of [`bytes=${n}-`, `bytes=${n + 100}-${n + 200}`, 'bytes=-0']) {
    const r = await get(port, '/model.dpm', `Range: ${range}\r\n`);
    assert.equal(r.status, 416, range);
    assert.match(r.head, new RegExp(`content-range: bytes \\*/${n}`, 'i'));
  }
});

test('ranges as the viewer asks them: open or past the end, HEAD, consecutive pieces; bad ones whole', async () => {
  const { port } = await start(dpm);
  const n = model.length;
  const open = await get(port, '/model.dpm', `Range: bytes=${n - 10}-\r\n`);
  assert.equal(open.status, 206);
  assert.match(open.head, new RegExp(`content-range: bytes ${n - 10}-${n - 1}/${n}`, 'i'));
  assert.ok(open.body.equals(model.subarray(n - 10)));
  // A last byte past the end is the end (the viewer asks for a chunk and the header after it).
  const past = await get(port, '/model.dpm', `Range: bytes=${n - 5}-${n + 1000}\r\n`);
  assert.equal(past.status, 206);
  assert.match(past.head, /content-length: 5\r?$/im);
  assert.ok(past.body.equals(model.subarray(n - 5)));
  const head = await raw(port, `HEAD /model.dpm HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\nRange: bytes=0-99\r\nConnection: close\r\n\r\n`);
  assert.equal(head.status, 206);
  assert.match(head.head, /content-length: 100\r?$/im);
  assert.equal(head.body.length, 0);
  // The file in consecutive pieces of 7,919 bytes is the file.
  const pieces = [];
  for (let at = 0; at < n; at += 7919) {
    const r = await get(port, '/model.dpm', `Range: bytes=${at}-${Math.min(n, at + 7919) - 1}\r\n`);
    assert.equal(r.status, 206, `bytes ${at}-`);
    pieces.push(r.body);
  }
  assert.ok(Buffer.concat(pieces).equals(model));
  // What a server may ignore (RFC 9110) is served whole: several ranges, last < first, not
  // numbers, another unit.
  for (const range of ['bytes=0-1,4-5', 'bytes=9-3', 'bytes=a-b', 'bytes=--1', 'items=0-1', 'bytes 0-1']) {
    const r = await get(port, '/model.dpm', `Range: ${range}\r\n`);
    assert.equal(r.status, 200, range);
    assert.ok(r.body.equals(model), range);
  }
});

// Reads a response body piece by piece; `during` runs after the first piece.
async function fetchWhile(url, during) {
  const r = await fetch(url);
  const length = Number(r.headers.get('content-length'));
  const reader = r.body.getReader();
  const pieces = [];
  let ran = false;
  try {
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      pieces.push(value);
      if (!ran) (ran = true), during();
    }
  } catch (e) {
    return { status: r.status, length, error: e };
  }
  return { status: r.status, length, body: Buffer.concat(pieces) };
}

test('a model rebuilt while served: never a 200 with a prefix of the new file', async () => {
  const file = join(dir, 'rebuilt.dpm');
  copyFileSync(dpm, file);
  // The rebuilt model: another, larger file (dynpm build writes a temporary and renames it).
  const rebuilt = Buffer.concat([model, Buffer.alloc(50000, 7)]);
  const { url } = await start(file, ['--throttle', '100']);
  const first = await fetchWhile(url + 'model.dpm', () => {
    writeFileSync(file + '.new', rebuilt);
    renameSync(file + '.new', file);
  });
  // The transfer under way finishes with the file it started with.
  assert.equal(first.error, undefined);
  assert.equal(first.length, model.length);
  assert.ok(first.body.equals(model), 'the old file, whole');
  // The next fetch gets the new file, whole, with its own length.
  const second = await fetch(url + 'model.dpm');
  const body = Buffer.from(await second.arrayBuffer());
  assert.equal(Number(second.headers.get('content-length')), rebuilt.length);
  assert.ok(body.equals(rebuilt), `${body.length} bytes, expected the rebuilt ${rebuilt.length}`);

  // Truncated in place while served: the transfer fails rather than ending short with 200.
  copyFileSync(dpm, file);
  const cut = await fetchWhile(url + 'model.dpm', () => {
    const fd = openSync(file, 'r+');
    ftruncateSync(fd, 1000);
    closeSync(fd);
  });
  assert.ok(cut.error || cut.body.equals(model), `a ${cut.body?.length}-byte body ended without error`);
  assert.equal(statSync(file).size, 1000);
});
