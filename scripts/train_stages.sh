# Sourced by scripts/train_vae.sh and scripts/train_dit.sh: builds the release CLI and defines
# `stage DIR ARGS...`, which runs `meshflow ARGS... -o DIR [--data DATA]` from the repository
# root and appends its output to DIR/train.log. The caller sets DATA (may be empty).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}"
cd "$ROOT"
cargo build --release -p meshflow-cli
MESHFLOW="$CARGO_TARGET_DIR/release/meshflow"

stage() {
    local dir="$1"
    shift
    local data_args=()
    [[ -n "${DATA:-}" ]] && data_args=(--data "$DATA")
    mkdir -p "$dir"
    "$MESHFLOW" "$@" -o "$dir" "${data_args[@]}" 2>&1 | tee -a "$dir/train.log"
}
