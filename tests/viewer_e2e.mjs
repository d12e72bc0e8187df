// End-to-end test of `linx view` (docs/visualization.md): records runs with `linx run`, serves
// one with `linx view --port 0`, and drives the page in headless Chromium (playwright-core).
// Checks that the page draws, that scrubbing puts the bodies where bodies.csv says, picking,
// toggles, playing, loading a folder (open) and dropped files, contacts, the server's file
// whitelist and host check, its clean stop on SIGTERM, and that no console error appears.
//
// Usage: node tests/viewer_e2e.mjs LINX EXAMPLES_DIR WORK_DIR
// Environment: LINX_VIEWER_NODE_MODULES (the build tree's viewer/node_modules, for
// playwright-core), CHROMIUM (default /usr/bin/chromium), LINX_VIEWER_SCREENSHOT (also save the
// final screenshot there).
import { spawn, spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import http from 'node:http';
import { createRequire } from 'node:module';
import path from 'node:path';

const [linx, examples, work] = process.argv.slice(2);
if (!work) {
  console.error('usage: node viewer_e2e.mjs LINX EXAMPLES_DIR WORK_DIR');
  process.exit(2);
}
const chromiumPath = process.env.CHROMIUM || '/usr/bin/chromium';
const nodeModules = process.env.LINX_VIEWER_NODE_MODULES;

let server = null;
let browser = null;
const step = (text) => console.log(`-- ${text}`);
function check(ok, what) {
  if (!ok) throw new Error(`FAILED: ${what}`);
  console.log(`ok   ${what}`);
}

async function cleanup() {
  if (browser) await browser.close().catch(() => {});
  browser = null;
  if (server && server.exitCode === null && server.signalCode === null) server.kill('SIGKILL');
}
const deadline = setTimeout(async () => {
  console.error('FAILED: the test took longer than 55 s');
  await cleanup();
  process.exit(1);
}, 55_000);

// bodies.csv -> { frames: [{ time, bodies: { name: [x, y, z] } }] } (test names need no quotes).
function readBodies(dir) {
  const lines = readFileSync(path.join(dir, 'bodies.csv'), 'utf8').trim().split('\n');
  const header = lines[0].split(',');
  const [ct, cb, cx] = ['time', 'body', 'x'].map((c) => header.indexOf(c));
  const frames = [];
  for (const line of lines.slice(1)) {
    const r = line.split(',');
    const t = Number(r[ct]);
    if (!frames.length || frames[frames.length - 1].time !== t) frames.push({ time: t, bodies: {} });
    frames[frames.length - 1].bodies[r[cb]] = [Number(r[cx]), Number(r[cx + 1]), Number(r[cx + 2])];
  }
  return frames;
}

function linxRun(scene, out, ...flags) {
  const r = spawnSync(linx, ['run', path.join(examples, scene), '--out', out, ...flags], { encoding: 'utf8' });
  if (r.status !== 0) throw new Error(`linx run ${scene} failed (${r.status}): ${r.stderr}`);
}

// A raw GET (no URL normalization, any Host header): resolves to the status code.
function rawGet(port, target, host) {
  return new Promise((resolve, reject) => {
    const req = http.request({ host: '127.0.0.1', port, path: target, headers: host ? { Host: host } : {} }, (res) => {
      res.resume();
      res.on('end', () => resolve(res.statusCode));
    });
    req.on('error', reject);
    req.end();
  });
}

async function main() {
  if (!nodeModules || !existsSync(path.join(nodeModules, 'playwright-core')))
    throw new Error('playwright-core not found: set LINX_VIEWER_NODE_MODULES to the build tree\'s viewer/node_modules (tests/viewer_e2e.cmake does)');
  if (!existsSync(chromiumPath))
    throw new Error(`Chromium not found at ${chromiumPath}: install the Debian package "chromium" (scripts/install-deps.sh) or set CHROMIUM`);
  const { chromium } = createRequire(path.join(nodeModules, 'noop.js'))('playwright-core');

  rmSync(work, { recursive: true, force: true });
  mkdirSync(work, { recursive: true });
  const slider = path.join(work, 'slider_crank');
  const boxes = path.join(work, 'box');
  step('recording runs');
  linxRun('slider_crank.json', slider, '--every', '10');
  linxRun('box_stack.json', boxes, '--every', '12', '--duration', '2', '--contacts');
  const truth = readBodies(slider);

  step('bad input');
  const missing = spawnSync(linx, ['view', path.join(work, 'no-such-run')], { encoding: 'utf8' });
  check(missing.status === 2 && missing.stderr.length > 0, 'linx view of a missing folder exits 2 with a message');
  const badPort = spawnSync(linx, ['view', slider, '--port', '70000'], { encoding: 'utf8' });
  check(badPort.status === 2 && /--port/.test(badPort.stderr), 'linx view --port 70000 exits 2 naming --port');

  step('starting linx view');
  server = spawn(linx, ['view', slider, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
  let serverErr = '';
  server.stderr.on('data', (d) => { serverErr += d; });
  const url = await new Promise((resolve, reject) => {
    let out = '';
    const t = setTimeout(() => reject(new Error(`no URL from linx view in 15 s; stderr: ${serverErr}`)), 15_000);
    server.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/^linx view: (http:\/\/127\.0\.0\.1:(\d+)\/) \(Ctrl-C to stop\)\n/);
      if (m) {
        clearTimeout(t);
        resolve(m[1]);
      }
    });
    server.on('exit', (code) => reject(new Error(`linx view exited (${code}): ${serverErr}`)));
  });
  const port = Number(new URL(url).port);
  check(port > 0, `linx view printed ${url}`);
  const taken = spawnSync(linx, ['view', slider, '--port', String(port)], { encoding: 'utf8', timeout: 10_000 });
  check(taken.status === 2 && /--port/.test(taken.stderr), 'a second linx view on the same port exits 2');

  step('server');
  const scene = await fetch(`${url}run/scene.json`);
  check(scene.ok && (await scene.json()).format === 'linx-run', 'GET /run/scene.json serves the run\'s scene.json');
  const csv = await (await fetch(`${url}run/bodies.csv`)).text();
  check(csv === readFileSync(path.join(slider, 'bodies.csv'), 'utf8'), 'GET /run/bodies.csv serves bodies.csv as it is');
  check(await rawGet(port, '/run/../../../etc/passwd') === 404, 'GET /run/../../../etc/passwd is 404');
  check(await rawGet(port, '/run/..%2Fbodies.csv') === 404, 'GET /run/..%2Fbodies.csv is 404');
  check(await rawGet(port, '/run/contacts.csv') === 404, 'GET of a run file the run lacks is 404');
  check(await rawGet(port, '/', 'evil.example:80') === 403, 'a request for another host name is 403');

  step('page');
  browser = await chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--no-sandbox'],
  });
  const context = await browser.newContext({ viewport: { width: 1000, height: 650 } });
  const page = await context.newPage();
  const problems = [];
  page.on('console', (m) => {
    if (m.type() === 'error') problems.push(`console error: ${m.text()}`);
  });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  await page.goto(url);
  await page.waitForFunction(() => window.linxViewer && (window.linxViewer.ready || window.linxViewer.error), null, { timeout: 20_000 });
  check(await page.evaluate(() => window.linxViewer.error) === null, 'the page loaded the run without error');
  check(await page.evaluate(() => window.linxViewer.frameCount) === truth.length, `the page has the ${truth.length} frames of bodies.csv`);

  // What the canvas shows, decoded by the browser from a PNG screenshot (independent of the page).
  const decoder = await context.newPage();
  async function pixelStats(png) {
    return decoder.evaluate(async (b64) => {
      const img = new Image();
      img.src = `data:image/png;base64,${b64}`;
      await img.decode();
      const c = document.createElement('canvas');
      c.width = img.width;
      c.height = img.height;
      const g = c.getContext('2d');
      g.drawImage(img, 0, 0);
      const d = g.getImageData(0, 0, c.width, c.height).data;
      const bg = [d[0], d[1], d[2]];  // the top left corner is background
      const colours = new Set();
      let other = 0;
      for (let i = 0; i < d.length; i += 4) {
        colours.add((d[i] >> 3) * 1024 + (d[i + 1] >> 3) * 32 + (d[i + 2] >> 3));
        if (Math.abs(d[i] - bg[0]) + Math.abs(d[i + 1] - bg[1]) + Math.abs(d[i + 2] - bg[2]) > 24) other++;
      }
      return { colours: colours.size, drawn: other / (d.length / 4), digest: Array.from(d.filter((_, i) => i % 97 === 0)).join(',') };
    }, png.toString('base64'));
  }
  const canvas = page.locator('#view canvas');
  const first = await pixelStats(await canvas.screenshot());
  check(first.colours > 30 && first.drawn > 0.01, `the canvas is drawn (${first.colours} colours, ${(first.drawn * 100).toFixed(1)}% not background)`);

  step('scrubbing');
  const near = (a, b) => a && b && a.every((v, i) => Math.abs(v - b[i]) <= 1e-6);
  const drawn = (name) => page.evaluate((n) => window.linxViewer.bodyWorldPosition(n), name);
  check(near(await drawn('piston'), truth[0].bodies.piston), 'frame 0: the piston is drawn where bodies.csv puts it');
  let k = truth.findIndex((f) => Math.abs(f.bodies.piston[0] - truth[0].bodies.piston[0]) > 0.05);
  if (k < 0) k = truth.length - 1;
  await page.locator('#scrub').fill(String(k));
  check(await page.evaluate(() => window.linxViewer.frame) === k, `the slider set frame ${k}`);
  const moved = await drawn('piston');
  check(near(moved, truth[k].bodies.piston), `frame ${k}: the piston is drawn at bodies.csv's ${truth[k].bodies.piston.join(', ')} (within 1e-6)`);
  check(near(await drawn('crank'), truth[k].bodies.crank) && near(await drawn('rod'), truth[k].bodies.rod), `frame ${k}: so are the crank and the rod`);
  check(Math.abs(moved[0] - truth[0].bodies.piston[0]) > 0.05, 'the piston moved');
  check((await page.locator('#time').textContent()).includes(truth[k].time.toFixed(3)), 'the clock shows the frame\'s time');
  const scrubbed = await pixelStats(await canvas.screenshot());
  check(scrubbed.digest !== first.digest, 'the picture changed');

  step('picking');
  const [px, py] = await page.evaluate(() => window.linxViewer.bodyScreenPosition('piston'));
  await page.mouse.click(px, py);
  await page.locator('#selection').waitFor({ state: 'visible', timeout: 5000 });
  check(await page.locator('#sel-name').textContent() === 'piston', 'clicking the piston shows its name');
  const info = await page.locator('#sel-table').textContent();
  check(info.includes(truth[k].bodies.piston[0].toFixed(4)), 'and its position at the current frame');
  await page.keyboard.press('Escape');
  check(await page.locator('#selection').isHidden(), 'Escape clears the selection');

  step('toggles');
  check((await page.evaluate(() => window.linxViewer.layers())).jointMarkers === 8, 'joint markers at the anchors of the 4 joints');
  const withJoints = await pixelStats(await canvas.screenshot());
  await page.locator('#show-joints').uncheck();
  check(!(await page.evaluate(() => window.linxViewer.layers())).joints, 'unchecking "joints" hides the joints');
  const noJoints = await pixelStats(await canvas.screenshot());
  check(noJoints.digest !== withJoints.digest, 'the picture changed');
  await page.locator('#show-joints').check();
  check((await page.evaluate(() => window.linxViewer.layers())).joints, 'checking it shows them again');
  check(await page.locator('#show-contacts').isDisabled(), 'the contacts toggle is off for a run without contacts.csv');

  step('playing');
  await page.locator('#speed').selectOption('2');
  const before = await page.evaluate(() => window.linxViewer.frame);
  await page.locator('#play').click();
  await page.waitForFunction((f) => window.linxViewer.frame !== f, before, { timeout: 5000 });
  await page.locator('#play').click();
  check(!(await page.evaluate(() => window.linxViewer.playing)), 'play advances the frames, pause stops');
  if (process.env.LINX_VIEWER_SCREENSHOT) await page.screenshot({ path: process.env.LINX_VIEWER_SCREENSHOT });

  step('opening a run\'s files, with contacts');
  // (Without webkitdirectory: Playwright's folder upload does not work with Debian's Chromium.)
  await page.evaluate(() => document.getElementById('open-input').removeAttribute('webkitdirectory'));
  await page.locator('#open-input').setInputFiles(['scene.json', 'bodies.csv', 'joints.csv', 'world.csv',
    'contacts.csv'].map((f) => path.join(boxes, f)));
  await page.waitForFunction(() => window.linxViewer.runName === 'opened run', null, { timeout: 10_000 });
  const boxTruth = readBodies(boxes);
  check(await page.evaluate(() => window.linxViewer.frameCount) === boxTruth.length, 'the opened run replaced the served one');
  const contactRows = readFileSync(path.join(boxes, 'contacts.csv'), 'utf8').trim().split('\n').slice(1);
  const lastTime = boxTruth[boxTruth.length - 1].time;
  const expected = contactRows.filter((r) => Number(r.split(',')[0]) === lastTime).length;
  await page.evaluate((n) => window.linxViewer.setFrame(n), boxTruth.length - 1);
  const layers = await page.evaluate(() => window.linxViewer.layers());
  check(expected > 0 && layers.contactPoints === expected && layers.contacts, `last frame: ${expected} contact points drawn, as in contacts.csv`);
  check(near(await drawn('box5'), boxTruth[boxTruth.length - 1].bodies.box5) || !boxTruth[0].bodies.box5, 'the boxes are drawn where bodies.csv puts them');
  await page.locator('#show-contacts').uncheck();
  check(!(await page.evaluate(() => window.linxViewer.layers())).contacts, 'unchecking "contacts" hides them');
  await page.screenshot({ path: path.join(work, 'viewer-box.png') });

  step('dropping files');
  const texts = Object.fromEntries(['scene.json', 'bodies.csv', 'joints.csv', 'world.csv']
    .map((f) => [f, readFileSync(path.join(slider, f), 'utf8')]));
  await page.evaluate((files) => {
    const dt = new DataTransfer();
    for (const [name, text] of Object.entries(files)) dt.items.add(new File([text], name));
    window.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
  }, texts);
  await page.waitForFunction(() => window.linxViewer.runName === 'dropped run', null, { timeout: 10_000 });
  check(await page.evaluate(() => window.linxViewer.frameCount) === truth.length, 'dropped files are loaded');
  await page.evaluate(() => {
    const dt = new DataTransfer();
    dt.items.add(new File(['x'], 'notes.txt'));
    window.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
  });
  await page.locator('#message.error').waitFor({ state: 'visible', timeout: 5000 });
  check((await page.locator('#message').textContent()).includes('scene.json'), 'dropping files without scene.json says so');
  check(await page.evaluate(() => window.linxViewer.frameCount) === truth.length, 'and keeps the run shown');

  await page.screenshot({ path: path.join(work, 'viewer.png') });
  check(problems.length === 0, `no console error or page error${problems.length ? `:\n  ${problems.join('\n  ')}` : ''}`);
  await browser.close();
  browser = null;

  step('stopping');
  const status = await new Promise((resolve) => {
    server.on('exit', (code, signal) => resolve(signal ? `signal ${signal}` : code));
    server.kill('SIGTERM');
  });
  check(status === 0, `linx view exits 0 on SIGTERM (got ${status})`);
  server = null;
}

main().then(async () => {
  clearTimeout(deadline);
  console.log('viewer e2e: all checks passed');
}, async (e) => {
  console.error(e.message || e);
  await cleanup();
  process.exit(1);
});
