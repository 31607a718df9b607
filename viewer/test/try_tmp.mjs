import { chromium } from 'playwright-core';
import { startServer, CHROMIUM_ARGS } from './chromium.mjs';
const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', headless: true, args: CHROMIUM_ARGS });
for (let i = 0; i < 2; i++) {
  const { server, url } = await startServer('../build/test/cli/dynpm', '/tmp/a23c/compare/fine.dpm', ['/tmp/a23c/compare/coarse.dpm']);
  const page = await browser.newPage({ viewport: { width: 1200, height: 600 } });
  page.on('console', (m) => console.log('console', m.type(), m.text()));
  await page.goto(url);
  await page.waitForTimeout(8000);
  console.log(JSON.stringify(await page.evaluate(() => [window.dpmViewer.state(), window.dpmViewer.compare()])));
  await page.close(); server.kill('SIGINT');
}
await browser.close();
