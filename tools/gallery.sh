#!/bin/sh
# Regenerates docs/gallery/<species>_<age>.png: builds configs/gallery.yaml (every preset x age at
# the default settings) and renders each mesh from the front through configs/cameras/gallery.yaml.
#   tools/gallery.sh [BUILD_DIR]      (default out/build; run from the repository root)
set -eu
build=${1:-out/build}
sylva="$build/app/sylva"
"$sylva" build configs/gallery.yaml -j "$(nproc)"
mkdir -p docs/gallery
for glb in out/gallery/mesh_*/tree.glb; do
  node=$(basename "$(dirname "$glb")")
  name=${node#mesh_}
  "$sylva" render "$glb" --camera configs/cameras/gallery.yaml --view front -o "docs/gallery/$name.png"
done
