#!/usr/bin/env bash
# Fuzzes every mesh reader in turn for SECONDS each (default 600 = the 10-minute campaign).
# Usage (from anywhere): fuzz/run-all.sh [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")"
secs="${1:-600}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    targets=(fuzz_obj fuzz_ply fuzz_stl fuzz_gltf fuzz_glb fuzz_points fuzz_pmd fuzz_spm fuzz_md2 fuzz_md3 fuzz_pie fuzz_ac3d fuzz_dae fuzz_ase fuzz_iqm fuzz_md5)
fi
for t in "${targets[@]}"; do
    mkdir -p "corpus/$t"
    echo "=== $t for ${secs}s ==="
    # Text formats with keywords have a dictionary of them (dicts/<target>.dict).
    dict=()
    if [ -f "dicts/$t.dict" ]; then
        dict=(-dict="dicts/$t.dict")
    fi
    cargo +nightly fuzz run "$t" "corpus/$t" "seeds/$t" -- \
        -max_total_time="$secs" -rss_limit_mb=2048 -max_len=65536 ${dict[@]+"${dict[@]}"}
done
