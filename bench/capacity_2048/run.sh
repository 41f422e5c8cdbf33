#!/usr/bin/env bash
# Issue 53: the shipped pair continued at a capacity of 2,048 vertices (512 latent tokens), the
# VAE's decoder and the DiT at once on one GPU (burn-wgpu over Vulkan), from the repository
# root of the commit that adds this file, with these ignored files carried beside the tree:
#   .dev/meshflow.xz        that commit's release CLI, stripped (`objcopy --strip-all`), xz'd
#   .dev/data2048.tar.xz    cdata2048/ = the shard build's train and val meshes of <= 2,048
#                           vertices (`python3 bench/vae_gpu_decoder/compact_data.py SHARDS
#                           cdata2048 2048`), tarred
#   .gl/*.deb               the Vulkan loader (the device tool's notes); SKIP_DEBS=1 skips it
# Both arms start from weights/ with its capacity raised to 2,048 (`raise` below: only the
# configuration changes, no weight does). The VAE arm trains the decoder alone, so its encoder,
# and the latents the DiT arm learns from, stay the shipped ones: the two results form a pair.
# `OUT=DIR bash bench/capacity_2048/run.sh` (BACKEND=cpu tries it without a GPU; PROBE_S and
# TRAIN_END_S change the budget). Phase 1 probes both arms' step rates at once; phase 2 trains
# each with a cosine schedule sized to the time left. Results -> $OUT (a split tarball).
set -u
T0=$(date +%s); END=$((T0 + ${TRAIN_END_S:-500}))
[ -z "${SKIP_DEBS:-}" ] && { for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig; }
ICD=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -f $ICD ] && export VK_DRIVER_FILES=$ICD __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export XDG_RUNTIME_DIR=/tmp
nvidia-smi -L 2>&1
M=${MESHFLOW:-/tmp/meshflow}; BACKEND=${BACKEND:-wgpu}; W=/tmp/raised
[ -x "$M" ] || { xz -T0 -dc .dev/meshflow.xz > $M && chmod +x $M; }
[ -d /tmp/cdata2048 ] || xz -T0 -dc .dev/data2048.tar.xz | tar xf - -C /tmp
# The shipped pair at capacity 2,048 (no weight changes; bench/capacity_2048/raise.py).
rm -rf $W && python3 bench/capacity_2048/raise.py weights $W 2048
train() { # ARM CONFIG RUN SECONDS
  if [ $1 = vae ]; then
    $M train vae --data /tmp/cdata2048 --backend $BACKEND --init $W --out $3 --config $2 \
       --time-budget-s $4 > $3.log 2>&1
  else
    $M train dit --data /tmp/cdata2048 --backend $BACKEND --vae $W --init $W --out $3 \
       --config $2 --time-budget-s $4 > $3.log 2>&1
  fi
}
ARMS="vae dit"; mkdir -p /tmp/probe /tmp/runs /tmp/cfg
for a in $ARMS; do train $a bench/capacity_2048/$a.config.json /tmp/probe/$a ${PROBE_S:-60} & done; wait
for a in $ARMS; do tail -3 /tmp/probe/$a.log; done
NOW=$(date +%s)
python3 - "$((END - NOW))" $ARMS <<'PY'
import json, sys, re
left = float(sys.argv[1])
for a in sys.argv[2:]:
    rows = [json.loads(l) for l in open(f'/tmp/probe/{a}/metrics.jsonl') if '"lr"' in l]
    log = open(f'/tmp/probe/{a}.log').read()
    m = re.search(r' meshes in ([0-9.]+) s', log)  # the DiT encodes its meshes before step 1
    setup = float(m.group(1)) if m else 0.0
    late = [r for r in rows if r['elapsed_s'] > rows[0]['elapsed_s'] + 10] or rows
    first = rows[0]['elapsed_s'] + setup + 10
    rate = (late[-1]['step'] - late[0]['step']) / max(late[-1]['elapsed_s'] - late[0]['elapsed_s'], 1e-6)
    steps = max(100, int(rate * (left - first - 30) * 0.9))
    c = json.load(open(f'bench/capacity_2048/{a}.config.json'))
    c['steps'] = steps; c['warmup_steps'] = min(c['warmup_steps'], steps // 10)
    c['eval_every'] = max(50, steps // 6 // 50 * 50); c['checkpoint_every'] = c['eval_every']
    json.dump(c, open(f'/tmp/cfg/{a}.json', 'w'), indent=2)
    print(f'{a}: first step after {first:.1f} s, {rate:.2f} steps/s ({rate*c["batch_size"]:.0f} examples/s) -> {steps} steps, {left:.0f} s left', flush=True)
PY
NOW=$(date +%s)
for a in $ARMS; do train $a /tmp/cfg/$a.json /tmp/runs/$a $((END - NOW)) & done; wait
for a in $ARMS; do tail -3 /tmp/runs/$a.log; grep val /tmp/runs/$a/metrics.jsonl | tail -1 | cut -c1-400; done
mkdir -p /tmp/pack
for a in $ARMS; do mkdir -p /tmp/pack/$a; cp /tmp/runs/$a/$a.* /tmp/runs/$a/metrics.jsonl /tmp/runs/$a.log /tmp/cfg/$a.json /tmp/pack/$a/ 2>/dev/null; cp /tmp/probe/$a/metrics.jsonl /tmp/pack/$a/probe.metrics.jsonl; cp /tmp/probe/$a.log /tmp/pack/$a/probe.log; done
cp $W/dit.json $W/vae.json /tmp/pack/
tar cf - -C /tmp pack | xz -T0 -1 | split -b 15M - ${OUT:-/tmp/out}/pack.tar.xz.
ls -la ${OUT:-/tmp/out}; echo total $(( $(date +%s) - T0 )) s
