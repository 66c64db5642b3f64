#!/usr/bin/env bash
# Installs what sylva needs on Debian 12, idempotently: the apt packages listed in
# cmake/apt-packages.txt (the only place they are named) and the npm test tools in
# tools/npm/package.json. Fast when everything is present: it only asks dpkg.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
mapfile -t pkgs < <(grep -v -e '^#' -e '^[[:space:]]*$' "$root/cmake/apt-packages.txt")
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
# npm test tools (gltf-validator), pinned by tools/npm/package-lock.json, installed under out/.
npm_dir="$root/out/npm"
if [ ! -f "$npm_dir/node_modules/.sylva-stamp" ] || ! cmp -s "$root/tools/npm/package-lock.json" "$npm_dir/package-lock.json"; then
  command -v npm >/dev/null || { echo "setup: npm not found (Debian package npm or nodejs)"; exit 1; }
  mkdir -p "$npm_dir"
  cp "$root/tools/npm/package.json" "$root/tools/npm/package-lock.json" "$npm_dir/"
  (cd "$npm_dir" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
  touch "$npm_dir/node_modules/.sylva-stamp"
fi
