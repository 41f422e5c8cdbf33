// Candidates drawn side by side on the CPU path: a generation's candidates (`samples`, 12 by
// default) are independent, so helper workers, each with its own wasm module and copy of the
// models, draw runs of them while the caller's module draws the first run; the caller's module
// then keeps the best and sharpens it. Candidate j is seeded from the seed and j in whichever
// run it is drawn, so the mesh is the one a single module (or `meshflow generate`) makes. The
// path for pages that are not cross-origin isolated: workers need no SharedArrayBuffer, so every
// host gets them; isolated pages run the threaded module instead (web/lib/index.js).

// Helper workers to start at most (each holds a copy of the models, about 60 MB).
export const MAX_HELPERS = 3;
// A helper that has not loaded its models by then is given up on.
const START_TIMEOUT_MS = 60_000;

/** One helper worker with its own CPU module and models. */
class CandidateWorker {
  #worker;
  #pending = new Map();
  #next = 0;

  constructor(worker) {
    this.#worker = worker;
    worker.onmessage = ({ data }) => {
      const job = this.#pending.get(data.id);
      if (!job) return;
      this.#pending.delete(data.id);
      if (data.type === 'drawn') job.resolve(data.bytes);
      else job.reject(Object.assign(new Error(data.message), { fromModel: true }));
    };
    worker.onerror = (e) => this.#failAll(new Error(`a candidate worker failed: ${e.message ?? 'unknown error'}`));
  }

  /** Starts a helper and loads the models (`files`, the four weight files) into it. */
  static start(files, wasmUrl) {
    return new Promise((resolve, reject) => {
      let worker;
      try {
        worker = new Worker(new URL('./candidates-worker.js', import.meta.url), { type: 'module' });
      } catch (e) {
        reject(e);
        return;
      }
      const timer = setTimeout(() => {
        worker.terminate();
        reject(new Error(`no answer in ${START_TIMEOUT_MS / 1000} s`));
      }, START_TIMEOUT_MS);
      worker.onmessage = ({ data }) => {
        clearTimeout(timer);
        if (data.type === 'ready') {
          resolve(new CandidateWorker(worker));
        } else {
          worker.terminate();
          reject(new Error(data.message));
        }
      };
      worker.onerror = (e) => {
        clearTimeout(timer);
        worker.terminate();
        reject(new Error(e.message || 'the worker script did not start'));
      };
      worker.postMessage({ type: 'load', files, wasmUrl: wasmUrl ? String(wasmUrl) : undefined });
    });
  }

  /** Candidates `first..first + count` as the bytes of `generateCandidates`. */
  draw(points, options, first, count) {
    const id = this.#next++;
    return new Promise((resolve, reject) => {
      this.#pending.set(id, { resolve, reject });
      this.#worker.postMessage({ type: 'draw', id, points, options, first, count });
    });
  }

  /** Stops the runs in progress between sampler steps (they reject as cancelled). */
  cancel() {
    this.#worker.postMessage({ type: 'cancel' });
  }

  terminate() {
    this.#worker.terminate();
    this.#failAll(new Error('the candidate worker was stopped'));
  }

  #failAll(error) {
    for (const job of this.#pending.values()) job.reject(error);
    this.#pending.clear();
  }
}

/**
 * Starts up to `count` helpers, each with a copy of the weight `files`. Resolves to
 * `{ helpers, failed }`: those that loaded, and why the others did not (empty when all did).
 */
export async function startHelpers(count, files, wasmUrl) {
  if (count <= 0) return { helpers: [], failed: [] };
  if (typeof Worker !== 'function') return { helpers: [], failed: ['this context cannot start workers'] };
  const settled = await Promise.allSettled(Array.from({ length: count }, () => CandidateWorker.start(files, wasmUrl)));
  return {
    helpers: settled.filter((s) => s.status === 'fulfilled').map((s) => s.value),
    failed: settled.filter((s) => s.status === 'rejected').map((s) => s.reason?.message ?? String(s.reason)),
  };
}

/** `samples` candidates split into `parts` consecutive runs `{ first, count }`, as even as can be. */
export function splitRuns(samples, parts) {
  const n = Math.max(1, Math.min(parts, samples));
  const runs = [];
  let first = 0;
  for (let k = 0; k < n; k++) {
    const count = Math.floor(samples / n) + (k < samples % n ? 1 : 0);
    runs.push({ first, count });
    first += count;
  }
  return runs;
}

/**
 * The mesh of `inner.generate(points, options, onStep)`, its candidates drawn by `inner` (the
 * first run, reporting `onStep`) and `helpers` (one run each) side by side. The model's errors
 * reject (the first run's first); a helper whose worker dies is dropped (`onHelperLost(helper,
 * error)`) and its run drawn by `inner`; `signal` cancels them all. Resolves to `inner.keepCandidates`'s mesh.
 */
export async function generateSideBySide(inner, helpers, points, options, samples, onStep, signal, onHelperLost) {
  const runs = splitRuns(samples, 1 + helpers.length);
  const stop = () => helpers.forEach((h) => h.cancel());
  signal?.addEventListener('abort', stop, { once: true });
  // The model's own errors (bad input, cancelling) are the generation's; only a worker that
  // died is dropped and its run drawn here.
  const ownError = (e) => signal?.aborted || e?.fromModel;
  try {
    const own = inner.generateCandidates(points, options, runs[0].first, runs[0].count, onStep);
    const others = runs.slice(1).map(({ first, count }, k) =>
      helpers[k].draw(points, options, first, count).catch((e) => {
        if (ownError(e)) throw e;
        onHelperLost(helpers[k], e);
        return inner.generateCandidates(points, options, first, count, () => !signal?.aborted);
      }),
    );
    // Every run settles before the promise does, so no helper is still drawing afterwards.
    const settled = await Promise.allSettled([own, ...others]);
    const failure = settled.find((s) => s.status === 'rejected');
    if (failure) throw failure.reason;
    return inner.keepCandidates(points, options, settled.map((s) => s.value));
  } finally {
    signal?.removeEventListener('abort', stop);
  }
}
