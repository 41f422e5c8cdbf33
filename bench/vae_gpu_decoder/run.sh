#!/usr/bin/env bash
# The decoder-only arms of docs/experiments/2026-11-26-gpu-decoder.md (issue 14, commit
# 881f07d, 2026-11-26; results in docs/experiments/data/2026-11-26-gpu-decoder/), as they ran
# on an H100 GPU machine (16 cores; burn-wgpu over Vulkan with the NVIDIA driver), from the
# repository root, with these ignored files carried beside the tree:
#   .dev/meshflow.xz   the release CLI of this commit, stripped (`objcopy --strip-all`), xz'd
#   .dev/data.tgz      data/ = the shard build's train and val meshes of <= 512 vertices
#                      (`python3 bench/vae_gpu_decoder/compact_data.py SHARDS data`), tarred
#   .dev/cfg/ARM.json  each arm's configuration (ARM/config.json here holds the steps it got)
#   .gl/*.deb          the Vulkan loader (docs of the device tool); SKIP_DEBS=1 skips it
# `OUT=DIR bash bench/vae_gpu_decoder/run.sh` (BACKEND=cpu to try it without a GPU; ARMS,
# PROBE_S and TRAIN_END_S change the arms and the budget).
# Phase 1 probes each arm's step rate (all arms at once, as in phase 2); phase 2 trains each arm
# with a cosine schedule sized to the time left. Results -> $OUT (a split tarball).
T0=$(date +%s); END=$((T0 + ${TRAIN_END_S:-535}))
[ -z "$SKIP_DEBS" ] && { for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig; }
ICD=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -f $ICD ] && export VK_DRIVER_FILES=$ICD __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export XDG_RUNTIME_DIR=/tmp
nvidia-smi -L; ls /usr/local/nvidia/share/vulkan/icd.d/ 2>&1
xz -dc .dev/meshflow.xz > /tmp/meshflow && chmod +x /tmp/meshflow
tar xzf .dev/data.tgz -C /tmp
M=/tmp/meshflow; ARMS="${ARMS:-cont w256d4 w192d6}"
mkdir -p /tmp/probe /tmp/runs /tmp/cfg
for a in $ARMS; do
  $M train vae --data /tmp/data -o /tmp/probe/$a --config .dev/cfg/$a.json --init weights --backend ${BACKEND:-wgpu} \
     --time-budget-s ${PROBE_S:-70} --val-meshes 8 > /tmp/probe/$a.log 2>&1 &
done; wait
for a in $ARMS; do tail -2 /tmp/probe/$a.log; done
first=${ARMS%% *}
if [ ! -s /tmp/probe/$first/metrics.jsonl ] && [ "${BACKEND:-wgpu}" = wgpu ]; then
  echo "wgpu did not train; falling back to the CPU backend"; BACKEND=cpu
  for a in $ARMS; do
    $M train vae --data /tmp/data -o /tmp/probe/$a --config .dev/cfg/$a.json --init weights --backend cpu \
       --time-budget-s 40 --val-meshes 8 > /tmp/probe/$a.log 2>&1 &
  done; wait
fi
NOW=$(date +%s)
python3 - "$((END - NOW))" $ARMS <<'PY'
import json, sys
left = float(sys.argv[1])
for a in sys.argv[2:]:
    rows = [json.loads(l) for l in open(f'/tmp/probe/{a}/metrics.jsonl') if '"lr"' in l]
    first = rows[0]['elapsed_s']; late = [r for r in rows if r['elapsed_s'] > first + 20] or rows
    rate = (late[-1]['step'] - late[0]['step']) / max(late[-1]['elapsed_s'] - late[0]['elapsed_s'], 1e-6)
    steps = max(100, int(rate * (left - first - 30) * 0.92))
    c = json.load(open(f'.dev/cfg/{a}.json'))
    c['steps'] = steps; c['warmup_steps'] = min(c['warmup_steps'], steps // 10)
    c['eval_every'] = max(100, steps // 16 // 50 * 50); c['checkpoint_every'] = c['eval_every']
    json.dump(c, open(f'/tmp/cfg/{a}.json', 'w'), indent=2)
    print(f'{a}: first step at {first:.1f} s, {rate:.2f} steps/s ({rate*c["batch_size"]:.0f} meshes/s) -> {steps} steps, {left:.0f} s left', flush=True)
PY
NOW=$(date +%s)
for a in $ARMS; do
  $M train vae --data /tmp/data -o /tmp/runs/$a --config /tmp/cfg/$a.json --init weights --backend ${BACKEND:-wgpu} \
     --time-budget-s $((END - NOW)) > /tmp/runs/$a.log 2>&1 &
done; wait
for a in $ARMS; do tail -3 /tmp/runs/$a.log; grep val_loss /tmp/runs/$a/metrics.jsonl | tail -1 | cut -c1-300; done
mkdir -p /tmp/pack
for a in $ARMS; do mkdir -p /tmp/pack/$a; cp /tmp/runs/$a/vae.* /tmp/runs/$a/metrics.jsonl /tmp/runs/$a.log /tmp/cfg/$a.json /tmp/pack/$a/ 2>/dev/null; cp /tmp/probe/$a/metrics.jsonl /tmp/pack/$a/probe.metrics.jsonl; cp /tmp/probe/$a.log /tmp/pack/$a/probe.log; done
tar cf - -C /tmp pack | xz -T16 -1 | split -b 15M - $OUT/pack.tar.xz.
ls -la $OUT; echo total $(( $(date +%s) - T0 )) s
