"""Drives the web page in headless Chromium over the DevTools protocol and times generations.

Used by bench/page_gpu/run.sh on a GPU machine, which has Python but no Node (and no room in
its transfer for one), so this stands in for playwright there; bench/browser.mjs and
bench/page_vs_cli.mjs do the same on machines with Node. Needs `websocket-client` (pure
Python; run.sh puts its wheel on the path).

    python3 drive.py --chromium PATH --url URL --input FILE [--input FILE2 ...] [--runs 3] [--flags '...'] -o OUT.json
    python3 drive.py --chromium PATH --probe --flags '...'   # which WebGPU adapter those flags give

A run: open URL (navigation to the model ready is `model_ready_s`), pick the first input in
the page's file box, then `--runs` generations at the page's defaults, each timed in the page
from the click to the mesh shown (`generate_s`), with the page's own report (stage times,
topology); then one generation of each further input.
"""

import argparse
import itertools
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

import websocket

# The adapter WebGPU offers the page (vendor, architecture, device, description), or why none.
ADAPTER_JS = """(async () => {
  if (!navigator.gpu) return {error: 'navigator.gpu is missing'};
  const late = new Promise((resolve) => setTimeout(() => resolve('late'), 15000));
  const a = await Promise.race([navigator.gpu.requestAdapter(), late]);
  if (a === 'late') return {error: 'requestAdapter() did not answer in 15 s'};
  if (!a) return {error: 'requestAdapter() gave null'};
  const i = a.info || {};
  // What the page's 'auto' asks for first (web/lib/index.js, chooseBackend).
  const hp = await Promise.race([navigator.gpu.requestAdapter({powerPreference: 'high-performance'}), late]);
  return {vendor: i.vendor, architecture: i.architecture, device: i.device, description: i.description,
          high_performance: hp === 'late' ? 'no answer' : hp ? (hp.info || {}).vendor ?? 'unnamed' : null};
})()"""


class Browser:
    """One headless Chromium with one page, driven over the DevTools protocol."""

    def __init__(self, chromium, flags, port):
        self.profile = tempfile.mkdtemp(prefix="meshflow-page-gpu-")
        args = [chromium, "--headless=new", "--no-sandbox", f"--remote-debugging-port={port}",
                f"--user-data-dir={self.profile}", *flags, "about:blank"]
        self.log = open(os.path.join(self.profile, "chromium.log"), "w")
        self.proc = subprocess.Popen(args, stdout=self.log, stderr=subprocess.STDOUT)
        deadline = time.time() + 30
        while True:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=2) as r:
                    pages = [t for t in json.load(r) if t["type"] == "page"]
                if pages:
                    break
            except OSError:
                pass
            if time.time() > deadline or self.proc.poll() is not None:
                raise RuntimeError(f"Chromium did not start: {self.log_tail()}")
            time.sleep(0.2)
        self.ws = websocket.create_connection(pages[0]["webSocketDebuggerUrl"], timeout=GENERATE_TIMEOUT_S + 30,
                                              suppress_origin=True)
        self.ids = itertools.count(1)

    def log_tail(self):
        self.log.flush()
        with open(self.log.name) as f:
            return f.read()[-3000:]

    def send(self, method, **params):
        """Sends one command and returns its result (events in between are dropped)."""
        i = next(self.ids)
        self.ws.send(json.dumps({"id": i, "method": method, "params": params}))
        while True:
            try:
                msg = json.loads(self.ws.recv())
            except websocket.WebSocketTimeoutException:
                raise RuntimeError(f"{method}: no answer in {GENERATE_TIMEOUT_S + 30} s (the page hangs)") from None
            if msg.get("id") == i:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg["result"]

    def eval(self, expression):
        """The value of a JavaScript expression in the page (a promise is awaited)."""
        r = self.send("Runtime.evaluate", expression=expression, awaitPromise=True, returnByValue=True)
        if "exceptionDetails" in r:
            raise RuntimeError(f"{expression[:60]}: {r['exceptionDetails']}")
        return r["result"].get("value")

    def wait_for(self, expression, timeout):
        deadline = time.time() + timeout
        while True:
            v = self.eval(expression)
            if v:
                return v
            if time.time() > deadline:
                raise RuntimeError(f"timed out after {timeout} s waiting for {expression}")
            time.sleep(0.05)

    def close(self):
        try:
            self.ws.close()
        finally:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
            shutil.rmtree(self.profile, ignore_errors=True)


def pick(b, input_file):
    """Picks a file in the page's file box and waits until the page has read it."""
    b.eval("document.getElementById('input-info').textContent = ''")
    root = b.send("DOM.getDocument")["root"]["nodeId"]
    node = b.send("DOM.querySelector", nodeId=root, selector="#file")["nodeId"]
    b.send("DOM.setFileInputFiles", files=[os.path.abspath(input_file)], nodeId=node)
    b.wait_for("document.getElementById('input-info').textContent.includes('points')", 60)


