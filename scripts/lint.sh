#!/usr/bin/env bash
# Static checks run by scripts/test.sh (and by hand): shellcheck on every shell script, and
# clang-tidy (.clang-tidy: the naming rules plus a few bug-prone checks) on the sources of core/,
# api/ and service/. clang-tidy needs a compilation database with one entry per source file, so
# it uses a configure-only tree of its own (build-tidy/, the release preset without unity
# batches) where only the generated headers are built. Exits non-zero on any finding and prints
# how long each part took.
#
# Environment: ROLLGAP_TIDY_BUILD_DIR (default build-tidy), ROLLGAP_JOBS as for the other
# scripts.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

status=0
tidy_dir="${ROLLGAP_TIDY_BUILD_DIR:-build-tidy}"

start=$(date +%s)
mapfile -t shell_scripts < <(git ls-files '*.sh' .ci/run)
if shellcheck -x "${shell_scripts[@]}"; then
    echo "lint: shellcheck: ${#shell_scripts[@]} scripts clean ($(($(date +%s) - start)) s)"
else
    echo "lint: shellcheck found the problems above"
    status=1
fi

start=$(date +%s)
(cd "$ROLLGAP_ROOT" && cmake --preset release -B "$tidy_dir" -DROLLGAP_UNITY=OFF \
    -DCMAKE_CXX_COMPILER_LAUNCHER= -DROLLGAP_WERROR=OFF) >/dev/null
cmake --build "$tidy_dir" --target rollgap_generated >/dev/null
mapfile -t sources < <(git ls-files 'core/*.cpp' 'api/*.cpp' 'service/*.cpp')
log=$(mktemp)
if run-clang-tidy -quiet -p "$tidy_dir" -j "$ROLLGAP_JOBS" "${sources[@]/#/$ROLLGAP_ROOT/}" \
    >"$log" 2>&1 && ! grep -qE '(warning|error): ' "$log"; then
    echo "lint: clang-tidy: ${#sources[@]} files clean ($(($(date +%s) - start)) s)"
else
    grep -E '(warning|error): ' "$log" | sort -u || tail -20 "$log"
    echo "lint: clang-tidy found the problems above ($(($(date +%s) - start)) s)"
    status=1
fi
rm -f "$log"
exit "$status"
