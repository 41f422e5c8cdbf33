#!/usr/bin/env bash
# The page's WebGPU path on a real GPU, against the page's CPU path and `meshflow generate` on
# the same machine (issue 54 item 6). Ran on an NVIDIA H200 machine (16 cores, no Node, no
# browser, nothing reachable), from the repository root: `OUT=DIR bash bench/page_gpu/run.sh`.
# Carried beside the tree: .dev/p1 .. .dev/p3, .dev/fonts and .gl (bench/page_gpu/pack.sh makes
# them). Everything it runs was built elsewhere and brought in parts (the machine takes at most 64 MiB
# a transfer) to /tmp/chunks/part.*, which together are one tar (bench/page_gpu/pack.sh) of:
#   chromium.xz             Debian's Chromium 156 binary (/usr/lib/chromium/chromium)
#   chromium_rest.tar.xz    chromium/: its data files, ANGLE, its Vulkan loader, and in lib/ the
#                           shared libraries `ldd` names (Debian 12's, less glibc's own)
#   meshflow.xz             the release CLI, stripped
#   pkg.tar.xz              web/pkg from scripts/build-web.sh
#   websocket_client-*.whl  for bench/page_gpu/drive.py
#   stone_lantern_2048.ply  tests/fixtures/points/ (the input the page-vs-CLI figures use)
# Order: the CLI on the CPU and on wgpu (Vulkan), RUNS (4) runs each; the page on WebGPU with
# the first Chromium flags (of FLAG_SETS) whose adapter is the GPU, a fresh profile (first
# visit), RUNS runs of the lantern and one of each bundled example; the same on the page's CPU
# path; one run of the page at `auto`; the CLI once per example on each backend, to compare
# meshes. Every step is bounded so that the whole ends inside the machine's 10-minute call.
# Results -> $OUT/page_gpu.tar.xz and $OUT/run.log.
set -u
T0=$(date +%s)
W=/tmp/pg R=/tmp/pg/res
mkdir -p $W $R
log() { echo "[$(($(date +%s) - T0)) s] $*" | tee -a $R/run.log; }
cat /tmp/chunks/part.* | tar xf - -C $W || { log "the parts do not make a whole tar"; ls -la /tmp/chunks; exit 1; }
xz -T0 -dc $W/chromium_rest.tar.xz | tar xf - -C $W
xz -T0 -dc $W/chromium.xz > $W/chromium/chromium && chmod +x $W/chromium/chromium
xz -T0 -dc $W/meshflow.xz > $W/meshflow && chmod +x $W/meshflow
mkdir -p web && xz -dc $W/pkg.tar.xz | tar xf - -C web
# The Vulkan loader and GLVND, which NVIDIA's Vulkan driver needs (.gl/, see pack.sh).
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export LD_LIBRARY_PATH=$W/chromium/lib:$W/chromium
# One font: without any, Chromium's renderer stops at its first line of text.
mkdir -p $W/fonts && cp .dev/fonts/*.ttf $W/fonts/
printf '<?xml version="1.0"?>\n<fontconfig><dir>%s</dir><cachedir>%s/cache</cachedir></fontconfig>\n' $W/fonts $W/fonts > $W/fonts/fonts.conf
export FONTCONFIG_FILE=$W/fonts/fonts.conf
ICD=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -f $ICD ] && export VK_DRIVER_FILES=$ICD __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export PYTHONPATH=$(ls $W/websocket_client-*.whl) XDG_RUNTIME_DIR=/tmp
LANTERN=$W/stone_lantern_2048.ply
EXAMPLES=(web/examples/milk_truck_4096.ply web/examples/panda_4096.ply web/examples/tube_shell_3072.ply
  web/examples/panda_walk_noisy_4096.ply web/examples/engine_normals_3072.ply)
{
  nvidia-smi -L; nproc; grep -m1 'model name' /proc/cpuinfo; $W/chromium/chromium --version
} 2>&1 | tee $R/machine.txt
log "unpacked"

# The CLI: whole process wall time (start, weights, generation, GLB written) and its own report.
cli() { # BACKEND INPUT NAME
  local t=$EPOCHREALTIME
  timeout 60 $W/meshflow generate "$2" -o /tmp/cli.glb --json --backend $1 > $R/$3.json 2> $R/$3.err
  local rc=$?
  echo "{\"process_s\": $(awk "BEGIN{print $EPOCHREALTIME - $t}"), \"rc\": $rc}" > $R/$3.wall.json
  log "cli $1 $(basename $2): rc $rc, $(tail -c 300 $R/$3.json | tr -d '\n' | grep -o '"faces":[0-9]*' | head -1)"
}
RUNS=${RUNS:-4}; CLI_BACKENDS=${CLI_BACKENDS:-cpu wgpu}
# PHASES picks steps for a rerun (default all); ONLY_LANTERN=1 leaves the examples out of the page runs.
PHASES=${PHASES:-cli probe page_webgpu page_cpu page_auto cli_examples}
on() { [[ " $PHASES " == *" $1 "* ]]; }
on cli && for b in $CLI_BACKENDS; do for i in $(seq 0 $((RUNS - 1))); do cli $b $LANTERN cli_${b}_lantern_$i; done; done

python3 bench/page_gpu/serve.py 8765 &
SERVER=$!
sleep 1
BASE=http://127.0.0.1:8765/web/
# Chromium's flags for WebGPU on the machine's GPU, most likely first (the first is what
# Chrome's own headless-GPU guidance uses); the first whose adapter is NVIDIA's runs the page.
FLAG_SETS=(
  "--use-angle=vulkan --enable-features=Vulkan --disable-vulkan-surface --enable-unsafe-webgpu"
  "--use-angle=vulkan --enable-features=Vulkan --disable-vulkan-surface --enable-unsafe-webgpu --ignore-gpu-blocklist --use-vulkan=native"
  "--enable-unsafe-webgpu --enable-features=Vulkan --ignore-gpu-blocklist"
)
GPU_FLAGS=""
on probe && for i in "${!FLAG_SETS[@]}"; do
  timeout 30 python3 bench/page_gpu/drive.py --chromium $W/chromium/chromium --probe --url "${BASE}?backend=cpu" \
    --flags "${FLAG_SETS[$i]}" -o $R/probe_$i.json > $R/probe_$i.log 2>&1
  pkill -f $W/chromium/chromium
  log "probe $i: $(head -c 400 $R/probe_$i.log)"
  if grep -qi '"vendor": "nvidia' $R/probe_$i.json 2>/dev/null; then GPU_FLAGS="${FLAG_SETS[$i]}"; break; fi
done
# EXTRA_FLAGS: more for the GPU runs (e.g. Dawn's toggles, to see where WebGPU's time goes).
[ -n "$GPU_FLAGS" ] && GPU_FLAGS="$GPU_FLAGS ${EXTRA_FLAGS:-}"
[ -z "$GPU_FLAGS" ] && { log "no flags gave WebGPU the GPU; the WebGPU page runs with the first set"; GPU_FLAGS="${FLAG_SETS[0]}"; }
INPUTS=(--input $LANTERN)
[ -z "${ONLY_LANTERN:-}" ] && for e in "${EXAMPLES[@]}"; do INPUTS+=(--input $e); done
page() { # NAME SECONDS URL FLAGS RUNS INPUT...
  local name=$1 limit=$2 url=$3 flags=$4 runs=$5; shift 5
  timeout $limit python3 bench/page_gpu/drive.py --chromium $W/chromium/chromium --url "$url" --flags "$flags" \
    "$@" --runs $runs -o $R/$name.json > $R/$name.log 2>&1
  local rc=$?
  pkill -f $W/chromium/chromium
  log "page $name: rc $rc"; cat $R/$name.log | tee -a $R/run.log
}
# Bounded so that the whole script ends inside the machine's 10-minute call.
on page_webgpu && page page_webgpu 150 "${BASE}?backend=webgpu" "$GPU_FLAGS" $RUNS "${INPUTS[@]}"
on page_cpu && page page_cpu 150 "${BASE}?backend=cpu" "" $RUNS "${INPUTS[@]}"
on page_auto && page page_auto 60 "${BASE}" "$GPU_FLAGS" 1 --input $LANTERN
kill $SERVER
on cli_examples && for e in "${EXAMPLES[@]}"; do
  n=$(basename $e .ply); for b in $CLI_BACKENDS; do cli $b $e cli_${b}_$n; done
done
log "done"
tar cf - -C $W res | xz -T0 -6 > $OUT/page_gpu.tar.xz
cp $R/run.log $OUT/
