#!/usr/bin/env bash
# Installs the npm tools of the contract and browser tests (tests/contract/, tests/browser/) into a cache OUTSIDE the
# repository, so the tree never holds node_modules:
#   ajv + ajv-formats      JSON Schema 2020-12 validation of real responses against /openapi.json
#   openapi-typescript     a TypeScript client type-checked with typescript (tsc --noEmit)
#   @redocly/cli           lint of the served OpenAPI document
#   playwright-core        drives Debian's chromium in browser tests
#   axe-core               accessibility checks of the workbench in the browser tests
# Idempotent: when the cache already holds exactly these versions it returns at once.
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
if [[ -f "$stamp" && "$(cat "$stamp")" == "$wanted" && -d "$dir/node_modules" ]]; then
    echo "$dir"
    exit 0
fi
mkdir -p "$dir"
[[ -f "$dir/package.json" ]] || echo '{"name": "rollgap-node-tools", "private": true}' >"$dir/package.json"
npm install --prefix "$dir" --no-audit --no-fund --loglevel=error "${packages[@]}" >&2
echo "$wanted" >"$stamp"
echo "$dir"
