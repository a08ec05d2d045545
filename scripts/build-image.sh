#!/usr/bin/env bash
# Build the container image (Dockerfile) with buildah, without a Docker engine, and check that
# the image's binary serves /readyz.
#
# 1. The base image debian:bookworm-slim is made locally with debootstrap (no registry is
#    reachable here), once; the runs after it reuse it.
# 2. buildah bud builds the Dockerfile (chroot isolation, vfs storage: works unprivileged in
#    a container and needs no daemon).
# 3. Smoke test: the image's root filesystem is mounted and its /usr/local/bin/rollgap runs in a
#    chroot as the image's user (uid 10001) on 127.0.0.1:$PORT with the image's data directory
#    (ROLLGAP_DATA_DIR=/var/lib/rollgap); the script waits for /readyz to answer 200, computes a
#    roll gap, runs a job to the end (with the job store: kept in the SQLite file under the data
#    directory, which the image's user must be able to create), runs the image's HEALTHCHECK
#    command, sends SIGTERM and expects exit status 0; checks the entrypoint (rollgap-container,
#    default command proxied) and that it passes other commands to the binary.
#
# Runs as root (debootstrap, buildah, chroot). Takes several minutes the first time.
# Environment: ROLLGAP_IMAGE (default rollgap:dev), ROLLGAP_SMOKE_PORT (default 18181).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

IMAGE="${ROLLGAP_IMAGE:-rollgap:dev}"
PORT="${ROLLGAP_SMOKE_PORT:-18181}"
BASE=docker.io/library/debian:bookworm-slim
B=(buildah --storage-driver vfs)

log() { printf 'build-image: %s\n' "$*" >&2; }

if [[ $(id -u) -ne 0 ]]; then
    log "run as root (debootstrap, buildah and chroot need it)"
    exit 1
fi
if ! command -v buildah >/dev/null || ! command -v debootstrap >/dev/null || ! command -v curl >/dev/null; then
    log "installing buildah, debootstrap and curl"
    apt-get update >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends buildah debootstrap curl >&2
fi

# ---- 1. the base image ----------------------------------------------------------------------
if ! "${B[@]}" images --quiet "$BASE" >/dev/null 2>&1; then
    mirror=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
    mirror="${mirror:-http://deb.debian.org/debian}"
    rootfs=$(mktemp -d)
    log "debootstrap bookworm (minbase) from $mirror"
    debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >&2
    c=$("${B[@]}" from scratch)
    m=$("${B[@]}" mount "$c")
    cp -a "$rootfs"/. "$m"/
    "${B[@]}" umount "$c" >/dev/null
    "${B[@]}" commit -q "$c" "$BASE" >/dev/null
    "${B[@]}" rm "$c" >/dev/null
    rm -rf "$rootfs"
    log "base image $BASE committed"
fi

# ---- 2. the image ---------------------------------------------------------------------------
log "building $IMAGE"
start=$(date +%s)
# Docker format: the OCI image format has no HEALTHCHECK.
"${B[@]}" bud --isolation chroot --pull-never --layers --format docker -t "$IMAGE" . >&2
log "built $IMAGE in $(( $(date +%s) - start )) s"
"${B[@]}" inspect --type image --format \
    'user={{.OCIv1.Config.User}} ports={{.OCIv1.Config.ExposedPorts}} entrypoint={{.OCIv1.Config.Entrypoint}} cmd={{.OCIv1.Config.Cmd}} healthcheck={{.Docker.Config.Healthcheck.Test}}{{println}}' \
    "$IMAGE" >&2

# ---- 3. smoke test: the image's binary serves /readyz ----------------------------------------
c=$("${B[@]}" from --pull-never "$IMAGE")
m=$("${B[@]}" mount "$c")
server_pid=""
cleanup() {
    if [[ -n "$server_pid" ]] && kill -0 "$server_pid" 2>/dev/null; then kill -KILL "$server_pid" 2>/dev/null || true; fi
    "${B[@]}" umount "$c" >/dev/null 2>&1 || true
    "${B[@]}" rm "$c" >/dev/null 2>&1 || true
}
trap cleanup EXIT

