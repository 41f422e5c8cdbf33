// Serves the repository root to 127.0.0.1 (a secure context, so WebGPU and Cache Storage
// work) with the page's content security policy and cross-origin isolation (the threaded CPU
// path): `node web/serve.mjs [PORT] [--no-isolation]`. Prints the page's URL. No dependencies.
import { createServer } from 'node:http';
import { readFile, stat } from 'node:fs/promises';
import { extname, join, normalize, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = resolve(fileURLToPath(new URL('..', import.meta.url)));
const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json',
  '.wasm': 'application/wasm',
  '.png': 'image/png',
  '.ply': 'application/octet-stream',
  '.safetensors': 'application/octet-stream',
};
// Same-origin scripts and wasm compilation only; nothing remote.
export const CSP =
  "default-src 'self'; script-src 'self' 'wasm-unsafe-eval'; worker-src 'self'; " +
  "connect-src 'self'; img-src 'self' blob: data:; style-src 'self'; object-src 'none'; " +
  "base-uri 'none'; form-action 'none'";

// Cross-origin isolation (COOP and COEP): the page may then share memory between workers, so
// its CPU path runs the threaded module on every core (web/lib/index.js). A host serving the
// page should send the same two headers; without them the page falls back to one module per
// worker and says so.
export const ISOLATION = {
  'cross-origin-opener-policy': 'same-origin',
  'cross-origin-embedder-policy': 'require-corp',
};

/**
 * Serves the repository root on 127.0.0.1 at `port` (0: any free one). `isolated` (default
 * true): send [`ISOLATION`]'s headers; false serves the page as a host without them would.
 */
export function serve(port = 0, { isolated = true } = {}) {
  const server = createServer(async (req, res) => {
    try {
      const path = decodeURIComponent(new URL(req.url, 'http://x').pathname);
      let file = normalize(join(ROOT, path));
      if (!file.startsWith(ROOT)) throw Object.assign(new Error('outside'), { code: 'ENOENT' });
      if ((await stat(file)).isDirectory()) file = join(file, 'index.html');
      const body = await readFile(file);
      res.writeHead(200, {
        'content-type': TYPES[extname(file)] ?? 'application/octet-stream',
        'content-length': body.length,
        'content-security-policy': CSP,
        'cache-control': 'no-cache',
        ...(isolated ? ISOLATION : {}),
      });
      res.end(req.method === 'HEAD' ? undefined : body);
    } catch (e) {
      res.writeHead(e.code === 'ENOENT' ? 404 : 500, { 'content-type': 'text/plain' });
      res.end(e.code === 'ENOENT' ? 'not found' : String(e));
    }
  });
  return new Promise((ok, fail) => {
    // A port already taken (often an earlier demo still serving) is the common failure:
    // say which port and how to pick another instead of Node's stack trace.
    server.once('error', (e) =>
      fail(
        e.code === 'EADDRINUSE'
          ? new Error(
              `port ${port} on 127.0.0.1 is already in use (an earlier demo still serving?); ` +
                'pass another: node web/serve.mjs 8081, or MESHFLOW_PORT=8081 bash scripts/demo.sh',
            )
          : e,
      ),
    );
    server.listen(port, '127.0.0.1', () => ok(server));
  });
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  try {
    const args = process.argv.slice(2);
    const port = args.find((a) => !a.startsWith('--'));
    const server = await serve(Number(port ?? 8080), { isolated: !args.includes('--no-isolation') });
    console.log(`MeshFlow: http://127.0.0.1:${server.address().port}/web/`);
  } catch (e) {
    console.error(`MeshFlow: ${e.message}`);
    process.exit(1);
  }
}
