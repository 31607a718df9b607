// Shared by the browser test and bench/scrub.mjs: how Chromium is started here, and
// `dynpm view` on a free port.
import { spawn } from 'node:child_process';

// As root in a container Chromium needs --no-sandbox; WebGL comes from ANGLE on SwiftShader
// (software Vulkan). The network flags stop it calling out on a machine without a network.
export const CHROMIUM_ARGS = [
  '--no-sandbox',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--disable-quic',
  '--no-first-run',
];

// Starts `dynpm view FILE` (or `dynpm serve DIR`) on a free port; resolves with the process and
// its address.
export function startServer(cli, file, extra = [], verb = 'view') {
  return new Promise((resolve, reject) => {
    const server = spawn(cli, [verb, file, '--port', '0', ...extra], {
      stdio: ['ignore', 'pipe', 'pipe'],
    });
    let text = '';
    const timer = setTimeout(() => reject(new Error(`dynpm ${verb} printed no address: ${text}`)), 30000);
    const onData = (d) => {
      text += d;
      const match = text.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (match) clearTimeout(timer), resolve({ server, url: match[0] });
    };
    server.stdout.on('data', onData);
    server.stderr.on('data', onData);
    server.on('exit', (code) => reject(new Error(`dynpm ${verb} exited with ${code}: ${text}`)));
  });
}

// The whole file decoded and shown: the page steps the level up over a few frames after the
// last splits, so `complete` alone can be seen while the base is still on screen.
export const allShown = () => ((s) => s?.complete && s.navigator && s.vertices === s.loadedVertices)(window.dpmViewer?.state());

// `dynpm view FILE [serverArgs]` and a headless Chromium page on it (`chromium` from
// playwright-core), its console errors (404s aside) and page errors pushed to `errors`; resolves
// with the server, browser, page and address once `ready` (run in the page) holds: by default,
// when the whole file is loaded and shown; `ready: false` returns as soon as the page's HTML is in
// (`waitUntil`, playwright's, default 'load'), to see its first moments.
export async function openViewer(chromium, cli, file, { viewport, errors, ready, timeout = 30000, serverArgs = [], acceptDownloads = true, waitUntil = 'load' }) {
  const { server, url } = await startServer(cli, file, serverArgs);
  const browser = await chromium.launch({
    executablePath: process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    args: CHROMIUM_ARGS,
  });
  const page = await browser.newPage({ viewport, acceptDownloads });
  page.on('console', (m) => m.type() === 'error' && !/404/.test(m.text()) && errors.push(m.text()));
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url, { waitUntil });
  if (ready !== false) await page.waitForFunction(ready ?? allShown, null, { timeout });
  return { server, browser, page, url };
}
