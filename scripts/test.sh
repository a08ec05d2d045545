#!/usr/bin/env bash
# Build rollgap (Release, warnings as errors) and run the whole test suite with ctest.
# This is the README's test command and exactly what CI runs (.ci/run).
#
# ctest's closing line "100% tests passed, 0 tests failed out of N" is what CI reads.
# Environment: ROLLGAP_WERROR=OFF to allow warnings in a local experiment (CI keeps it ON),
# ROLLGAP_BUILD_DIR (default build), ROLLGAP_JOBS (default nproc),
# ROLLGAP_TEST_TIMEOUT per-test timeout in seconds (default 600).
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

rollgap_install_deps     # a fast no-op when the packages are installed
bash "$ROLLGAP_ROOT/scripts/install-node-tools.sh" >/dev/null  # contract tests' npm tools, outside the tree
rollgap_configure
# shellcheck disable=SC2119  # no targets: build everything
rollgap_build
# --no-tests=error: a build that registered no test must fail, not pass silently.
ctest --test-dir "$ROLLGAP_BUILD_DIR" --output-on-failure --no-tests=error \
    --timeout "${ROLLGAP_TEST_TIMEOUT:-600}"
