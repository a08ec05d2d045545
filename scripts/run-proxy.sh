#!/usr/bin/env bash
# Run the front proxy (Debian's nginx with deploy/nginx/rollgap.conf) in the foreground in
# front of a running service (docs/operations.md: "Front proxy"):
#
#   bash scripts/run-service.sh &          # the service on 127.0.0.1:8080
#   bash scripts/run-proxy.sh              # the proxy on 127.0.0.1:8000 -> 127.0.0.1:8080
#   curl -s localhost:8000/readyz
#
# Options: --listen ADDRESS:PORT (default 127.0.0.1:8000; the port clients use),
#          --service PORT (default 8080; the service's port on 127.0.0.1).
# The configuration is used as it is; only its two marked addresses are set (as the test
# tests/system/test_http_front_proxy.cpp does). nginx's files (pid, temporary bodies) go to a
# temporary directory removed on exit; its access log goes to stdout, its errors to stderr.
# Ctrl-C or SIGTERM stops it. Installs nginx if it is missing (scripts/install-deps.sh).
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

LISTEN=127.0.0.1:8000
SERVICE_PORT=8080
while [[ $# -gt 0 ]]; do
    case "$1" in
        --listen) LISTEN="$2"; shift 2 ;;
        --service) SERVICE_PORT="$2"; shift 2 ;;
        -h | --help) sed -n '2,16p' "$0"; exit 0 ;;
        *) echo "run-proxy: unknown argument $1 (--help)" >&2; exit 2 ;;
    esac
done
[[ "$LISTEN" == *:* ]] || LISTEN="127.0.0.1:$LISTEN"

rollgap_install_deps >&2
CONFIG=deploy/nginx/rollgap.conf
# Both addresses must be where the test expects them, once each.
if [[ $(grep -c '^        listen 8080;$' "$CONFIG") -ne 1 || $(grep -c 'server 127\.0\.0\.1:8090 ' "$CONFIG") -ne 1 ]]; then
    echo "run-proxy: $CONFIG no longer has exactly one 'listen 8080;' and one 'server 127.0.0.1:8090'" >&2
    exit 1
fi

prefix=$(mktemp -d)
chmod 755 "$prefix"   # nginx's workers (nobody, when started as root) use its temporary directories
nginx_pid=""
cleanup() {
    if [[ -n "$nginx_pid" ]] && kill -0 "$nginx_pid" 2>/dev/null; then
        kill -QUIT "$nginx_pid" 2>/dev/null || true
        wait "$nginx_pid" 2>/dev/null || true
    fi
    rm -rf "$prefix"
}
trap cleanup EXIT
trap 'exit 0' INT TERM

sed -e "s/^        listen 8080;\$/        listen $LISTEN;/" \
    -e "s/server 127\.0\.0\.1:8090 /server 127.0.0.1:$SERVICE_PORT /" "$CONFIG" >"$prefix/rollgap.conf"
/usr/sbin/nginx -t -q -p "$prefix/" -c "$prefix/rollgap.conf" -e stderr
if ! curl -sf "http://127.0.0.1:$SERVICE_PORT/readyz" >/dev/null 2>&1; then
    echo "run-proxy: nothing answers on 127.0.0.1:$SERVICE_PORT yet (start it: bash scripts/run-service.sh); nginx answers 502 until it does" >&2
fi
echo "run-proxy: http://$LISTEN -> 127.0.0.1:$SERVICE_PORT (deploy/nginx/rollgap.conf)" >&2
/usr/sbin/nginx -p "$prefix/" -c "$prefix/rollgap.conf" -e stderr &
nginx_pid=$!
wait "$nginx_pid"
