// Makes docs/images/viewer.png (docs/visualization.md, "Browser viewer"): box_stack in linx view,
// at t = 3.5 s with its contacts, box7 selected. Run from the repository, after scripts/test.sh:
//   build/linx run examples/box_stack.json --out out/box_stack --every 10 --contacts
//   LINX_VIEWER_NODE_MODULES=build/viewer/node_modules node docs/images/viewer_shot.mjs \
//       build/linx out/box_stack docs/images/viewer.png
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import path from 'node:path';

const [linx, run, out] = process.argv.slice(2);
const require = createRequire(path.resolve(process.env.LINX_VIEWER_NODE_MODULES, 'x.js'));
const { chromium } = require('playwright-core');

const server = spawn(linx, ['view', run], { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((resolve) => {
  let text = '';
  server.stdout.on('data', (d) => {
    text += d;
    const m = text.match(/(http:\/\/127\.0\.0\.1:\d+\/)/);
    if (m) resolve(m[1]);
  });
});
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--no-sandbox'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1000, height: 650 } });
  await page.goto(url);
  await page.waitForFunction(() => window.linxViewer && window.linxViewer.ready);
  await page.evaluate(() => window.linxViewer.setFrame(42));
  const [x, y] = await page.evaluate(() => window.linxViewer.bodyScreenPosition('box7'));
  await page.mouse.click(x, y);
  await page.waitForTimeout(300);
  await page.screenshot({ path: out });
  console.log(`wrote ${out}`);
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