CHROOT=$(command -v chroot)
log "starting the image's rollgap serve on 127.0.0.1:$PORT (chroot, uid 10001)"
# A chroot does not apply the image's ENV: the data directory is passed as the image sets it.
env -i PATH=/usr/local/bin:/usr/bin:/bin ROLLGAP_BIND=127.0.0.1 ROLLGAP_PORT="$PORT" ROLLGAP_INSTANCE=smoke \
    ROLLGAP_DATA_DIR=/var/lib/rollgap \
    "$CHROOT" --userspec=10001:10001 "$m" /usr/local/bin/rollgap serve >&2 &
server_pid=$!

status=000
for _ in $(seq 1 100); do
    status=$(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:$PORT/readyz" || true)
    [[ "$status" == 200 ]] && break
    sleep 0.1
done
if [[ "$status" != 200 ]]; then
    log "FAIL: /readyz answered $status"
    exit 1
fi
log "/readyz: 200"
answer=$(curl -s -X POST "http://127.0.0.1:$PORT/v1/roll-gap" -H 'Content-Type: application/json' \
    -d '{"options":{"distributions":false}}')
if [[ "$answer" != *'"status":"ok"'* ]]; then
    log "FAIL: POST /v1/roll-gap answered: $answer"
    exit 1
fi
log "POST /v1/roll-gap: a result with status ok"
job=$(curl -s -o /dev/null -w '%header{location}' -X POST "http://127.0.0.1:$PORT/v1/jobs" \
    -H 'Content-Type: application/json' -d '{"analysis": "evaluate"}')
if [[ "$job" != /v1/jobs/* ]]; then
    log "FAIL: POST /v1/jobs gave no job location ($job)"
    exit 1
fi
state=""
for _ in $(seq 1 300); do
    state=$(curl -s "http://127.0.0.1:$PORT$job" | sed -n 's/.*"state":"\([a-z_]*\)".*/\1/p')
    [[ "$state" == succeeded || "$state" == failed || "$state" == cancelled ]] && break
    sleep 0.1
done
if [[ "$state" != succeeded ]]; then
    log "FAIL: the job $job ended as '$state'"
    exit 1
fi
log "job $job: succeeded"
# A binary with the job store (it knows --data-dir) keeps the job in the data directory's
# SQLite file, created by the image's user.
if "$CHROOT" "$m" /usr/local/bin/rollgap serve --help 2>/dev/null | grep -q -- '--data-dir'; then
    if [[ ! -s "$m/var/lib/rollgap/jobs.db" ]]; then
        log "FAIL: no job store at /var/lib/rollgap/jobs.db in the image's data directory"
        exit 1
    fi
    log "job store: /var/lib/rollgap/jobs.db ($(stat -c 'uid %u, gid %g, %s bytes' "$m/var/lib/rollgap/jobs.db"))"
fi
env -i ROLLGAP_PORT="$PORT" "$CHROOT" --userspec=10001:10001 "$m" /usr/local/bin/rollgap healthcheck >&2
log "HEALTHCHECK command: exit 0"
# The entrypoint and its default (the single-container proxied mode, tested with this build's
# binary and Debian's nginx by tests/system/test_container_entrypoint.cpp); any other command
# reaches the binary.
entry=$("${B[@]}" inspect --type image --format '{{.OCIv1.Config.Entrypoint}} {{.OCIv1.Config.Cmd}}' "$IMAGE")
if [[ "$entry" != "[/usr/local/bin/rollgap-container] [proxied]" ]]; then
    log "FAIL: entrypoint and command are $entry, not [/usr/local/bin/rollgap-container] [proxied]"
    exit 1
fi
env -i PATH=/usr/local/bin:/usr/bin:/bin "$CHROOT" --userspec=10001:10001 "$m" /usr/local/bin/rollgap-container --version >&2
log "entrypoint: rollgap-container proxied by default; other commands run rollgap"
kill -TERM "$server_pid"
exit_status=0
wait "$server_pid" || exit_status=$?
server_pid=""
if [[ $exit_status -ne 0 ]]; then
    log "FAIL: rollgap serve exited $exit_status after SIGTERM"
    exit 1
fi
log "SIGTERM: drained, exit 0"
size=$("${B[@]}" images --format '{{.Size}}' "$IMAGE" | head -1)
log "OK: $IMAGE ($size) serves /readyz"
