// Two builds of the page side by side in one browser, on the CPU path: each tree's own
// web/serve.mjs serves that tree (its web/pkg and weights), in two tabs. Without cross-origin
// isolation (the default) the tabs are the page on its default workers and with `?workers=1`
// (the candidates on single-threaded modules); with `--isolated` they are the isolated page on
// its threaded module and with `?threads=0` (its workers). The tabs generate in turn, the order
// reversed every other round, and one `meshflow generate --json --backend cpu` process runs
// after each round. Not a test: run by hand on an otherwise idle machine, after building each
// tree's web/pkg,
//   node bench/page_ab.mjs OUT.json ROUNDS TREE_A TREE_B [--input FILE] [--isolated]
// (the lantern scan by default, at the page's defaults). MESHFLOW names the CLI (default
// $CARGO_TARGET_DIR/release/meshflow), CHROMIUM the browser (default /usr/bin/chromium). One
// warm-up generation per tab is not counted. OUT gets every run's click-to-mesh time and
// stage times, and the CLI's process time and stage times; `python3 bench/page_ab_table.py
// OUT.json` prints its table.
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromiumVersion, generateOnCli, generateOnPage, launchBrowser, meshflowBinary, openPage } from './page_timing.mjs';

const ROOT = resolve(fileURLToPath(new URL('..', import.meta.url)));
const args = process.argv.slice(2);
const flag = (name, fallback) => {
  const i = args.indexOf(name);
  return i < 0 ? fallback : args.splice(i, 2)[1];
};
const input = resolve(flag('--input', join(ROOT, 'tests/fixtures/points/stone_lantern_2048.ply')));
const isolated = args.includes('--isolated');
if (isolated) args.splice(args.indexOf('--isolated'), 1);
const [outFile, roundsArg, ...trees] = args;
const rounds = Number(roundsArg);
if (!outFile || !(rounds > 0) || trees.length !== 2) {
  console.error('usage: node bench/page_ab.mjs OUT.json ROUNDS TREE_A TREE_B [--input FILE] [--isolated]');
  process.exit(2);
}
const meshflow = meshflowBinary();

const work = mkdtempSync(join(tmpdir(), 'meshflow-page-ab-'));
const context = await launchBrowser(join(work, 'profile'));
const servers = [];
const tabs = [];
for (const tree of trees.map((t) => resolve(t))) {
  const { serve } = await import(join(tree, 'web/serve.mjs'));
  const server = await serve(0, { isolated });
  servers.push(server);
  for (const query of isolated ? ['', '&threads=0'] : ['', '&workers=1']) {
    const page = await context.newPage();
    await openPage(page, () => page.goto(`http://127.0.0.1:${server.address().port}/web/?backend=cpu${query}`), input);
    // A page from before the workers (2026-12-02) has no `workers` and ignores `?workers=1`.
    const { workers, threads } = await page.evaluate(() => ({ ...document.body.dataset }));
    const kind = threads && threads !== '0' ? `${threads} threads` : workers && query !== '&workers=1' ? `${workers} workers` : 'one module';
    tabs.push({ name: `${tree} ${kind}`, tree, page, runs: [] });
  }
}

for (const tab of tabs) await generateOnPage(tab.page);
const cli = [];
for (let round = 0; round < rounds; round++) {
  for (const tab of round % 2 ? [...tabs].reverse() : tabs) tab.runs.push(await generateOnPage(tab.page));
  cli.push(generateOnCli(meshflow, input, join(work, 'cli.glb')));
  console.log(
    `round ${round + 1}: ` +
      tabs.map((t) => `${t.name} ${t.runs.at(-1).generate_s.toFixed(2)} s (${t.runs.at(-1).faces} faces)`).join(', ') +
      `, CLI ${cli.at(-1).process_s.toFixed(2)} s (${cli.at(-1).faces} faces)`,
  );
}
await context.close();
for (const server of servers) server.close();
rmSync(work, { recursive: true, force: true });
writeFileSync(
  outFile,
  JSON.stringify(
    {
      method: `node bench/page_ab.mjs${isolated ? ' --isolated' : ''}: click to mesh on screen per tab, the CLI process start to GLB written`,
      isolated,
      date: new Date().toISOString(),
      chromium: chromiumVersion(),
      input,
      tabs: tabs.map(({ name, tree, runs }) => ({ name, tree, runs })),
      cli,
    },
    null,
    1,
  ) + '\n',
);
