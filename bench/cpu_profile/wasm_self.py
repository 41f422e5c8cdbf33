"""Self time per wasm function of the CPU module's generations, from the `.cpuprofile` that
`node --cpu-prof` writes for bench/cpu_profile/wasm.mjs: only samples inside
`MeshFlow.generate` (the weights' loading left out), divided by the generations (GENERATIONS:
wasm.mjs's ROUNDS + 1). Not a test.

    python3 bench/cpu_profile/wasm_self.py PROFILE.cpuprofile GENERATIONS OUT.json
"""

import collections
import json
import sys

profile_path, generations, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
profile = json.load(open(profile_path))
nodes = {n["id"]: n for n in profile["nodes"]}
parent = {c: n["id"] for n in profile["nodes"] for c in n.get("children", [])}


def inside_generate(node_id):
    while node_id is not None:
        if "MeshFlow_generate" in nodes[node_id]["callFrame"]["functionName"]:
            return True
        node_id = parent.get(node_id)
    return False


self_s = collections.Counter()
deltas = profile["timeDeltas"][1:] + [0]
for node_id, dt in zip(profile["samples"], deltas):
    if inside_generate(node_id):
        name = nodes[node_id]["callFrame"]["functionName"] or "(anonymous)"
        self_s[name] += dt / 1e6 / generations

json.dump({"self_s": dict(self_s.most_common())}, open(out, "w"), indent=1)
