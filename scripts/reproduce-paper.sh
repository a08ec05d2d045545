#!/usr/bin/env bash
# Regenerate the paper reproduction (Wang et al. 2013, Figs. 8-15) with one command: build the
# reproduce_paper tool (Release, tools/) and run it. It writes docs/paper-reproduction.md and
# docs/paper-reproduction/*.csv and *.svg (the old CSV/SVG files there are removed first), and
# prints its progress on stderr. Arguments go to reproduce_paper (e.g. --threads 1).
# Environment: ROLLGAP_BUILD_DIR (default build), ROLLGAP_WERROR (default ON), ROLLGAP_JOBS.
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

if ! grep -Eq '^[[:space:]]*add_subdirectory\(tools\)' CMakeLists.txt; then
    echo "reproduce-paper.sh: the top-level CMakeLists.txt has no add_subdirectory(tools);" \
         "the reproduce_paper target is defined in tools/CMakeLists.txt" >&2
    exit 1
fi

# Build output goes to stderr, like scripts/bench.sh.
rollgap_install_deps >&2
rollgap_configure >&2
rollgap_build reproduce_paper >&2

out_dir=docs/paper-reproduction
mkdir -p "$out_dir"
rm -f "$out_dir"/*.csv "$out_dir"/*.svg
"$ROLLGAP_BUILD_DIR/tools/reproduce_paper" --out "$out_dir" --doc docs/paper-reproduction.md "$@"
