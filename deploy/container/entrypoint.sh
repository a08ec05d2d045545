#!/usr/bin/env bash
# The container image's entrypoint (/usr/local/bin/rollgap-container; docs/operations.md:
# "Container and Kubernetes").
#
#   rollgap-container proxied       the default: one container, nginx in front of the service.
#                                   nginx with the front proxy's configuration (deploy/nginx/
#                                   rollgap.conf, only its two addresses set, as scripts/
#                                   run-proxy.sh and the tests set them) listens on
#                                   $ROLLGAP_PROXY_LISTEN (default 8080: every interface); the
#                                   service listens on 127.0.0.1:$ROLLGAP_SERVICE_PORT (default
#                                   8090) only, so a published port is always nginx's.
#   rollgap-container ARGS...       rollgap ARGS... (serve, run -, healthcheck, scenario, ...);
#                                   the Kubernetes pod runs the two processes as two containers.
#
# In the proxied mode SIGTERM or SIGINT (docker stop) stops both: nginx gracefully (SIGQUIT:
# it finishes the requests it holds) and the service drains (SIGTERM); the exit status is the
# service's. Should either process end on its own, the other is stopped and the container
# exits non-zero, so the runtime's restart policy sees one failure, never a half-alive pair.
#
# The service's other settings come from the environment as usual (ROLLGAP_WORKERS, ROLLGAP_
# STORE, ROLLGAP_TOKEN_FILE, ...); ROLLGAP_BIND and ROLLGAP_PORT are set here and a different
# ROLLGAP_BIND is refused (it would be unreachable or unproxied). nginx's pid file and
# temporary bodies go to $ROLLGAP_NGINX_PREFIX (default /tmp/nginx; a tmpfs when the root
# filesystem is read-only). ROLLGAP_BINARY, ROLLGAP_NGINX_BINARY and ROLLGAP_NGINX_CONF name
# the programs and the configuration (the image's paths by default; the test
# tests/system/test_container_entrypoint.cpp runs this script outside an image with them).
set -euo pipefail

ROLLGAP="${ROLLGAP_BINARY:-/usr/local/bin/rollgap}"

