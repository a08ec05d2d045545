#!/usr/bin/env bash
# Install the dependencies, build rollgap and run the HTTP service (`build/rollgap serve`) on
# http://localhost:8080 in the foreground, the default scenario ready (README.md; the API:
# docs/http-api.md).
# Ctrl-C or SIGTERM drains it and exits 0.
#
# Extra arguments are passed to `rollgap serve` (e.g. --port 9000 --workers 4; --help).
# Environment: ROLLGAP_BUILD_DIR (default build), ROLLGAP_WERROR (default ON), ROLLGAP_JOBS.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

run_service() {
    local cli="$ROLLGAP_BUILD_DIR/rollgap"
    exec "$cli" serve "$@"
}

# Build output goes to stderr, like the service's log.
rollgap_install_deps >&2
rollgap_configure >&2
rollgap_build rollgap >&2
run_service "$@"
