# shellcheck shell=bash
# Shared by the HTTP load scripts (bench-http.sh, load.sh; sourced after common.sh, not run):
# wrk's installation, the wrk Lua functions that count answers by status, and starting and
# stopping `rollgap serve` on loopback.

# wrk from Debian if it is missing.
load_install_wrk() {
    command -v wrk >/dev/null && return 0
    echo "installing wrk" >&2
    local sudo=()
    [[ $(id -u) -ne 0 ]] && sudo=(sudo)
    "${sudo[@]}" apt-get update >&2
    "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends wrk >&2
}

# Prints wrk Lua functions that count the answers by status over all threads and print
# "statuses: 200=N 503=M" when wrk is done; append them to a wrk script.
load_status_counter_lua() {
    cat <<'LUA'
local threads = {}
function setup(thread) table.insert(threads, thread) end
function init(args) statuses = {} end
function response(status, headers, body) statuses[status] = (statuses[status] or 0) + 1 end
function done(summary, latency, requests)
    local total = {}
    for _, thread in ipairs(threads) do
        for status, count in pairs(thread:get("statuses")) do total[status] = (total[status] or 0) + count end
    end
    local parts = {}
    for status, count in pairs(total) do table.insert(parts, status .. "=" .. count) end
    table.sort(parts)
    io.write("statuses: " .. table.concat(parts, " ") .. "\n")
end
LUA
}

# load_start_server LOG URL [rollgap serve arguments...]: the service in the background (its
# pid in $server_pid), its log appended to LOG (so LOG may be emptied while it runs); waits
# up to 10 s for URL/readyz.
load_start_server() {
    local log=$1 url=$2
    shift 2
    "$ROLLGAP_BUILD_DIR/rollgap" serve "$@" 2>>"$log" &
    server_pid=$!
    for _ in $(seq 1 100); do
        curl -sf "$url/readyz" >/dev/null 2>&1 && return 0
        sleep 0.1
    done
    echo "the server did not become ready" >&2
    cat "$log" >&2
    exit 1
}

# SIGTERM to $server_pid, and wait for it.
load_stop_server() {
    kill -TERM "$server_pid" 2>/dev/null || true
    wait "$server_pid" 2>/dev/null || true
    server_pid=""
}
