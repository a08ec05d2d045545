#!/usr/bin/env bash
# Regenerate the tandem mill's verification report with one command: build the verify_mill tool
# (Release, tools/) and run it. It writes docs/mill-verification.md (the specification's
# identities, the Padé-order convergence, the Lu et al. 2019 schedule, the default mill's critical
# speeds over span length and interstand tension) and prints its progress on stderr. Arguments go
# to verify_mill (e.g. --threads 1). A few minutes on two cores.
# Environment: ROLLGAP_BUILD_DIR (default build), ROLLGAP_WERROR (default ON), ROLLGAP_JOBS.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

# Build output goes to stderr, like scripts/bench.sh.
rollgap_install_deps >&2
rollgap_configure >&2
rollgap_build verify_mill >&2

"$ROLLGAP_BUILD_DIR/tools/verify_mill" --doc docs/mill-verification.md "$@"
