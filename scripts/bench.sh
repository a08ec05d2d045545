#!/usr/bin/env bash
# Build rollgap (Release) and run every benchmark executable (build/bench/bench_*), printing
# their figures, one "name: value unit" line each. Arguments are passed to every bench binary
# (e.g. --filter roll_gap, --min-time 2, --reps 5000).
# Environment: ROLLGAP_BUILD_DIR (default build), ROLLGAP_WERROR (default ON), ROLLGAP_JOBS.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

# Bench targets come from bench/bench_*.cpp (one executable each, see bench/CMakeLists.txt).
targets=()
for src in bench/bench_*.cpp; do
    targets+=("$(basename "$src" .cpp)")
done

# Build output goes to stderr, so stdout carries only the figures.
rollgap_install_deps >&2
rollgap_configure >&2
rollgap_build "${targets[@]}" >&2

status=0
for t in "${targets[@]}"; do
    bin="$ROLLGAP_BUILD_DIR/bench/$t"
    printf '# %s\n' "$t" >&2
    "$bin" "$@" || { echo "bench.sh: $t failed (exit $?)" >&2; status=1; }
done
exit "$status"
