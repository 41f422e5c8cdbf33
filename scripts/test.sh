#!/usr/bin/env bash
# The project's test command: `bash scripts/test.sh` (also `npm test`, and
# what CI runs through .ci/run).
#
# It first checks the wording of the tracked files (check_wording below: they
# name commits, dates and machines; a cheap git grep). On a fresh Debian
# machine with rustup/cargo and node/npm it then installs what the tests need
# (idempotently, so repeated runs are quick), and runs, in order, stopping at
# the first failure:
#   cargo fmt --all --check
#   cargo test --release --workspace --all-targets --no-fail-fast
#                                          (lib, bins, integration tests, and
#                                           benches compiled and run once)
#   cargo test --release --workspace --doc (--all-targets leaves doctests out)
#   cargo clippy --workspace --all-targets -- -D warnings
#   cargo doc --no-deps -p meshflow --features train,data-build
#             (RUSTDOCFLAGS=-D rustdoc::broken_intra_doc_links)
#   node tests/snip-wasm.test.mjs          (the wasm snipping tool build-web.sh uses)
#   bash scripts/build-web.sh              (the three wasm modules, into web/pkg/)
#   cargo clippy --target wasm32-unknown-unknown -p meshflow [--no-default-features] --features web,webgl | web,wgpu
#                --profile wasm-release -- -D warnings
#                                          (the wasm-only code: web/api.rs, web/viewer.rs)
#   node tests/e2e/browser.test.mjs        (the page and the npm package in
#                                           headless Chromium over SwiftShader)
# Each step prints its time; the last line is a plain
# "summary: N passed, N failed, N skipped" tally of the cargo, snip-wasm and
# browser test results.
#
# Builds go to ${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target} so that
# repeated runs, and scripts/demo.sh, reuse one build. Tests run in the release
# profile: the models train and run there at usable speed, and Burn (the
# largest dependency by far) is then compiled once for the CLI and the tests.

set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}"
# Output is piped through tee below, which would turn cargo's colours off.
if [[ -t 1 ]]; then
    export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-always}"
fi

# Debian packages the tests need. Add to this list rather than installing
# things by hand: CI machines start bare.
# mesa-vulkan-drivers: lavapipe, the Vulkan device the wgpu golden tests run on.
# chromium: the browser tests (WebGPU through its bundled SwiftShader).
# rustc-web, cargo-web, rust-web-src: the threaded wasm module's compiler and std source
# (scripts/build-web.sh, THREADS).
APT_PACKAGES=(mesa-vulkan-drivers chromium rustc-web cargo-web rust-web-src)

LOG_DIR="$(mktemp -d "${TMPDIR:-/tmp}/meshflow-test.XXXXXX")"
trap 'rm -rf "$LOG_DIR"' EXIT

STEP_NAMES=()
STEP_TIMES=()
STEP_STATUS=()

log() { printf '[test.sh] %s\n' "$*"; }

now_ms() { date +%s%3N; }

fmt_secs() { printf '%d.%ds' $(($1 / 1000)) $(($1 % 1000 / 100)); }

have() { command -v "$1" >/dev/null 2>&1; }

# ---- installing ----------------------------------------------------------

