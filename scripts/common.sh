# shellcheck shell=bash
# Shared by scripts/*.sh (sourced, not run): one build directory and one set of configure
# flags, so the service, test and bench scripts reuse each other's build instead of
# reconfiguring it back and forth.
#
#   ROLLGAP_BUILD_DIR       build directory (default: build, so the CLI is build/rollgap)
#   ROLLGAP_ASAN_BUILD_DIR  the sanitizer + fuzzer build (default: build-asan; clang, ASan+UBSan)
#   ROLLGAP_WERROR          ON (default, locally and in CI) or OFF: warnings are errors
#   ROLLGAP_JOBS            parallel build jobs (default: nproc)

ROLLGAP_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ROLLGAP_BUILD_DIR="${ROLLGAP_BUILD_DIR:-build}"
ROLLGAP_ASAN_BUILD_DIR="${ROLLGAP_ASAN_BUILD_DIR:-build-asan}"
ROLLGAP_WERROR="${ROLLGAP_WERROR:-ON}"
ROLLGAP_JOBS="${ROLLGAP_JOBS:-$(nproc)}"

rollgap_install_deps() {
    bash "$ROLLGAP_ROOT/scripts/install-deps.sh"
}

# The presets build with Ninja (every object of every target compiles in parallel; with Make a
# target's objects wait for the libraries it links). A build directory an older checkout
# configured for another generator is re-configured from scratch: cmake refuses to switch.
rollgap_forget_other_generator() {
    local dir="$1"
    [[ "$dir" == /* ]] || dir="$ROLLGAP_ROOT/$dir"
    local cache="$dir/CMakeCache.txt"
    if [[ -f "$cache" ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$cache"; then
        rm -rf "$cache" "$dir/CMakeFiles"
    fi
}

# The build flags live in CMakePresets.json (presets release and asan); these only choose the
# directory and the warnings policy.
rollgap_configure() {
    rollgap_forget_other_generator "$ROLLGAP_BUILD_DIR"
    (cd "$ROLLGAP_ROOT" && cmake --preset release -B "$ROLLGAP_BUILD_DIR" -DROLLGAP_WERROR="$ROLLGAP_WERROR")
}

# The same sources with clang under AddressSanitizer (LeakSanitizer on) and UBSan, every report
# fatal, plus the libFuzzer harnesses of fuzz/ (preset asan: ROLLGAP_SANITIZE, ROLLGAP_FUZZ). Its
# ctest runs the whole suite and replays the fuzz seed corpora.
rollgap_configure_asan() {
    rollgap_forget_other_generator "$ROLLGAP_ASAN_BUILD_DIR"
    (cd "$ROLLGAP_ROOT" && cmake --preset asan -B "$ROLLGAP_ASAN_BUILD_DIR" -DROLLGAP_WERROR="$ROLLGAP_WERROR")
}

# Run-time settings for the sanitizer build's programs (exported: the tests start the rollgap
# binary and it inherits them). Leaks are reported at exit; any report fails the program.
rollgap_sanitizer_env() {
    export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:check_initialization_order=1:detect_stack_use_after_return=1"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    # Leaks inside Debian's libpq/libpqxx when a server goes away (scripts/lsan.supp).
    export LSAN_OPTIONS="suppressions=$ROLLGAP_ROOT/scripts/lsan.supp:print_suppressions=0"
}

# rollgap_build_in <dir> [target...]: build everything in <dir>, or only the given targets.
rollgap_build_in() {
    local dir="$1"
    shift
    local args=()
    local t
    for t in "$@"; do args+=(--target "$t"); done
    cmake --build "$dir" -j"$ROLLGAP_JOBS" "${args[@]}"
}

# What the sanitizer stage needs (the asan build preset's targets): the program, the test
# runners, the fuzz harnesses; the benchmarks and tools are built (and warned about) by the
# Release build.
# shellcheck disable=SC2034  # used by the scripts that source this file
ROLLGAP_ASAN_TARGETS=(rollgap rollgap_tests fuzz_harnesses)

# rollgap_build [target...]: the same in $ROLLGAP_BUILD_DIR.
rollgap_build() {
    rollgap_build_in "$ROLLGAP_BUILD_DIR" "$@"
}
