"""Serves the repository root to 127.0.0.1 as web/serve.mjs does (same types, content security
policy and no-cache), for machines with Python and no Node: `python3 serve.py PORT`."""

import http.server
import os
import re
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
# The policy web/serve.mjs exports (its string literals joined), so that the two cannot drift.
_MJS = open(os.path.join(ROOT, "web/serve.mjs")).read()
CSP = "".join(re.findall(r'"([^"]*)"', _MJS.split("export const CSP =")[1].split(";\n")[0]))


class Handler(http.server.SimpleHTTPRequestHandler):
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                      ".js": "text/javascript; charset=utf-8", ".mjs": "text/javascript; charset=utf-8",
                      ".wasm": "application/wasm", ".json": "application/json"}

    def __init__(self, *a, **k):
        super().__init__(*a, directory=ROOT, **k)

    def end_headers(self):
        self.send_header("content-security-policy", CSP)
        self.send_header("cache-control", "no-cache")
        super().end_headers()

    def log_message(self, *a):
        pass


if __name__ == "__main__":
    http.server.ThreadingHTTPServer(("127.0.0.1", int(sys.argv[1])), Handler).serve_forever()