# Install the named Debian packages that are not installed yet.
ensure_apt_packages() {
    local missing=() pkg
    for pkg in "$@"; do
        dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q 'ok installed' ||
            missing+=("$pkg")
    done
    ((${#missing[@]} == 0)) && return 0
    log "installing Debian packages: ${missing[*]}"
    local sudo=()
    if ((EUID != 0)); then
        have sudo || { log "need root or sudo to install ${missing[*]}"; return 1; }
        sudo=(sudo)
    fi
    "${sudo[@]}" apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq "${missing[@]}"
}

ensure_system_tools() {
    have cargo || { log "cargo not found: install Rust with rustup first"; return 1; }
    if ! have node || ! have npm; then
        ensure_apt_packages nodejs npm
    fi
    if ((${#APT_PACKAGES[@]} > 0)); then
        ensure_apt_packages "${APT_PACKAGES[@]}"
    fi
}

ensure_rust_components() {
    if ! cargo fmt --version >/dev/null 2>&1; then
        rustup component add rustfmt
    fi
    if ! cargo clippy --version >/dev/null 2>&1; then
        rustup component add clippy
    fi
}

# `npm ci` when node_modules is missing or package-lock.json changed since the
# last install (a hash of the lock file is kept inside node_modules).
ensure_node_modules() {
    local stamp="node_modules/.meshflow-lock.sha256" want
    want="$(sha256sum package-lock.json | cut -d' ' -f1)"
    if [[ -d node_modules && -f "$stamp" && "$(cat "$stamp")" == "$want" ]]; then
        log "node_modules up to date with package-lock.json"
        return 0
    fi
    npm ci --no-audit --no-fund
    printf '%s\n' "$want" >"$stamp"
}

install_deps() {
    ensure_system_tools
    ensure_rust_components
    ensure_node_modules
}

# ---- checks ----------------------------------------------------------------

# The repository speaks of itself: its text names commits (short hashes, `git log
# --format='%h %cd %s'`), dates and machines (cores and CPU model), never the bookkeeping
# of the work that wrote it. Fails listing file:line for each tracked text file (binary
# files skipped) that uses one of the phrases below, and each tracked file name with
# such a number. The words are assembled from pieces so that this file does not match
# its own pattern; the one-word phrases match as whole words only.
check_wording() {
    if ! git -C "$ROOT" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
        log "not a git checkout: wording check skipped"
        return 0
    fi
    local b='(^|[^[:alnum:]_])' e='([^[:alnum:]_]|$)'
    local st='st''op' se='ses''sion' le='le''nt' ho='ho''st'
    local pattern="${b}${st}s? ?[0-9]|${b}${se}|${b}${le}${e}|this ${ho}${e}|this ${st}${e}"
    local lines names
    lines="$(git -C "$ROOT" grep -n -I -i -E -e "$pattern" | cut -c1-200 || true)"
    names="$(git -C "$ROOT" ls-files | grep -i -E "${st}[_ -]?[0-9]" || true)"
    if [[ -z "$lines" && -z "$names" ]]; then
        return 0
    fi
    log "name commits, dates and machines instead (pattern: $pattern):"
    [[ -n "$lines" ]] && printf '%s\n' "$lines"
    [[ -n "$names" ]] && printf '%s\n' "$names" | sed 's/^/file name: /'
    log "$(printf '%s' "$lines" | grep -c . || true) lines, $(printf '%s' "$names" | grep -c . || true) file names"
    return 1
}

check_fmt() { cargo fmt --all --check; }

# Test output is shown as it comes and also kept, to tally the results.
run_tests() { cargo test --release --workspace --all-targets --no-fail-fast 2>&1 | tee "$LOG_DIR/test.log"; }

run_doctests() { cargo test --release --workspace --doc 2>&1 | tee "$LOG_DIR/doctest.log"; }

check_clippy() { cargo clippy --workspace --all-targets -- -D warnings; }

# The library's docs build with every intra-doc link resolved.
check_docs() {
    RUSTDOCFLAGS="-D rustdoc::broken_intra_doc_links" cargo doc --no-deps -p meshflow --features train,data-build
}

# The build tool's own test comes first: build-web.sh relies on it.
run_snip_tests() { node tests/snip-wasm.test.mjs 2>&1 | tee "$LOG_DIR/snip-wasm.log"; }

build_web() { bash scripts/build-web.sh; }

# The wasm-only modules are invisible to the native clippy run above; both browser modules
# (the CPU one and the WebGPU one, which has no CPU backend) are checked as built.
check_clippy_wasm() {
    cargo clippy --target wasm32-unknown-unknown -p meshflow --features web,webgl \
        --profile wasm-release -- -D warnings &&
        cargo clippy --target wasm32-unknown-unknown -p meshflow --no-default-features \
            --features web,wgpu --profile wasm-release -- -D warnings
}

run_browser_tests() { node tests/e2e/browser.test.mjs 2>&1 | tee "$LOG_DIR/browser.log"; }

# ---- driver ----------------------------------------------------------------

# Sum the "test result: ok. 3 passed; 0 failed; 1 ignored; ..." lines.
tally() {
    cat "$LOG_DIR"/*.log 2>/dev/null |
        sed 's/\x1b\[[0-9;]*m//g' |
        awk '/^test result:/ {
                for (i = 1; i <= NF; i++) {
                    if ($(i+1) ~ /^passed/)  p += $i
                    if ($(i+1) ~ /^failed/)  f += $i
                    if ($(i+1) ~ /^ignored/) s += $i
                }
             }
             /^(browser|snip-wasm): [0-9]+ passed, [0-9]+ failed/ { p += $2; f += $4 }
             END { printf "%d passed, %d failed, %d skipped\n", p, f, s }'
}

print_summary() {
    local i
    echo
    log "steps:"
    for i in "${!STEP_NAMES[@]}"; do
        printf '[test.sh]   %-8s %-12s %s\n' "${STEP_STATUS[$i]}" "${STEP_NAMES[$i]}" "${STEP_TIMES[$i]}"
    done
    echo "summary: $(tally)"
}

# run_step NAME FUNCTION: run it with errexit in force (a subshell, so that a
# failing command inside the function stops it), time it, and stop the whole
# run on failure.
run_step() {
    local name="$1" start rc elapsed
    shift
    echo
    log "==> $name"
    start="$(now_ms)"
    set +e
    (
        set -e
        "$@"
    )
    rc=$?
    set -e
    elapsed="$(fmt_secs $(($(now_ms) - start)))"
    STEP_NAMES+=("$name")
    STEP_TIMES+=("$elapsed")
    if ((rc == 0)); then
        STEP_STATUS+=("ok")
        log "<== $name: ok in $elapsed"
    else
        STEP_STATUS+=("FAILED")
        log "<== $name: FAILED (exit $rc) after $elapsed"
        print_summary
        log "FAILED at step: $name"
        exit "$rc"
    fi
}

# The golden vectors live in shared/golden beside the checkout. A clone made elsewhere (say
# /tmp) finds them beside the repository it was cloned from, unless MESHFLOW_GOLDEN_DIR says.
find_golden() {
    [[ -n "${MESHFLOW_GOLDEN_DIR:-}" || -d "$ROOT/../shared/golden" ]] && return 0
    local origin
    origin="$(git -C "$ROOT" remote get-url origin 2>/dev/null || true)"
    if [[ -n "$origin" && -d "$origin/../shared/golden" ]]; then
        MESHFLOW_GOLDEN_DIR="$(cd "$origin/../shared/golden" && pwd)"
        export MESHFLOW_GOLDEN_DIR
        log "golden vectors: $MESHFLOW_GOLDEN_DIR (beside the clone's origin)"
    fi
}

main() {
    log "repo: $ROOT"
    find_golden
    log "CARGO_TARGET_DIR=$CARGO_TARGET_DIR"
    run_step wording check_wording
    run_step install install_deps
    run_step fmt check_fmt
    run_step test run_tests
    run_step doctest run_doctests
    run_step clippy check_clippy
    run_step docs check_docs
    run_step snip-wasm run_snip_tests
    run_step web build_web
    run_step clippy-wasm check_clippy_wasm
    run_step browser run_browser_tests
    print_summary
}

main "$@"
