#!/usr/bin/env bash
# Build the libFuzzer harnesses of fuzz/ (clang, ASan + UBSan, in build-asan/) and run each for a
# bounded time, starting from its seed corpus fuzz/corpus/<harness>/. Prints one line per
# harness with its executions; exits non-zero when a harness finds a crash, a leak, undefined
# behaviour, a broken invariant or an input slower than the per-input timeout (the input is
# kept under $ROLLGAP_ASAN_BUILD_DIR/fuzz-artifacts/ and its path printed: make it a test).
#
# Usage: scripts/fuzz.sh [harness...]      (default: every fuzz/fuzz_*.cpp)
# Environment: ROLLGAP_FUZZ_SECONDS per harness (default 60), ROLLGAP_FUZZ_TIMEOUT seconds per
# input (default 30), ROLLGAP_FUZZ_NO_BUILD=1 to skip the build (scripts/test.sh built it),
# ROLLGAP_ASAN_BUILD_DIR, ROLLGAP_WERROR, ROLLGAP_JOBS as for the other scripts.
#
# New inputs that reach new code go to a scratch corpus, not into the repository. To grow the
# seed corpus, minimise it into fuzz/corpus/<harness>/ with libFuzzer's -merge=1.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

seconds="${ROLLGAP_FUZZ_SECONDS:-60}"
timeout="${ROLLGAP_FUZZ_TIMEOUT:-30}"
harnesses=("$@")
if [[ ${#harnesses[@]} -eq 0 ]]; then
    for src in fuzz/fuzz_*.cpp; do harnesses+=("$(basename "$src" .cpp)"); done
fi

if [[ "${ROLLGAP_FUZZ_NO_BUILD:-0}" != 1 ]]; then
    rollgap_install_deps >&2
    rollgap_configure_asan >&2
    rollgap_build_in "$ROLLGAP_ASAN_BUILD_DIR" "${harnesses[@]}" >&2
fi
rollgap_sanitizer_env

artifacts="$ROLLGAP_ASAN_BUILD_DIR/fuzz-artifacts"
mkdir -p "$artifacts"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

# run_harness <harness>: one bounded run; its exit status goes to $scratch/<harness>.rc.
run_harness() {
    local h="$1"
    local bin="$ROLLGAP_ASAN_BUILD_DIR/fuzz/$h" seeds="fuzz/corpus/$h" result=0
    mkdir -p "$scratch/$h"
    local args=(-max_total_time="$seconds" -timeout="$timeout" -rss_limit_mb=2560 -print_final_stats=1
                -artifact_prefix="$artifacts/$h-")
    [[ -f "fuzz/$h.dict" ]] && args+=(-dict="fuzz/$h.dict")
    "$bin" "${args[@]}" "$scratch/$h" "$seeds" >"$scratch/$h.log" 2>&1 || result=$?
    echo "$result" >"$scratch/$h.rc"
}

# The harnesses run ROLLGAP_JOBS at a time: each is one single-threaded process, so on two
# cores two of them get the same time each as one alone would, in half the wall time.
running=0
for h in "${harnesses[@]}"; do
    if [[ $running -ge $ROLLGAP_JOBS ]]; then
        wait -n || true
        running=$((running - 1))
    fi
    run_harness "$h" &
    running=$((running + 1))
done
wait || true

status=0
failed=()
for h in "${harnesses[@]}"; do
    log="$scratch/$h.log"
    result=$(cat "$scratch/$h.rc" 2>/dev/null || echo "no exit status")
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    corpus=$(grep -Eo 'corp: [0-9]+/[0-9]+[a-zA-Z]*' "$log" | tail -1 | cut -d' ' -f2 || true)
    if [[ $result == 0 ]]; then
        printf 'fuzz: %s: %s executions in %s s, corpus %s, no finding\n' "$h" "${execs:-?}" "$seconds" "${corpus:-?}"
    else
        status=1
        printf 'fuzz: %s: FAILED (exit %s) after %s executions\n' "$h" "$result" "${execs:-?}"
        grep -E 'ERROR|invariant broken|runtime error|SUMMARY|Test unit written|^#0 |^    #[0-9] ' "$log" | head -40 || true
        echo "fuzz: full log of $h:" && tail -60 "$log"
        failed+=("$h")
    fi
done
# Last, where a truncated CI log still shows it: why each failed harness stopped and the input
# that did it (base64, when small), so that the finding can be reproduced without the machine:
#   base64 -d > crash && build-asan/fuzz/<harness> crash
for h in "${failed[@]}"; do
    log="$scratch/$h.log"
    echo "fuzz: $h stopped on:"
    grep -E 'invariant broken|runtime error|ERROR: |deadly signal|timeout|out-of-memory' "$log" | head -5 || true
    input=$(sed -n "s/.*Test unit written to \(.*\)$/\1/p" "$log" | tail -1)
    if [[ -n $input && -f $input && $(stat -c %s "$input") -le 4096 ]]; then
        echo "fuzz: the input ($(stat -c %s "$input") bytes, base64):"
        base64 -w 100 "$input"
    fi
done
exit "$status"
