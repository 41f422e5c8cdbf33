"""The page's CPU module (V8, one thread) against the CLI (one thread), per kind of work, from
the self times that wasm.mjs and native.py write (bench/cpu_profile/run.sh). Not a test.

    python3 bench/cpu_profile/table.py WASM.json NATIVE.json
"""

import json
import re
import sys

# First match wins; matched against the whole (mangling-free) function name.
KINDS = [
    ("matrix products (gemm)", r"gemm"),
    ("attention: scores, softmax, exp", r"attention|expf|__exp|\bexp\b"),
    ("GELU's erf", r"erf"),
    ("other tensor work (element-wise, copies)", r"burn|memmove|memcpy|memset|copy_2d"),
    ("k-d tree queries", r"kiddo"),
    ("allocation", r"malloc|free|realloc|dlmalloc|__rust_(alloc|dealloc|realloc)"),
    ("mesh geometry (extract, fit, complete, sharpen)", r"meshflow|glam|sort"),
]


def kinds(self_s):
    total = {name: 0.0 for name, _ in KINDS}
    total["other"] = 0.0
    for fn, s in self_s.items():
        kind = next((name for name, pattern in KINDS if re.search(pattern, fn)), "other")
        total[kind] += s
    return total


wasm, native = (json.load(open(p)) for p in sys.argv[1:3])
w, n = kinds(wasm["self_s"]), kinds(native["self_s"])
print("| work | page's CPU module, 1 thread | CLI, 1 thread | ratio |")
print("|---|---:|---:|---:|")
for kind in w:
    ratio = f"{w[kind] / n[kind]:.1f}" if n[kind] > 0.005 else ""
    print(f"| {kind} | {w[kind]:.2f} s | {n[kind]:.2f} s | {ratio} |")
tw, tn = sum(w.values()), sum(n.values())
print(f"| **all** | **{tw:.2f} s** | **{tn:.2f} s** | **{tw / tn:.2f}** |")
