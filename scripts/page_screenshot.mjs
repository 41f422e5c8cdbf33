// The screenshot at the top of README.md (docs/web/page.png): the page in Debian's headless
// Chromium, driven by playwright-core the way tests/e2e/browser.test.mjs drives it.
//   bash scripts/build-web.sh                      # once: web/pkg/
//   node scripts/page_screenshot.mjs [OUT.png]     # default docs/web/page.png
// Serves the repository root (web/serve.mjs), opens /web/?backend=cpu in a 1280x800 viewport
// (no WebGPU flags: the CPU path inside WebAssembly, drawn by the wgpu viewer on WebGL2), picks the bundled
// milk-truck example (web/examples/examples.json), generates at the page's defaults with the
// input points overlay on (orange points over the mesh), saves a full-page screenshot (1280
// wide, tall enough for the stats table) and prints the stats the page shows. CHROMIUM
// overrides the browser (default /usr/bin/chromium), as in the browser test.
import { chromium } from 'playwright-core';
import { readFileSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from '../web/serve.mjs';

const ROOT = resolve(fileURLToPath(new URL('..', import.meta.url)));
const OUT = resolve(process.argv[2] ?? join(ROOT, 'docs/web/page.png'));
const TIMEOUT = 600_000;

const examples = JSON.parse(readFileSync(join(ROOT, 'web/examples/examples.json'), 'utf8'));
const truck = examples.find((e) => /milk.?truck/i.test(e.file));
if (!truck) throw new Error('no milk-truck example in web/examples/examples.json');

const server = await serve(0);
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox'],
});
try {
  const context = await browser.newContext({ viewport: { width: 1280, height: 800 } });
  const page = await context.newPage();
  page.on('pageerror', (e) => console.error(`pageerror: ${e.message}`));
  await page.goto(`http://127.0.0.1:${server.address().port}/web/?backend=cpu`);
  await page.waitForFunction(() => document.body.dataset.backend, null, { timeout: TIMEOUT });
  const backend = await page.evaluate(() => document.body.dataset.backend);
  if (backend !== 'cpu') throw new Error(`backend ${backend}, not cpu`);

  // The example list is filled from examples.json after the page loads.
  await page.waitForSelector(`#example option[value="${truck.file}"]`, { state: 'attached' });
  await page.selectOption('#example', truck.file);
  await page.waitForFunction((f) => document.getElementById('input-info').textContent.startsWith(`${f}:`), truck.file);

  // The overlay is on by default; make sure of it (the toggle updates the viewer on change).
  if (!(await page.isChecked('#show-points'))) await page.check('#show-points');

  // The page's defaults: no vertex or face count, its steps and seed; just Generate.
  const before = Number(await page.evaluate(() => document.body.dataset.generated ?? 0));
  const t0 = Date.now();
  await page.click('#generate');
  await page.waitForFunction(
    (n) => Number(document.body.dataset.generated ?? 0) > n || !document.getElementById('error').hidden,
    before,
    { timeout: TIMEOUT },
  );
  const wall = (Date.now() - t0) / 1000;
  if (await page.isVisible('#error')) throw new Error(`the page says: ${await page.textContent('#error')}`);
  if (!(await page.isChecked('#show-points'))) throw new Error('the points overlay is off');
  // The worker's frame (its OffscreenCanvas) reaches the page's compositor after the message
  // that the mesh is done: give it a moment before the screenshot.
  await page.waitForTimeout(1000);
  // The whole page: the stats table runs below the 800-pixel fold.
  await page.screenshot({ path: OUT, fullPage: true });

  // The stats table as shown, row by row.
  const rows = Object.fromEntries(
    await page.$$eval('#stats tr', (trs) => trs.map((tr) => [tr.dataset.key, tr.cells[1].textContent])),
  );
  const report = await page.evaluate(() => window.__meshflowReport);
  const [vertices, faces] = rows['vertices / faces'].split('/').map((s) => s.trim());
  const [, holes] = rows['boundary edges / holes'].split('/').map((s) => s.trim());
  const stages = ['condition', 'sample', 'decode', 'extract', 'fit'];
  const total = stages.reduce((s, k) => s + report.times[`${k}_s`], 0);
  console.log(`example: ${truck.file} (${await page.textContent('#input-info')})`);
  console.log(`backend: ${backend} (${await page.textContent('#backend')})`);
  console.log(`vertex budget: ${rows['vertex budget']}`);
  console.log(`vertices: ${vertices}`);
  console.log(`faces: ${faces}`);
  console.log(`components (pieces): ${rows.components}`);
  console.log(`holes: ${holes} (boundary edges: ${rows['boundary edges / holes'].split('/')[0].trim()})`);
  console.log(`non-manifold edges: ${rows['non-manifold edges']}`);
  console.log(`inconsistent winding: ${rows['inconsistent winding']}, degenerate faces: ${rows['degenerate faces']}`);
  console.log(`time: ${total.toFixed(2)} s (${stages.map((k) => `${k} ${rows[k]}`).join(', ')}); click to mesh ${wall.toFixed(2)} s`);
  console.log(`screenshot: ${OUT}`);
  await context.close();
} finally {
  await browser.close();
  server.close();
}
