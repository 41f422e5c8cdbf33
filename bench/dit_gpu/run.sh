#!/usr/bin/env bash
# The DiT continuation arms of docs/experiments/2026-11-27-dit-on-h100.md (issue 14, commit
# 1107f76, 2026-11-27; the results are in docs/experiments/data/2026-11-27-dit-on-h100/), as
# they ran on an H100 GPU machine (16 cores; burn-wgpu over Vulkan, the NVIDIA driver), from
# the repository root, with these ignored files carried beside the tree:
#   .dev/meshflow.xz    the release CLI of this commit, stripped (`objcopy --strip-all`), xz'd
#   .dev/data.tar.xz    cdata/ = the shard build's train and val meshes of <= 512 vertices
#                       (`python3 bench/vae_gpu_decoder/compact_data.py SHARDS cdata`), tarred
#   .dev/cfg/ARM.json   each arm's configuration (bench/dit_gpu/ARM.config.json: the steps it got)
#   .gl/*.deb           the Vulkan loader (docs of the device tool); SKIP_DEBS=1 skips it
# Every arm starts from the shipped pair in weights/ (`--vae weights --init weights`).
# `OUT=DIR bash bench/dit_gpu/run.sh` (BACKEND=cpu to try it without a GPU; ARMS, PROBE_S and
# TRAIN_END_S change the arms and the budget).
# Phase 1 probes each arm's step rate (all arms at once, as in phase 2); phase 2 trains each arm
# with a cosine schedule sized to the time left. Results -> $OUT (a split tarball).
T0=$(date +%s); END=$((T0 + ${TRAIN_END_S:-520}))
[ -z "$SKIP_DEBS" ] && { for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig; }
ICD=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -f $ICD ] && export VK_DRIVER_FILES=$ICD __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export XDG_RUNTIME_DIR=/tmp
nvidia-smi -L 2>&1
xz -T0 -dc .dev/meshflow.xz > /tmp/meshflow && chmod +x /tmp/meshflow
xz -T0 -dc .dev/data.tar.xz | tar xf - -C /tmp
M=/tmp/meshflow; ARMS="${ARMS:-b16 b64 b256}"; BACKEND=${BACKEND:-wgpu}
train() { # ARM CONFIG RUN SECONDS
  $M train dit --data /tmp/cdata --backend $BACKEND --vae weights --init weights --out $3 \
     --config $2 --time-budget-s $4 > $3.log 2>&1
}
mkdir -p /tmp/probe /tmp/runs /tmp/cfg
for a in $ARMS; do train $a .dev/cfg/$a.json /tmp/probe/$a ${PROBE_S:-75} & done; wait
for a in $ARMS; do tail -2 /tmp/probe/$a.log; done
NOW=$(date +%s)
python3 - "$((END - NOW))" $ARMS <<'PY'
import json, sys
left = float(sys.argv[1])
for a in sys.argv[2:]:
    rows = [json.loads(l) for l in open(f'/tmp/probe/{a}/metrics.jsonl') if '"lr"' in l]
    # elapsed_s counts from the first step; encoding the meshes with the VAE comes before it
    encode = float(open(f'/tmp/probe/{a}.log').read().split(' meshes in ')[1].split(' s')[0])
    late = [r for r in rows if r['elapsed_s'] > rows[0]['elapsed_s'] + 10] or rows
    first = rows[0]['elapsed_s'] + encode
    rate = (late[-1]['step'] - late[0]['step']) / max(late[-1]['elapsed_s'] - late[0]['elapsed_s'], 1e-6)
    steps = max(100, int(rate * (left - first - 25) * 0.9))
    c = json.load(open(f'.dev/cfg/{a}.json'))
    c['steps'] = steps; c['warmup_steps'] = min(c['warmup_steps'], steps // 10)
    c['eval_every'] = max(100, steps // 8 // 50 * 50); c['checkpoint_every'] = c['eval_every']
    json.dump(c, open(f'/tmp/cfg/{a}.json', 'w'), indent=2)
    print(f'{a}: first step at {first:.1f} s, {rate:.2f} steps/s ({rate*c["batch_size"]:.0f} examples/s) -> {steps} steps, {left:.0f} s left', flush=True)
PY
NOW=$(date +%s)
for a in $ARMS; do train $a /tmp/cfg/$a.json /tmp/runs/$a $((END - NOW)) & done; wait
for a in $ARMS; do tail -2 /tmp/runs/$a.log; grep val_loss /tmp/runs/$a/metrics.jsonl | tail -1 | cut -c1-300; done
mkdir -p /tmp/pack
for a in $ARMS; do mkdir -p /tmp/pack/$a; cp /tmp/runs/$a/dit.* /tmp/runs/$a/metrics.jsonl /tmp/runs/$a.log /tmp/cfg/$a.json /tmp/pack/$a/ 2>/dev/null; cp /tmp/probe/$a/metrics.jsonl /tmp/pack/$a/probe.metrics.jsonl; cp /tmp/probe/$a.log /tmp/pack/$a/probe.log; done
tar cf - -C /tmp pack | xz -T0 -1 | split -b 15M - $OUT/pack.tar.xz.
ls -la $OUT; echo total $(( $(date +%s) - T0 )) s
