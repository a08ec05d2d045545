#!/usr/bin/env bash
# Install the dependencies, build the rollgap CLI and run the service.
#
# The HTTP service does not exist yet (planned). Until it does, "running the service" means
# one roll-gap analysis of the default scenario through the CLI: the request below goes to
# `build/rollgap run -` on stdin and the JSON result is printed.
# Switching to the HTTP service later is one line: the command in run_service().
#
# Extra arguments are passed to the CLI after the subcommand.
# Environment: ROLLGAP_BUILD_DIR (default build), ROLLGAP_WERROR (default ON), ROLLGAP_JOBS.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

DEFAULT_REQUEST='{"analysis":"roll_gap"}'

run_service() {
    local cli="$ROLLGAP_BUILD_DIR/rollgap"
    # Later, for the HTTP service:  exec "$cli" serve "$@"
    printf '%s\n' "$DEFAULT_REQUEST" | "$cli" run - "$@"
}

# Build output goes to stderr, so stdout carries only the service's output (pipe it to jq).
rollgap_install_deps >&2
rollgap_configure >&2
rollgap_build rollgap >&2
run_service "$@"
