#!/usr/bin/env bash
# Benchmark the HTTP service with wrk on loopback: POST /v1/roll-gap (default scenario, no
# distributions) and GET /livez at 16 and 64 connections, then an overload run (a short queue,
# 64 connections) that must answer only 200s and fast 503s with flat memory.
# Prints one line per run: requests/s, p50 and p99 latency, status codes, the server's RSS.
#
# Environment: BENCH_DURATION (default 10s), BENCH_THREADS (wrk threads, default 2),
# BENCH_PORT (default 18090), ROLLGAP_BUILD_DIR etc. as for the other scripts.
# Installs wrk if it is missing (Debian package). Targets only 127.0.0.1; every run is bounded.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
# shellcheck source=scripts/load-lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/load-lib.sh"
cd "$ROLLGAP_ROOT"

DURATION="${BENCH_DURATION:-10s}"
THREADS="${BENCH_THREADS:-2}"
PORT="${BENCH_PORT:-18090}"
URL="http://127.0.0.1:$PORT"

load_install_wrk
rollgap_install_deps >&2
rollgap_configure >&2
rollgap_build rollgap >&2

work=$(mktemp -d)
server_pid=""
cleanup() {
    if [[ -n "$server_pid" ]] && kill -0 "$server_pid" 2>/dev/null; then
        kill -TERM "$server_pid" 2>/dev/null || true
        wait "$server_pid" 2>/dev/null || true
    fi
    rm -rf "$work"
}
trap cleanup EXIT

cat > "$work/roll_gap.lua" <<'LUA'
wrk.method = "POST"
wrk.body = '{"options":{"distributions":false}}'
wrk.headers["Content-Type"] = "application/json"
LUA
# The same request, counting the status codes of the answers (overload run).
{ cat "$work/roll_gap.lua"; load_status_counter_lua; } > "$work/roll_gap_statuses.lua"

start_server() { load_start_server "$work/server.log" "$URL" --bind 127.0.0.1 --port "$PORT" "$@"; }
stop_server() { load_stop_server; }

rss_mib() { awk -v key="$2" '$1 == key":" {printf "%.1f", $2 / 1024}' "/proc/$1/status"; }

# run NAME CONNECTIONS [wrk arguments...]: one wrk run, one summary line.
run() {
    local name=$1 connections=$2
    shift 2
    wrk -t"$THREADS" -c"$connections" -d"$DURATION" --latency "$@" > "$work/wrk.txt" 2>&1 || {
        cat "$work/wrk.txt" >&2
        return 1
    }
    local rps p50 p99 non2xx errors statuses
    rps=$(awk '/^Requests\/sec:/ {print $2}' "$work/wrk.txt")
    p50=$(awk '$1 == "50%" {print $2}' "$work/wrk.txt")
    p99=$(awk '$1 == "99%" {print $2}' "$work/wrk.txt")
    non2xx=$(awk '/Non-2xx or 3xx responses:/ {print $NF}' "$work/wrk.txt")
    errors=$(awk '/Socket errors:/ {sub(/.*Socket errors: /, ""); print}' "$work/wrk.txt")
    statuses=$(awk '/^statuses:/ {sub(/^statuses: /, ""); print}' "$work/wrk.txt")
    printf '%-28s conns=%-3s req/s=%-9s p50=%-9s p99=%-9s non2xx=%-7s %s%s rss=%s MiB peak_rss=%s MiB\n' \
        "$name" "$connections" "$rps" "$p50" "$p99" "${non2xx:-0}" \
        "${statuses:+statuses: $statuses }" "${errors:+socket_errors: $errors }" \
        "$(rss_mib "$server_pid" VmRSS)" "$(rss_mib "$server_pid" VmHWM)"
}

echo "# rollgap serve on $URL, $(nproc) cores, wrk -t$THREADS -d$DURATION; server log: info level to a file"
start_server
curl -sf -X POST "$URL/v1/roll-gap" -H 'Content-Type: application/json' -d '{"options":{"distributions":false}}' >/dev/null
run "POST /v1/roll-gap" 16 -s "$work/roll_gap.lua" "$URL/v1/roll-gap"
run "POST /v1/roll-gap" 64 -s "$work/roll_gap.lua" "$URL/v1/roll-gap"
run "GET /livez" 16 "$URL/livez"
run "GET /livez" 64 "$URL/livez"
stop_server

echo "# overload: --queue-length 4 --io-threads 128, 64 connections (expect 200s and fast 503s only)"
start_server --queue-length 4 --io-threads 128
run "POST /v1/roll-gap overload" 64 -s "$work/roll_gap_statuses.lua" "$URL/v1/roll-gap"
run "POST /v1/roll-gap overload 2" 64 -s "$work/roll_gap_statuses.lua" "$URL/v1/roll-gap"
stop_server
