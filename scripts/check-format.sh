#!/usr/bin/env bash
# Check that the tracked C++ files follow .clang-format (clang-format 14, Debian's
# clang-format package): exit 0 if every file is formatted, 1 and clang-format's warnings
# (file:line: what would change) otherwise. Changes nothing; to reformat, run
#   git ls-files '*.cpp' '*.h' | xargs clang-format -i
# Arguments: files to check instead of every tracked one.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

if ! command -v clang-format >/dev/null; then
    echo "check-format.sh: clang-format is not installed (apt-get install clang-format)" >&2
    exit 2
fi

if [ "$#" -gt 0 ]; then
    files=("$@")
else
    mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.hpp' '*.cc')
fi
[ "${#files[@]}" -gt 0 ] || exit 0

failed=0
clang-format --dry-run --Werror --style=file "${files[@]}" || failed=1
if [ "$failed" -ne 0 ]; then
    echo "check-format.sh: the files above differ from .clang-format" \
         "(reformat: clang-format -i FILE)" >&2
fi
exit "$failed"
