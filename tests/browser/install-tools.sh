#!/usr/bin/env bash
# Installs the npm packages of the browser tests into the node-tools cache OUTSIDE the
# repository (the same place and variable as the other npm tools, ROLLGAP_NODE_TOOLS), so the
# tree never holds node_modules. Idempotent: returns at once when they are there.
# Prints the cache directory on its last line.
set -euo pipefail

dir="${ROLLGAP_NODE_TOOLS:-/var/cache/rollgap/node-tools}"
packages=(playwright-core@1.65.1 axe-core@4.14.1)

if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
    sudo_cmd=()
    [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
    "${sudo_cmd[@]}" apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends nodejs npm >&2
fi

stamp="$dir/.installed-browser"
if [[ -f "$stamp" && "$(cat "$stamp")" == "${packages[*]}" && -d "$dir/node_modules/playwright-core" && -d "$dir/node_modules/axe-core" ]]; then
    echo "$dir"
    exit 0
fi
mkdir -p "$dir"
[[ -f "$dir/package.json" ]] || echo '{"name": "rollgap-node-tools", "private": true}' >"$dir/package.json"
npm install --prefix "$dir" --no-audit --no-fund --loglevel=error "${packages[@]}" >&2
echo "${packages[*]}" >"$stamp"
echo "$dir"
