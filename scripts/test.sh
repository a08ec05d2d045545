#!/usr/bin/env bash
# The README's test command and exactly what CI runs (.ci/run). In order:
#   0. check that every tracked C++ file is formatted as .clang-format says (check-format.sh),
#      and the static checks (lint.sh: shellcheck on the scripts, clang-tidy on core/api/service);
#   1. build (Release, GCC, warnings as errors) in build/ and run the whole suite with ctest;
#   2. build the same sources with clang under ASan + LeakSanitizer + UBSan (every report
#      fatal) in build-asan/ and run the whole suite again, plus the fuzz seed corpora;
#   3. run each libFuzzer harness of fuzz/ for a bounded time (scripts/fuzz.sh).
# Every stage runs even when an earlier one failed, so one run shows everything. The last line
# is the summary CI reads, "rollgap: N passed, M failed": N counts the ctest tests passed in
# both suites plus the fuzz harnesses that found nothing; a build that fails counts as one
# failure. The exit status is non-zero when M > 0.
#
# Environment: ROLLGAP_WERROR=OFF to allow warnings in a local experiment (CI keeps it ON),
# ROLLGAP_BUILD_DIR (default build), ROLLGAP_ASAN_BUILD_DIR (default build-asan),
# ROLLGAP_JOBS (default nproc), ROLLGAP_TEST_TIMEOUT per-test timeout in seconds (default 600),
# ROLLGAP_FUZZ_SECONDS per harness (default 60; 0 skips the fuzz stage, counted as failed in CI).
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
cd "$ROLLGAP_ROOT"

passed=0
failed=0
start=$(date +%s)
# Each stage's start; the summary at the end lists how long each took (CI shows only the tail).
stage_names=()
stage_starts=()
stage() {
    stage_names+=("$*")
    stage_starts+=("$(date +%s)")
    printf '\n==== rollgap test: %s (%d s)\n' "$*" "$(( $(date +%s) - start ))"
}
stage_times() {
    local i next
    for ((i = 0; i + 1 < ${#stage_names[@]}; i++)); do
        next=${stage_starts[i + 1]}
        printf 'rollgap test: %5d s  %s\n' "$((next - stage_starts[i]))" "${stage_names[i]}"
    done
}

# run_suite <build dir> <label>: ctest over the whole suite; adds its counts to the summary.
run_suite() {
    local dir="$1" label="$2" log
    log=$(mktemp)
    local result=0
    # --no-tests=error: a build that registered no test must fail, not pass silently.
    # -j: tests run ROLLGAP_JOBS at a time; those that time or saturate the machine run alone
    # (RUN_SERIAL, tests/test_properties.cmake).
    ctest --test-dir "$dir" -j"$ROLLGAP_JOBS" --output-on-failure --no-tests=error \
        --timeout "${ROLLGAP_TEST_TIMEOUT:-600}" 2>&1 | tee "$log" || result=$?
    local line total bad
    line=$(grep -E '^[0-9]+% tests passed, [0-9]+ tests? failed out of [0-9]+' "$log" | tail -1 || true)
    rm -f "$log"
    if [[ -z "$line" ]]; then
        echo "rollgap test: $label: ctest printed no summary (exit $result)"
        failed=$((failed + 1))
        return
    fi
    total=$(sed -E 's/.* out of ([0-9]+).*/\1/' <<<"$line")
    bad=$(sed -E 's/.*passed, ([0-9]+) tests? failed.*/\1/' <<<"$line")
    passed=$((passed + total - bad))
    failed=$((failed + bad))
    if [[ $result -ne 0 && $bad -eq 0 ]]; then failed=$((failed + 1)); fi
    echo "rollgap test: $label: $((total - bad)) of $total passed"
}

rollgap_install_deps     # a fast no-op when the packages are installed
# The contract and browser tests' npm tools, installed outside the tree.
if ! bash "$ROLLGAP_ROOT/scripts/install-node-tools.sh" >/dev/null; then
    echo "rollgap test: the node tools could not be installed (scripts/install-node-tools.sh)"
    failed=$((failed + 1))
fi

# Tests that need an outside program (nginx, curl) say so and skip when it is missing; in this
# command a missing one is a failure, not a skip.
for tool in nginx curl clang++; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "rollgap test: $tool is not installed (scripts/install-deps.sh installs it)"
        failed=$((failed + 1))
    fi
done

stage "0/3 format (.clang-format, scripts/check-format.sh)"
if bash scripts/check-format.sh; then
    passed=$((passed + 1))
    echo "rollgap test: every tracked C++ file is formatted as .clang-format says"
else
    failed=$((failed + 1))
fi

stage "0/3 static checks (shellcheck, clang-tidy: scripts/lint.sh)"
if bash scripts/lint.sh; then
    passed=$((passed + 1))
else
    failed=$((failed + 1))
fi

stage "1/3 Release build ($ROLLGAP_BUILD_DIR)"
# shellcheck disable=SC2119  # no targets: build everything
if rollgap_configure && rollgap_build; then
    stage "1/3 Release suite"
    run_suite "$ROLLGAP_BUILD_DIR" "Release suite"
else
    echo "rollgap test: the Release build failed"
    failed=$((failed + 1))
fi

stage "2/3 ASan + UBSan build ($ROLLGAP_ASAN_BUILD_DIR, clang)"
asan_built=0
if rollgap_configure_asan && rollgap_build_in "$ROLLGAP_ASAN_BUILD_DIR" "${ROLLGAP_ASAN_TARGETS[@]}"; then
    asan_built=1
    stage "2/3 ASan + UBSan suite"
    suite_start=$(date +%s)
    rollgap_sanitizer_env   # exported from here on: the fuzz stage runs under the same settings
    run_suite "$ROLLGAP_ASAN_BUILD_DIR" "ASan + UBSan suite"
    echo "rollgap test: ASan + UBSan suite took $(( $(date +%s) - suite_start )) s"
else
    echo "rollgap test: the ASan + UBSan build failed"
    failed=$((failed + 1))
fi

stage "3/3 bounded fuzz runs (${ROLLGAP_FUZZ_SECONDS:-60} s per harness)"
if [[ $asan_built -eq 1 && "${ROLLGAP_FUZZ_SECONDS:-60}" != 0 ]]; then
    fuzz_log=$(mktemp)
    fuzz_result=0
    ROLLGAP_FUZZ_NO_BUILD=1 bash scripts/fuzz.sh 2>&1 | tee "$fuzz_log" || fuzz_result=$?
    clean=$(grep -c '^fuzz: .*no finding$' "$fuzz_log" || true)
    findings=$(grep -c '^fuzz: .*FAILED' "$fuzz_log" || true)
    passed=$((passed + clean))
    failed=$((failed + findings))
    if [[ $fuzz_result -ne 0 && $findings -eq 0 ]]; then failed=$((failed + 1)); fi
    rm -f "$fuzz_log"
else
    echo "rollgap test: fuzz runs not done"
    failed=$((failed + 1))
fi

stage "done"
stage_times
echo "rollgap: $passed passed, $failed failed"
[[ $failed -eq 0 ]]
