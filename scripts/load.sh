#!/usr/bin/env bash
# Load runs of the HTTP service that print their figures (docs/performance.md: "Load figures"):
#
#   overload  more concurrent requests than the workers and the queue hold: answers by status,
#             p99 of the accepted (200) requests, service RSS at start, middle and end.
#   soak      a long mixed load (analyses, documents, health, jobs created, polled and deleted):
#             answers by status, p99 of the accepted requests, RSS at start, middle and end.
#   sigterm   SIGTERM in the middle of a steady load, then with one slow client as well: the
#             time from SIGTERM to the process's exit, its exit status, the answers by status.
#   all       the three in turn (default).
#
# bash scripts/load.sh [overload|soak|sigterm|all]
#
# Environment: LOAD_PORT (default 18190; the service's admin listener, where the build has one,
# gets LOAD_PORT+1), LOAD_CONNECTIONS (64), LOAD_THREADS (wrk threads, 2),
# LOAD_OVERLOAD_DURATION (20 s), LOAD_SOAK_DURATION (60 s), LOAD_DRAIN_TIMEOUT_MS (2000),
# LOAD_EXIT_LIMIT (90 s: a process still running then is killed and reported as such),
# ROLLGAP_BUILD_DIR etc. as for the other scripts. Installs wrk if it is missing (Debian
# package). Targets only 127.0.0.1; every run is bounded in time.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
# shellcheck source=scripts/load-lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/load-lib.sh"
cd "$ROLLGAP_ROOT"

MODE="${1:-all}"
PORT="${LOAD_PORT:-18190}"
CONNECTIONS="${LOAD_CONNECTIONS:-64}"
THREADS="${LOAD_THREADS:-2}"
OVERLOAD_DURATION="${LOAD_OVERLOAD_DURATION:-20}"
SOAK_DURATION="${LOAD_SOAK_DURATION:-60}"
DRAIN_TIMEOUT_MS="${LOAD_DRAIN_TIMEOUT_MS:-2000}"
EXIT_LIMIT="${LOAD_EXIT_LIMIT:-90}"
URL="http://127.0.0.1:$PORT"

case "$MODE" in
    overload | soak | sigterm | all) ;;
    *)
        echo "usage: $0 [overload|soak|sigterm|all]" >&2
        exit 2
        ;;
esac

load_install_wrk
rollgap_install_deps >&2
rollgap_configure >&2
rollgap_build rollgap >&2
CLI="$ROLLGAP_BUILD_DIR/rollgap"

# The admin listener (/livez, /readyz, /metrics on threads of their own) exists in newer builds:
# give it a port beside ours so runs do not collide on its default.
ADMIN_ARGS=()
if "$CLI" serve --help 2>&1 | grep -q -- '--admin-port'; then
    ADMIN_ARGS=(--admin-port "$((PORT + 1))")
fi

work=$(mktemp -d)
server_pid=""
background_pids=()
cleanup() {
    local pid
    for pid in "${background_pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    if [[ -n "$server_pid" ]] && kill -0 "$server_pid" 2>/dev/null; then
        kill -KILL "$server_pid" 2>/dev/null || true
        wait "$server_pid" 2>/dev/null || true
    fi
    rm -rf "$work"
}
trap cleanup EXIT

