#!/usr/bin/env bash
# Installs the npm tools of the contract and browser tests (tests/contract/, tests/browser/) into a cache OUTSIDE the
# repository, so the tree never holds node_modules:
#   ajv + ajv-formats      JSON Schema 2020-12 validation of real responses against /openapi.json
#   openapi-typescript     a TypeScript client type-checked with typescript (tsc --noEmit)
#   @redocly/cli           lint of the served OpenAPI document
#   playwright-core        drives Debian's chromium in browser tests
#   axe-core               accessibility checks of the workbench in the browser tests
# Idempotent: when the cache already holds exactly these versions, complete, it returns at once.
# Prints the cache directory on its last line. ROLLGAP_NODE_TOOLS overrides the location.
# Without node/npm on PATH it installs Debian's nodejs and npm (the machine image may bring
# its own node in /usr/local or from nodesource; then nothing is installed).
set -euo pipefail

dir="${ROLLGAP_NODE_TOOLS:-/var/cache/rollgap/node-tools}"
packages=(
    ajv@8.20.0
    ajv-formats@3.0.1
    openapi-typescript@7.13.0
    typescript@5.9.3
    @redocly/cli@2.77.0
    playwright-core@1.65.1
    axe-core@4.14.1
)

if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
    sudo_cmd=()
    [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
    "${sudo_cmd[@]}" apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends nodejs npm >&2
fi

stamp="$dir/.installed"
wanted="${packages[*]}"
# complete: the stamp names these versions and every package and command the tests use is there.
# (The stamp alone is not enough: two installs at once once left a cache whose stamp was
# written while another npm had half-emptied node_modules.)
complete() {
    [[ -f "$stamp" && "$(cat "$stamp")" == "$wanted" ]] || return 1
    local p
    for p in "${packages[@]}"; do
        [[ -f "$dir/node_modules/${p%@*}/package.json" ]] || return 1
    done
    for p in tsc openapi-typescript redocly; do
        [[ -x "$dir/node_modules/.bin/$p" ]] || return 1
    done
}

if complete; then
    echo "$dir"
    exit 0
fi
# One install at a time (ctest fixtures and several checkouts share the cache), into a fresh
# directory that replaces the cache only once npm has finished: a broken or interrupted install
# never becomes the cache.
mkdir -p "$(dirname "$dir")"
exec 9>"$dir.lock"
flock 9
if complete; then
    echo "$dir"
    exit 0
fi
fresh="$dir.new.$$"
rm -rf "$fresh"
mkdir -p "$fresh"
echo '{"name": "rollgap-node-tools", "private": true}' >"$fresh/package.json"
if ! npm install --prefix "$fresh" --no-audit --no-fund --loglevel=error "${packages[@]}" >&2; then
    rm -rf "$fresh"
    exit 1
fi
echo "$wanted" >"$fresh/.installed"
rm -rf "$dir.old"
[[ -e "$dir" ]] && mv "$dir" "$dir.old"
mv "$fresh" "$dir"
rm -rf "$dir.old"
echo "$dir"
