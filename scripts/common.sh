# shellcheck shell=bash
# Shared by scripts/*.sh (sourced, not run): one build directory and one set of configure
# flags, so the service, test and bench scripts reuse each other's build instead of
# reconfiguring it back and forth.
#
#   ROLLGAP_BUILD_DIR  build directory (default: build, so the CLI is build/rollgap)
#   ROLLGAP_WERROR     ON (default, locally and in CI) or OFF: warnings are errors
#   ROLLGAP_JOBS       parallel build jobs (default: nproc)

ROLLGAP_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ROLLGAP_BUILD_DIR="${ROLLGAP_BUILD_DIR:-build}"
ROLLGAP_WERROR="${ROLLGAP_WERROR:-ON}"
ROLLGAP_JOBS="${ROLLGAP_JOBS:-$(nproc)}"

rollgap_install_deps() {
    bash "$ROLLGAP_ROOT/scripts/install-deps.sh"
}

rollgap_configure() {
    cmake -S "$ROLLGAP_ROOT" -B "$ROLLGAP_BUILD_DIR" \
        -DCMAKE_BUILD_TYPE=Release \
        -DROLLGAP_WERROR="$ROLLGAP_WERROR"
}

# rollgap_build [target...]: build everything, or only the given targets.
rollgap_build() {
    local args=()
    local t
    for t in "$@"; do args+=(--target "$t"); done
    cmake --build "$ROLLGAP_BUILD_DIR" -j"$ROLLGAP_JOBS" "${args[@]}"
}
