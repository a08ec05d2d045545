#!/usr/bin/env bash
# Checks of the HTTP service's machine-readable outputs that need tools CI does not install:
#   - the OpenAPI document served at /openapi.json passes `@redocly/cli lint` (installed with
#     npm into a temporary directory, never into the repository);
#   - /metrics passes `promtool check metrics` (Debian package prometheus, installed if missing).
# Builds rollgap, starts it on a loopback port, sends a few requests, checks, stops it.
# Environment: CHECK_PORT (default 18095), ROLLGAP_BUILD_DIR etc. as for the other scripts.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

PORT="${CHECK_PORT:-18095}"
URL="http://127.0.0.1:$PORT"
SUDO=(); [[ $(id -u) -ne 0 ]] && SUDO=(sudo)

if ! command -v promtool >/dev/null; then
    echo "check-http: installing prometheus (for promtool)" >&2
    "${SUDO[@]}" apt-get update >&2
    "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends prometheus >&2
fi
command -v npm >/dev/null || { echo "check-http: npm is needed for @redocly/cli (apt-get install npm)" >&2; exit 1; }
rollgap_install_deps >&2
rollgap_configure >&2
rollgap_build rollgap >&2

work=$(mktemp -d)
server_pid=""
# shellcheck disable=SC2317  # run by the EXIT trap
cleanup() {
    if [[ -n "$server_pid" ]]; then kill -TERM "$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; fi
    rm -rf "$work"
}
trap cleanup EXIT

"$ROLLGAP_BUILD_DIR/rollgap" serve --bind 127.0.0.1 --port "$PORT" 2>"$work/server.log" &
server_pid=$!
for _ in $(seq 1 100); do curl -sf "$URL/readyz" >/dev/null 2>&1 && break; sleep 0.1; done

# Some traffic, so that every metric family has samples.
curl -s -o /dev/null -X POST "$URL/v1/roll-gap" -H 'Content-Type: application/json' -d '{}'
curl -s -o /dev/null -X POST "$URL/v1/roll-gap" -H 'Content-Type: application/json' -d '{"scenario":{"x":1}}'
curl -s -o /dev/null "$URL/nothing"
curl -s -o /dev/null -X POST "$URL/v1/jobs" -H 'Content-Type: application/json' -d '{"analysis":"roll_gap"}'

curl -sf "$URL/openapi.json" > "$work/openapi.json"
curl -sf "$URL/metrics" > "$work/metrics.txt"

status=0
echo "== promtool check metrics"
if promtool check metrics < "$work/metrics.txt"; then echo "OK"; else status=1; fi

echo "== @redocly/cli lint /openapi.json"
(cd "$work" && npm init -y >/dev/null 2>&1 && npm install --silent --no-audit --no-fund @redocly/cli >/dev/null 2>&1) || {
    echo "check-http: npm install @redocly/cli failed" >&2
    exit 1
}
if (cd "$work" && npx --no-install redocly lint openapi.json --format=stylish); then echo "OK"; else status=1; fi
exit "$status"
