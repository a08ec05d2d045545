#!/usr/bin/env bash
# Static checks run by scripts/test.sh (and by hand): shellcheck on every shell script, and
# clang-tidy (.clang-tidy: the naming rules plus a few bug-prone checks) on the sources of core/,
# api/ and service/. Exits non-zero on any finding and prints how long each part took.
#
# Environment: ROLLGAP_BUILD_DIR, ROLLGAP_WERROR, ROLLGAP_JOBS as for the other scripts.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

status=0

# Approximate comparisons in the tests are relative (tests/support/approx.h says why doctest's
# own Approx is not: its scale 1 makes a tolerance absolute below 1).
if raw=$(git grep -n 'doctest::Approx(' -- tests ':!tests/support/approx.h'); then
    echo "$raw"
    echo "lint: tests compare with rollgap::test::approx (tests/support/approx.h), not doctest::Approx"
    status=1
else
    echo "lint: tests: every approximate comparison relative"
fi

start=$(date +%s)
mapfile -t shell_scripts < <(git ls-files '*.sh' .ci/run)
if shellcheck -x "${shell_scripts[@]}"; then
    echo "lint: shellcheck: ${#shell_scripts[@]} scripts clean ($(($(date +%s) - start)) s)"
else
    echo "lint: shellcheck found the problems above"
    status=1
fi

# clang-tidy reads the Release build's compilation database (rollgap_configure: configured, not
# built; only its generated headers are made here). With unity builds (ROLLGAP_UNITY, the
# default) it parses the batches of the core, api, store, service and http libraries, so each
# heavy header is parsed once per batch, and reports what it finds in their sources.
start=$(date +%s)
rollgap_configure >/dev/null
cmake --build "$ROLLGAP_BUILD_DIR" --target rollgap_generated >/dev/null
mapfile -t units < <(python3 - "$ROLLGAP_BUILD_DIR/compile_commands.json" "$ROLLGAP_ROOT" <<'PY'
import json, re, sys
root = sys.argv[2].rstrip("/") + "/"
libraries = r"/(rollgap_core|rollgap_api|rollgap_store|rollgap_service_lib|rollgap_http)\.dir/Unity/"
for entry in json.load(open(sys.argv[1])):
    path = entry["file"]
    if re.search(libraries, path) or re.match(re.escape(root) + r"(core|api|service)/.*\.cpp$", path):
        print(path)
PY
)
log=$(mktemp)
if [[ ${#units[@]} -eq 0 ]]; then
    echo "lint: clang-tidy: no core/api/service sources in $ROLLGAP_BUILD_DIR/compile_commands.json"
    status=1
elif run-clang-tidy -quiet -p "$ROLLGAP_BUILD_DIR" -j "$ROLLGAP_JOBS" "${units[@]}" >"$log" 2>&1 &&
    ! grep -qE '(warning|error): ' "$log"; then
    echo "lint: clang-tidy: ${#units[@]} translation units clean ($(($(date +%s) - start)) s)"
else
    grep -E '(warning|error): ' "$log" | sed -E 's/\x1b\[[0-9;]*m//g' | sort -u || tail -20 "$log"
    echo "lint: clang-tidy found the problems above ($(($(date +%s) - start)) s)"
    status=1
fi
rm -f "$log"
exit "$status"
