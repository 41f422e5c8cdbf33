"""Self time per function of the CLI's generations, from `perf script` of a one-thread
`meshflow bench generate` (bench/cpu_profile/run.sh): every sample of the process but those
loading the weights, each 1/FREQ seconds, divided by the generations. (Not only the samples
under `Generator::generate`: rayon's pool thread, which runs most of the work even at one
thread, has its own stack.) Not a test.

    perf script -i DATA --no-inline | python3 bench/cpu_profile/native.py FREQ RUNS OUT.json
"""

import collections
import itertools
import json
import re
import sys

freq, runs, out = float(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
self_s = collections.Counter()


def frame(line):
    # "    55d1c0 gemm_f32::microkernel::fma::f32::x2x6+0x1a (/path/meshflow)"
    parts = line.strip().split(None, 1)
    name = parts[1] if len(parts) == 2 else parts[0]
    return re.sub(r"::h[0-9a-f]{16}$", "", re.sub(r"\+0x[0-9a-f]+ \(.*\)$|\s\(.*\)$", "", name))


stack = []
# Streamed: a few generations' `perf script` is hundreds of megabytes.
for line in itertools.chain(sys.stdin, ["\n"]):
    if line.strip():
        if line[0] in " \t":
            stack.append(frame(line))
        continue
    if stack and not any(re.search(r"load_models|from_safetensors", f) for f in stack):
        self_s[stack[0]] += 1.0 / freq / runs
    stack = []

json.dump({"self_s": dict(self_s.most_common())}, open(out, "w"), indent=1)
