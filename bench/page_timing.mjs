// What the page benches share (bench/page_vs_cli.mjs, bench/page_ab.mjs): opening the page on
// an input, timing one generation click to mesh, and timing one `meshflow generate` process on
// the same input. Not a bench itself.
import { chromium } from 'playwright-core';
import { execFileSync } from 'node:child_process';
import { homedir } from 'node:os';
import { join } from 'node:path';

/** The stage times both the page's report and the CLI's JSON carry. */
export const STAGES = ['condition_s', 'sample_s', 'decode_s', 'extract_s', 'fit_s'];

/** The release CLI: MESHFLOW, else the build in CARGO_TARGET_DIR (the scripts' cache folder by default). */
export const meshflowBinary = () =>
  process.env.MESHFLOW ?? join(process.env.CARGO_TARGET_DIR ?? join(homedir(), '.cache/meshflow/target'), 'release/meshflow');

const chromiumPath = () => process.env.CHROMIUM ?? '/usr/bin/chromium';

/** The browser's version line, for a result's method. */
export const chromiumVersion = () => execFileSync(chromiumPath(), ['--version'], { encoding: 'utf8' }).trim();

/** Headless Chromium (CHROMIUM, default /usr/bin/chromium) on a fresh profile in `profile`. */
export const launchBrowser = (profile) =>
  chromium.launchPersistentContext(profile, { executablePath: chromiumPath(), headless: true, args: ['--no-sandbox'] });

/** The median of `xs` (the upper one of an even count). */
export const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];

/**
 * Navigates `page` with `navigate` (a goto or a reload), waits for the model and picks `input`;
 * returns the seconds from navigation to the model being ready.
 */
export async function openPage(page, navigate, input) {
  const start = Date.now();
  await navigate();
  await page.waitForFunction(() => document.body.dataset.backend, null, { timeout: 600_000 });
  const ready = (Date.now() - start) / 1000;
  await page.setInputFiles('#file', input);
  await page.waitForFunction(() => document.getElementById('input-info').textContent.includes('points'));
  return ready;
}

/**
 * One generation on `page`, click to mesh on screen: its time, the page's stage times and the
 * mesh's size. The tab is brought to the front first: Chromium lowers a background tab's
 * priority, which took the two-worker page from 3.5 to 5.1 s in two of three rounds (2026-12-04).
 */
export async function generateOnPage(page) {
  await page.bringToFront();
  const before = Number(await page.evaluate(() => document.body.dataset.generated ?? 0));
  const clicked = Date.now();
  await page.click('#generate');
  await page.waitForFunction((n) => Number(document.body.dataset.generated ?? 0) > n, before, { timeout: 1_800_000 });
  const generate_s = (Date.now() - clicked) / 1000;
  const report = await page.evaluate(() => window.__meshflowReport);
  return {
    generate_s,
    weights_from_cache: (await page.evaluate(() => document.body.dataset.weightsFromCache)) === 'true',
    stages_s: Object.fromEntries(STAGES.map((k) => [k, report.times[k]])),
    vertices: report.topology.vertices,
    faces: report.topology.faces,
  };
}

/**
 * One `meshflow generate INPUT -o OUT --json --backend cpu` process at the defaults, start to
 * GLB written, with `env` added to the environment: its time, stage times and mesh size.
 */
export function generateOnCli(meshflow, input, out, env = {}) {
  const start = process.hrtime.bigint();
  const stdout = execFileSync(meshflow, ['generate', input, '-o', out, '--json', '--backend', 'cpu'], {
    encoding: 'utf8',
    env: { ...process.env, ...env },
  });
  const process_s = Number(process.hrtime.bigint() - start) / 1e9;
  const r = JSON.parse(stdout.trim().split('\n').pop());
  return {
    process_s,
    load_s: r.load_s,
    stages_s: Object.fromEntries(STAGES.map((k) => [k, r.times[k]])),
    vertices: r.topology.vertices,
    faces: r.topology.faces,
  };
}