# wrk script: POST one analysis (the request in $LOAD_BODY and $LOAD_PATH per run), or a
# mixed load, counting the answers by status over all threads.
{
    cat <<'LUA'
local mix = os.getenv("LOAD_MIX") == "1"
local requests = {
    {"POST", "/v1/roll-gap", '{"options":{"distributions":false}}'},
    {"POST", "/v1/roll-gap", '{}'},
    {"POST", "/v1/stability", '{}'},
    {"POST", "/v1/roll-gap", '{"scenario":{"strip":{"reduction":5}}}'},
    {"GET", "/v1/scenarios/default", nil},
    {"GET", "/openapi.json", nil},
    {"GET", "/readyz", nil},
    {"GET", "/metrics", nil},
}
local single = {"POST", os.getenv("LOAD_PATH") or "/v1/stability", os.getenv("LOAD_BODY") or "{}"}
local counter = 0
function request()
    local r = single
    if mix then counter = counter + 1; r = requests[(counter % #requests) + 1] end
    local headers = {}
    if r[3] then headers["Content-Type"] = "application/json" end
    return wrk.format(r[1], r[2], headers, r[3])
end
LUA
    load_status_counter_lua
} >"$work/load.lua"

# start_server [serve arguments...]: the service on loopback, its log (info: one line per
# request) in $work/server.log.
start_server() {
    : >"$work/server.log"
    load_start_server "$work/server.log" "$URL" --bind 127.0.0.1 --port "$PORT" "${ADMIN_ARGS[@]}" --log-level info "$@"
}

rss_mib() { awk '$1 == "VmRSS:" {printf "%.1f", $2 / 1024}' "/proc/$1/status" 2>/dev/null || echo "-"; }

# The p99 of the accepted requests (status=200 lines of the service's request log), in ms,
# and how many there were.
accepted_p99() {
    grep -o 'status=200 duration_ms=[0-9.]*' "$work/server.log" | sed 's/.*duration_ms=//' | sort -n |
        awk '{ v[NR] = $1 } END { if (NR == 0) { print "- (none)"; exit } i = int(NR * 0.99); if (i < 1) i = 1; printf "%.1f ms (of %d)", v[i], NR }'
}

# wrk_run SECONDS OUTPUT [env...]: wrk in the background against $URL; its pid in $wrk_pid.
wrk_run() {
    local seconds=$1 output=$2
    shift 2
    # --timeout: an accepted request that waited long still counts as answered.
    env "$@" wrk -t"$THREADS" -c"$CONNECTIONS" -d"${seconds}s" --timeout 40s --latency -s "$work/load.lua" "$URL" >"$output" 2>&1 &
    wrk_pid=$!
    background_pids+=("$wrk_pid")
}

wrk_summary() {
    local file=$1 rps p99 statuses errors
    rps=$(awk '/^Requests\/sec:/ {print $2}' "$file")
    p99=$(awk '$1 == "99%" {print $2}' "$file")
    statuses=$(awk '/^statuses:/ {sub(/^statuses: /, ""); print}' "$file")
    errors=$(awk '/Socket errors:/ {sub(/.*Socket errors: /, ""); print}' "$file")
    printf 'req/s=%s p99(all answers)=%s statuses: %s%s' "${rps:--}" "${p99:--}" "${statuses:-none}" \
        "${errors:+ socket_errors: $errors}"
}

# A load run of SECONDS with RSS sampled at start, middle and end.
measured_run() {
    local name=$1 seconds=$2
    shift 2
    local start middle end
    start=$(rss_mib "$server_pid")
    wrk_run "$seconds" "$work/wrk.txt" "$@"
    sleep "$((seconds / 2))"
    middle=$(rss_mib "$server_pid")
    wait "$wrk_pid" || true
    end=$(rss_mib "$server_pid")
    printf '%-10s %s\n' "$name" "$(wrk_summary "$work/wrk.txt")"
    printf '%-10s p99(accepted, service log)=%s rss_mib start=%s middle=%s end=%s\n' "$name" "$(accepted_p99)" \
        "$start" "$middle" "$end"
}

overload() {
    echo "# overload: POST /v1/stability, $CONNECTIONS connections, ${OVERLOAD_DURATION}s;" \
        "--workers 2 --queue-length 8 --io-threads 128 (expect 200s and fast 503s only)"
    start_server --workers 2 --queue-length 8 --io-threads 128
    measured_run overload "$OVERLOAD_DURATION" LOAD_PATH=/v1/stability LOAD_BODY='{}'
    load_stop_server
}

# Jobs during the soak: create, poll until finished, delete; one at a time, counted by status.
job_loop() {
    local until=$1 created=0 deleted=0 cancelled=0 refused=0 location status
    while [[ $(date +%s) -lt $until ]]; do
        location=$(curl -s -o /dev/null -w '%header{location}' -X POST "$URL/v1/jobs" \
            -H 'Content-Type: application/json' -d '{"analysis": "stability"}' || true)
        if [[ -z "$location" ]]; then
            refused=$((refused + 1))
            sleep 0.5
            continue
        fi
        created=$((created + 1))
        for _ in $(seq 1 100); do
            status=$(curl -s "$URL$location" | grep -o '"state":"[a-z]*"' || true)
            [[ "$status" == *queued* || "$status" == *running* ]] || break
            sleep 0.1
        done
        # 204: a finished job deleted; 200/202: a queued or running one cancelled.
        case $(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$URL$location") in
            204) deleted=$((deleted + 1)) ;;
            200 | 202) cancelled=$((cancelled + 1)) ;;
        esac
    done
    echo "jobs: created=$created finished+deleted=$deleted cancelled=$cancelled refused=$refused" >"$work/jobs.txt"
}

soak() {
    echo "# soak: mixed requests (roll gap, stability, invalid scenario, default scenario, OpenAPI," \
        "readyz, metrics), $CONNECTIONS connections, ${SOAK_DURATION}s, and a job loop;" \
        "--workers 2 --queue-length 32 --io-threads 128"
    start_server --workers 2 --queue-length 32 --io-threads 128
    job_loop "$(($(date +%s) + SOAK_DURATION))" &
    local jobs_pid=$!
    background_pids+=("$jobs_pid")
    measured_run soak "$SOAK_DURATION" LOAD_MIX=1
    wait "$jobs_pid" || true
    printf '%-10s %s\n' soak "$(cat "$work/jobs.txt")"
    load_stop_server
}

# A client that sends one header byte every 5 s and never finishes its request.
slow_client() {
    exec 3<>"/dev/tcp/127.0.0.1/$PORT" || return 0
    local request="GET /livez HTTP/1.1"$'\r\n'"Host: x"$'\r\n'"X-Slow: aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"
    local i
    for ((i = 0; i < ${#request}; i++)); do
        printf '%s' "${request:i:1}" >&3 2>/dev/null || return 0
        sleep 5
    done
}

# sigterm_run NAME SLOW_CLIENTS: SIGTERM 5 s into a steady overload, then the time to exit.
sigterm_run() {
    local name=$1 slow=$2 i
    start_server --workers 2 --queue-length 8 --io-threads 128 --drain-timeout-ms "$DRAIN_TIMEOUT_MS"
    for ((i = 0; i < slow; i++)); do
        slow_client &
        background_pids+=("$!")
    done
    : >"$work/server.log"
    wrk_run "$((EXIT_LIMIT + 30))" "$work/wrk.txt" LOAD_PATH=/v1/stability LOAD_BODY='{}'
    sleep 5
    local rss before after exit_status=0 outcome
    rss=$(rss_mib "$server_pid")
    before=$(date +%s.%N)
    kill -TERM "$server_pid"
    local deadline=$(($(date +%s) + EXIT_LIMIT))
    while kill -0 "$server_pid" 2>/dev/null && [[ $(date +%s) -lt $deadline ]]; do sleep 0.05; done
    after=$(date +%s.%N)
    if kill -0 "$server_pid" 2>/dev/null; then
        outcome="still running after ${EXIT_LIMIT}s: killed"
        kill -KILL "$server_pid"
        wait "$server_pid" 2>/dev/null || true
    else
        wait "$server_pid" || exit_status=$?
        outcome="exited with status $exit_status"
    fi
    server_pid=""
    kill -INT "$wrk_pid" 2>/dev/null || true
    wait "$wrk_pid" 2>/dev/null || true
    for pid in "${background_pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    background_pids=()
    printf '%-22s exit_after_sigterm=%ss (drain timeout %ss) %s; rss_mib at SIGTERM=%s\n' "$name" \
        "$(awk -v a="$after" -v b="$before" 'BEGIN { printf "%.1f", a - b }')" \
        "$(awk -v t="$DRAIN_TIMEOUT_MS" 'BEGIN { printf "%.1f", t / 1000 }')" "$outcome" "$rss"
    printf '%-22s %s\n' "$name" "$(wrk_summary "$work/wrk.txt")"
    printf '%-22s p99(accepted, service log)=%s; answers the service logged during the run: %s, of which 504: %s\n' \
        "$name" "$(accepted_p99)" "$(grep -c 'request id=' "$work/server.log" || true)" \
        "$(grep -c 'status=504' "$work/server.log" || true)"
}

sigterm() {
    echo "# sigterm: POST /v1/stability, $CONNECTIONS connections; SIGTERM after 5 s;" \
        "--drain-timeout-ms $DRAIN_TIMEOUT_MS; the process is killed if it still runs after ${EXIT_LIMIT}s"
    sigterm_run "sigterm" 0
    sigterm_run "sigterm+slow-client" 1
}

echo "# rollgap serve on $URL ($("$CLI" --version 2>&1 | head -1)), $(nproc) cores, wrk -t$THREADS -c$CONNECTIONS, $(date -u +%FT%TZ)"
case "$MODE" in
    overload) overload ;;
    soak) soak ;;
    sigterm) sigterm ;;
    all)
        overload
        soak
        sigterm
        ;;
esac