def generate(b):
    """One generation at the page's settings, timed in the page from the click to the mesh shown."""
    ms = b.eval("""new Promise((resolve) => {
      const n = Number(document.body.dataset.generated ?? 0);
      const t0 = performance.now();
      document.getElementById('generate').click();
      const iv = setInterval(() => {
        if (Number(document.body.dataset.generated ?? 0) > n) { clearInterval(iv); resolve(performance.now() - t0); }
        else if (document.getElementById('error')?.textContent) { clearInterval(iv); resolve(-1); }
        else if (performance.now() - t0 > GENERATE_TIMEOUT_MS) { clearInterval(iv); resolve(-2); }
      }, 5);
    })""".replace("GENERATE_TIMEOUT_MS", str(GENERATE_TIMEOUT_S * 1000)))
    if ms == -2:
        raise RuntimeError(f"no mesh after {GENERATE_TIMEOUT_S} s")
    if ms < 0:
        raise RuntimeError(f"generation failed on the page: {b.eval(ERROR_JS)}")
    report = b.eval("window.__meshflowReport")
    return {"generate_s": ms / 1000, "stages_s": report["times"], "vertices": report["topology"]["vertices"],
            "faces": report["topology"]["faces"], "report": report}


ERROR_JS = "document.getElementById('error')?.textContent"
# Bounds that end a run which hangs (a GPU process that never answers) with a message.
READY_TIMEOUT_S = 120
GENERATE_TIMEOUT_S = 90


def page_runs(b, url, inputs, runs, out, save=lambda: None):
    """Opens the page, then `runs` generations of the first input and one of each other input,
    into `out` as they come (a failure keeps what came before it)."""
    b.send("Page.navigate", url=url)
    b.wait_for(f"location.href === {json.dumps(url)}", 60)
    # Navigation start to the model ready (weights fetched, module and device up).
    ready = b.wait_for(f"document.body.dataset.backend ? performance.now() : ({ERROR_JS} ? -1 : 0)", READY_TIMEOUT_S)
    if ready < 0:
        raise RuntimeError(f"the page failed to load the model: {b.eval(ERROR_JS)}")
    info = b.eval("""({backend: document.body.dataset.backend, module: document.body.dataset.wasmModule,
      reason: document.body.dataset.backendReason, workers: document.body.dataset.workers,
      workersReason: document.body.dataset.workersReason, weightsFromCache: document.body.dataset.weightsFromCache,
      shown: document.getElementById('backend').textContent})""")
    out.update({"page": info, "model_ready_s": ready / 1000, "inputs": []})
    for k, input_file in enumerate(inputs):
        pick(b, input_file)
        done = []
        out["inputs"].append({"input": os.path.basename(input_file), "runs": done})
        for _ in range(runs if k == 0 else 1):
            r = generate(b)
            done.append(r)
            save()
            print(f"  {info['backend']} {os.path.basename(input_file)}: {r['generate_s']:.2f} s, "
                  f"{r['vertices']} vertices, {r['faces']} faces", flush=True)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--chromium", required=True)
    p.add_argument("--flags", default="", help="extra Chromium flags, space-separated")
    p.add_argument("--port", type=int, default=9333)
    p.add_argument("--probe", action="store_true", help="only report the WebGPU adapter and chrome://gpu")
    p.add_argument("--url")
    p.add_argument("--input", action="append", help="a point cloud; repeat for more")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("-o", "--output")
    a = p.parse_args()
    b = Browser(a.chromium, a.flags.split(), a.port)
    result = {}

    def save():
        # After every generation, so that a run stopped from outside keeps what it measured.
        if a.output:
            with open(a.output + ".part", "w") as f:
                json.dump(result, f, indent=2)
            os.replace(a.output + ".part", a.output)

    try:
        if a.probe:
            b.send("Page.navigate", url="chrome://gpu")
            time.sleep(3)
            gpu = b.eval("document.querySelector('info-view')?.shadowRoot?.querySelector('#content')?.innerText"
                         " ?? document.body.innerText")
            b.send("Page.navigate", url="about:blank")
            time.sleep(0.5)
            # WebGPU needs a secure context: a page from 127.0.0.1 (the caller's server) or about:blank.
            if a.url:
                b.send("Page.navigate", url=a.url)
                time.sleep(1)
            result.update({"adapter": b.eval(ADAPTER_JS), "chrome_gpu": gpu})
        else:
            page_runs(b, a.url, a.input, a.runs, result, save)
            result["adapter"] = b.eval(ADAPTER_JS)
        result["flags"] = a.flags
    except Exception as e:  # noqa: BLE001 (the caller records what failed and tries the next flags)
        result.update({"error": str(e), "flags": a.flags, "chromium_log": b.log_tail()})
    finally:
        b.close()
    save()
    print(json.dumps({k: v for k, v in result.items() if k not in ("chrome_gpu", "chromium_log")})[:2000])
    if "error" in result:
        print(result.get("chromium_log", "")[-1500:], file=sys.stderr)
    return 1 if "error" in result else 0


if __name__ == "__main__":
    sys.exit(main())
