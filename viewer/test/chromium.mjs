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

// Starts `dynpm view` on a free port; resolves with the process and its address.
export function startServer(cli, file, extra = []) {
  return new Promise((resolve, reject) => {
    const server = spawn(cli, ['view', file, '--port', '0', ...extra], {
      stdio: ['ignore', 'pipe', 'pipe'],
    });
    let text = '';
    const timer = setTimeout(() => reject(new Error(`dynpm view printed no address: ${text}`)), 10000);
    const onData = (d) => {
      text += d;
      const match = text.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (match) clearTimeout(timer), resolve({ server, url: match[0] });
    };
    server.stdout.on('data', onData);
    server.stderr.on('data', onData);
    server.on('exit', (code) => reject(new Error(`dynpm view exited with ${code}: ${text}`)));
  });
}
