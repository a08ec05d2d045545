#!/usr/bin/env bash
# Runs one contract script (tests/contract/<name>.mjs) against the rollgap binary; fails with a
# clear message when node or the npm tools are missing (scripts/install-node-tools.sh).
# usage: run.sh NAME path/to/rollgap
set -euo pipefail
name=$1
binary=$2
tools="${ROLLGAP_NODE_TOOLS:-/var/cache/rollgap/node-tools}"
if ! command -v node >/dev/null 2>&1; then
    echo "contract test $name: node is not on PATH; run scripts/install-node-tools.sh" >&2
    exit 1
fi
if [[ ! -d "$tools/node_modules/ajv" || ! -x "$tools/node_modules/.bin/tsc" ]]; then
    echo "contract test $name: the npm tools are missing in $tools; run scripts/install-node-tools.sh" >&2
    exit 1
fi
exec node "$(dirname "${BASH_SOURCE[0]}")/$name.mjs" "$binary"
