// `dynpm view` as a command: its flags' messages, a second server on a taken port, what
// --export leaves behind when it fails or when DIR exists, and --layout (docs/viewer.md).
import assert from 'node:assert/strict';
import { spawn, spawnSync } from 'node:child_process';
import { mkdirSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, test } from 'node:test';

import { startServer } from './chromium.mjs';

const { DYNPM_CLI: cli, DYNPM_DPM: dpm, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !dpm || !out) throw new Error('cli.test.mjs needs DYNPM_CLI, DYNPM_DPM, DYNPM_TEST_OUT');
const dir = join(out, 'cli');
rmSync(dir, { recursive: true, force: true });
mkdirSync(dir, { recursive: true });

const servers = [];
after(() => servers.forEach((s) => s.kill('SIGTERM')));

const view = (...args) => spawnSync(cli, ['view', dpm, ...args], { encoding: 'utf8', timeout: 10000 });

test('--port and --throttle each say what they take', () => {
  for (const port of ['abc', '70000', '-1', '1.5', '', '65536', '8080x']) {
    const r = view('--port', port);
    assert.equal(r.status, 2, `--port '${port}': ${r.stderr}`);
    assert.match(r.stderr, /--port/);
    assert.match(r.stderr, /0…65535/);
    assert.doesNotMatch(r.stderr, /--throttle/, `--port '${port}'`);
    assert.ok(r.stderr.includes(`'${port}'`), `names the value: ${r.stderr}`);
  }
  for (const rate of ['inf', '1e-300', 'nan', '0', '-5', 'abc', '0.5', '1e12', 'infinity']) {
    const r = view('--port', '0', '--throttle', rate);
    assert.equal(r.status, 2, `--throttle '${rate}': ${r.stderr}`);
    assert.match(r.stderr, /--throttle/);
    assert.match(r.stderr, /1…1048576/);
    assert.doesNotMatch(r.stderr, /--port/, `--throttle '${rate}'`);
  }
});

test('a second dynpm view on a port in use fails with the "in use" message', async () => {
  const { server, url } = await startServer(cli, dpm);
  server.removeAllListeners('exit');
  servers.push(server);
  const port = new URL(url).port;
  const second = spawn(cli, ['view', dpm, '--port', port], { stdio: ['ignore', 'pipe', 'pipe'] });
  servers.push(second);
  let text = '';
  second.stdout.on('data', (d) => (text += d));
  second.stderr.on('data', (d) => (text += d));
  const code = await new Promise((resolve) => {
    const timer = setTimeout(() => resolve('still running'), 3000);
    second.on('exit', (c) => (clearTimeout(timer), resolve(c)));
  });
  assert.equal(code, 1, `the second server: ${code}: ${text}`);
  assert.match(text, new RegExp(`127\\.0\\.0\\.1:${port} \\(in use\\?`));
});

function tree(root) {
  const list = [];
  const walk = (d, prefix) => {
    for (const e of readdirSync(d, { withFileTypes: true }).sort((a, b) => a.name.localeCompare(b.name))) {
      list.push(prefix + e.name + (e.isDirectory() ? '/' : ''));
      if (e.isDirectory()) walk(join(d, e.name), prefix + e.name + '/');
    }
  };
  walk(root, '');
  return list;
}

test('--export writes a new folder, replaces an earlier export, and refuses anything else', () => {
  const target = join(dir, 'export');
  // What a killed export left (its process, 4194304, is above any pid_max): removed.
  mkdirSync(join(dir, 'export.tmp-4194304-0', 'src'), { recursive: true });
  let r = view('--export', target);
  assert.equal(r.status, 0, r.stderr);
  const written = tree(target);
  assert.ok(written.includes('index.html') && written.includes('model.dpm') && written.includes('vendor/'));
  assert.ok(readFileSync(join(target, 'model.dpm')).equals(readFileSync(dpm)));
  // Again into the same folder: an earlier export is replaced.
  r = view('--export', target);
  assert.equal(r.status, 0, r.stderr);
  assert.deepEqual(tree(target), written);
  // An empty folder is fine.
  const empty = join(dir, 'empty');
  mkdirSync(empty);
  assert.equal(view('--export', empty).status, 0);
  assert.deepEqual(tree(empty), written);
  // Nothing of ours left beside them.
  assert.deepEqual(readdirSync(dir).sort(), ['empty', 'export']);
});

test('a failed --export leaves no partial folder and touches nothing of yours', () => {
  // A folder with a file of someone else's: refused, kept as it was.
  const foreign = join(dir, 'foreign');
  mkdirSync(foreign);
  writeFileSync(join(foreign, 'notes.txt'), 'mine');
  let r = view('--export', foreign);
  assert.equal(r.status, 1);
  assert.match(r.stderr, /foreign: .*not an earlier export/);
  assert.deepEqual(tree(foreign), ['notes.txt']);

  // A folder in which the model's place is taken by a folder: the old code wrote the page and
  // then failed on the model, leaving a page without its model.
  const blocked = join(dir, 'blocked');
  mkdirSync(join(blocked, 'model.dpm'), { recursive: true });
  writeFileSync(join(blocked, 'model.dpm', 'keep'), 'x');
  r = view('--export', blocked);
  assert.equal(r.status, 1);
  assert.deepEqual(tree(blocked), ['model.dpm/', 'model.dpm/keep']);

  // Below a file: fails before anything is written.
  writeFileSync(join(dir, 'a-file'), 'x');
  r = view('--export', join(dir, 'a-file', 'sub'));
  assert.equal(r.status, 1);
  assert.match(r.stderr, /a-file/);
  assert.deepEqual(readdirSync(dir).filter((name) => name.includes('.tmp')), [], 'no temporary folder left');
});

test('--layout: with two models it goes into dpm.json for the page; alone, or another value, refused', () => {
  const target = join(out, 'cli-layout');
  rmSync(target, { recursive: true, force: true });
  const both = (...args) => spawnSync(cli, ['view', dpm, dpm, ...args], { encoding: 'utf8', timeout: 10000 });
  let r = both('--layout', 'edges', '--export', target);
  assert.equal(r.status, 0, r.stderr);
  assert.equal(JSON.parse(readFileSync(join(target, 'dpm.json'), 'utf8')).compareLayout, 'edges');
  r = view('--layout', 'edges');
  assert.equal(r.status, 2, r.stderr);
  assert.match(r.stderr, /--layout needs a second model/);
  r = both('--layout', 'stacked');
  assert.equal(r.status, 2, r.stderr);
  assert.match(r.stderr, /--layout is side, edges or surface, got 'stacked'/);
});
