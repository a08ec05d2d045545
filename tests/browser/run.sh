#!/usr/bin/env bash
# The browser tests of the workbench (ctest: browser_workbench). Fails, never skips, when
# chromium or node is missing: CI installs both (scripts/install-deps.sh, scripts/install-node-tools.sh).
#   run.sh <rollgap binary> <screenshot dir>
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
chromium_bin="${CHROMIUM:-/usr/bin/chromium}"
if [[ ! -x "$chromium_bin" ]]; then
    echo "browser tests: $chromium_bin not found (Debian package chromium, scripts/install-deps.sh)" >&2
    exit 1
fi
tools=$(bash "$here/../../scripts/install-node-tools.sh" | tail -n 1)
if ! command -v node >/dev/null 2>&1; then
    echo "browser tests: node not found" >&2
    exit 1
fi
export ROLLGAP_NODE_TOOLS="$tools" CHROMIUM="$chromium_bin"
exec node "$here/workbench.test.mjs" "$1" "$2"
