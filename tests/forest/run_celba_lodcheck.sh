#!/bin/sh
# ctest lodcheck_forest_celba: `sylva lodcheck` of configs/forest_celba.yaml's own LOD chains
# (forest_lod_oak, forest_lod_scots_pine: every level at its switch distance against the
# full-detail tree, the judgement of docs/stages/lod.md "lodcheck"), in the verify gate's output
# directory (the trees are in its cache), then the Khronos glTF-Validator on every glTF file
# those nodes wrote.
# usage: run_celba_lodcheck.sh SYLVA OUT_DIR
set -u
sylva=$1 out=$2
"$sylva" --out "$out" lodcheck configs/forest_celba.yaml --no-images --node forest_lod_oak \
  --node forest_lod_scots_pine || { echo "lodcheck of forest_celba's chains FAILED" >&2; exit 1; }
files=$(find "$out/forest_celba/forest_lod_oak" "$out/forest_celba/forest_lod_scots_pine" -maxdepth 1 -type f \
  \( -name '*.glb' -o -name '*.gltf' \) | sort)
[ "$(printf '%s\n' "$files" | grep -c .)" -eq 20 ] || { echo "expected 20 glTF files (2 chains: lod.gltf, lod0-7.gltf, full.glb), got: $files" >&2; exit 1; }
exec sh tests/validate_gltf.sh "forest_celba's chains" $files