if [[ $# -eq 0 || "$1" != proxied ]]; then
    exec "$ROLLGAP" "$@"
fi
if [[ $# -ne 1 ]]; then
    echo "rollgap-container: 'proxied' takes no arguments (settings come from ROLLGAP_* variables)" >&2
    exit 2
fi

NGINX="${ROLLGAP_NGINX_BINARY:-/usr/sbin/nginx}"
CONFIG="${ROLLGAP_NGINX_CONF:-/etc/rollgap/nginx/rollgap.conf}"
PREFIX="${ROLLGAP_NGINX_PREFIX:-/tmp/nginx}"
LISTEN="${ROLLGAP_PROXY_LISTEN:-8080}"
SERVICE_PORT="${ROLLGAP_SERVICE_PORT:-8090}"

log() { printf 'rollgap-container: %s\n' "$*" >&2; }

if [[ -n "${ROLLGAP_BIND:-}" && "${ROLLGAP_BIND}" != 127.0.0.1 ]]; then
    log "ROLLGAP_BIND=$ROLLGAP_BIND: in the proxied mode the service listens on 127.0.0.1 behind nginx (publish ROLLGAP_PROXY_LISTEN's port instead)"
    exit 2
fi
if ! [[ "$SERVICE_PORT" =~ ^[0-9]+$ ]] || ! [[ "$LISTEN" =~ ^([0-9.]+:|\[[0-9a-fA-F:]+\]:)?[0-9]+$ ]]; then
    log "ROLLGAP_SERVICE_PORT must be a port and ROLLGAP_PROXY_LISTEN a port or ADDRESS:PORT"
    exit 2
fi
# Both addresses must be where the tests expect them, once each (scripts/run-proxy.sh checks
# the same): a configuration that moved them is refused, never half-applied.
if [[ $(grep -c '^        listen 8080;$' "$CONFIG") -ne 1 || $(grep -c 'server 127\.0\.0\.1:8090 ' "$CONFIG") -ne 1 ]]; then
    log "$CONFIG no longer has exactly one 'listen 8080;' and one 'server 127.0.0.1:8090'"
    exit 1
fi
mkdir -p "$PREFIX"
sed -e "s/^        listen 8080;\$/        listen $LISTEN;/" \
    -e "s/server 127\.0\.0\.1:8090 /server 127.0.0.1:$SERVICE_PORT /" "$CONFIG" >"$PREFIX/rollgap.conf"
"$NGINX" -t -q -p "$PREFIX/" -c "$PREFIX/rollgap.conf" -e stderr

export ROLLGAP_BIND=127.0.0.1 ROLLGAP_PORT="$SERVICE_PORT"
# nginx is the edge: it passes the public Host, and server_name decides what is served.
export ROLLGAP_ALLOWED_HOSTS="${ROLLGAP_ALLOWED_HOSTS:-*}"

stopping=0
rollgap_pid=""
nginx_pid=""
stop() {
    stopping=1
    # Either may have ended already: kill's failure is no error here.
    if [[ -n "$nginx_pid" ]]; then kill -QUIT "$nginx_pid" 2>/dev/null || true; fi
    if [[ -n "$rollgap_pid" ]]; then kill -TERM "$rollgap_pid" 2>/dev/null || true; fi
}
trap stop TERM INT

"$ROLLGAP" serve &
rollgap_pid=$!
# The access log is /dev/stdout, which a non-root nginx cannot open when stdout is the
# runtime's (root's) pipe; a pipe made by this user it can (the Kubernetes pod's "| cat").
# setsid: nginx and its worker in a process group of their own (a background child of this
# shell leads no group, so setsid runs nginx in place: $! is nginx), so that a master that dies
# abruptly does not leave its worker holding the port.
setsid "$NGINX" -p "$PREFIX/" -c "$PREFIX/rollgap.conf" -e stderr > >(cat) &
nginx_pid=$!
log "nginx on $LISTEN (pid $nginx_pid) -> rollgap serve on 127.0.0.1:$SERVICE_PORT (pid $rollgap_pid)"

# Until a signal arrives or one of the two ends (wait -n -p: bash 5.1, Debian 12 has 5.2).
ended=""
ended_status=0
while [[ $stopping -eq 0 && -z "${ended:-}" ]]; do
    ended_status=0
    wait -n -p ended "$rollgap_pid" "$nginx_pid" || ended_status=$?
done
failed=0
if [[ -n "${ended:-}" && $stopping -eq 0 ]]; then
    if [[ "$ended" == "$rollgap_pid" ]]; then
        log "the service ended on its own (status $ended_status): stopping nginx"
    else
        log "nginx ended on its own (status $ended_status): stopping the service"
    fi
    failed=1
    stop
    # nginx's worker outlives a master killed outright: its whole group goes.
    if [[ "$ended" == "$nginx_pid" ]]; then kill -KILL -- "-$nginx_pid" 2>/dev/null || true; fi
fi

# The exit status of background process $1 into reaped_status, waiting through signals (a
# trapped signal interrupts wait; the process may still be draining).
reaped_status=0
reap() {
    if [[ "$1" == "${ended:-}" ]]; then
        reaped_status=$ended_status
        return
    fi
    while :; do
        reaped_status=0
        wait "$1" || reaped_status=$?
        kill -0 "$1" 2>/dev/null || return 0
    done
}
reap "$nginx_pid"
reap "$rollgap_pid"
if [[ $failed -ne 0 ]]; then
    exit $((reaped_status == 0 ? 1 : reaped_status))
fi
log "stopped (the service's exit status $reaped_status)"
exit "$reaped_status"
