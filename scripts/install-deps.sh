#!/usr/bin/env bash
# Install rollgap's build and test dependencies on Debian 12 (bookworm).
#
# Idempotent: if every package is already installed it returns at once without touching apt
# (no apt-get update, no root needed), so every other script can call it first.
# Runs as root; otherwise uses sudo when it is available.
set -euo pipefail

# --- The packages -------------------------------------------------------------------------
# Add new packages to one of these groups (or a new group) and to PACKAGES below.
BUILD_PACKAGES=(build-essential cmake ninja-build pkg-config)
LIBRARY_PACKAGES=(libeigen3-dev libsundials-dev libcpp-httplib-dev nlohmann-json3-dev libspdlog-dev libcli11-dev libsqlite3-dev libpqxx-dev libssl-dev)
# postgresql: the job store tests start a PostgreSQL 15 server of their own (initdb, pg_ctl).
# sqlite3: the migration test makes a store of the previous schema with the sqlite3 program.
TEST_PACKAGES=(doctest-dev postgresql sqlite3)
# The sanitizer build and the fuzzers (scripts/test.sh, scripts/fuzz.sh): clang 14 (clang++),
# its sanitizer and libFuzzer runtimes (libclang-rt-14-dev is only a Recommends of clang, and
# --no-recommends below would leave it out) and llvm for llvm-symbolizer (readable stacks).
SANITIZER_PACKAGES=(clang libclang-rt-14-dev llvm)
# Tools for scripts and CI.
# curl: the test that runs the documentation's HTTP examples; nginx: the test that runs two
# service instances behind a load balancer. (wrk and prometheus/promtool are installed by the
# scripts that use them, bench-http.sh and check-http.sh, not in CI.)
# clang-format: the format check of scripts/test.sh (scripts/check-format.sh); clang-tidy
# (run-clang-tidy) and shellcheck: its static checks (scripts/lint.sh).
# python3-yaml: deploy/check.py, the static check of the Kubernetes files (ctest deploy_check).
TOOL_PACKAGES=(curl nginx clang-format clang-tidy shellcheck python3-yaml)
# The browser workbench: Chart.js embedded at build time; chromium runs its browser tests.
WEB_PACKAGES=(libjs-chart.js chromium)

PACKAGES=("${BUILD_PACKAGES[@]}" "${LIBRARY_PACKAGES[@]}" "${TEST_PACKAGES[@]}" "${SANITIZER_PACKAGES[@]}"
          "${TOOL_PACKAGES[@]}" "${WEB_PACKAGES[@]}")
# -------------------------------------------------------------------------------------------

log() { printf 'install-deps: %s\n' "$*" >&2; }

if ! command -v dpkg-query >/dev/null 2>&1; then
    log "dpkg-query not found: this script targets Debian 12 (bookworm)."
    log "Install the equivalents of: ${PACKAGES[*]}"
    exit 1
fi

# A package counts as installed only when dpkg says "install ok installed".
missing=()
for pkg in "${PACKAGES[@]}"; do
    status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
    if [[ "$status" != "install ok installed" ]]; then
        missing+=("$pkg")
    fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
    log "all ${#PACKAGES[@]} packages already installed; nothing to do."
    exit 0
fi

log "missing: ${missing[*]}"

SUDO=()
if [[ $(id -u) -ne 0 ]]; then
    if command -v sudo >/dev/null 2>&1; then
        SUDO=(sudo)
    else
        log "not root and sudo is not available: run as root, or install: ${missing[*]}"
        exit 1
    fi
fi

export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
# Install the whole list (not only the missing ones) so apt resolves them together; packages
# already present are left as they are.
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y --no-install-recommends "${PACKAGES[@]}" </dev/null
log "done."
