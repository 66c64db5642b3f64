#!/bin/sh
# ctest lodcheck_default_recipe: `sylva lodcheck` on a recipe in the verify gate's output
# directory (its trees are already in that cache), then the Khronos glTF-Validator on every glTF
# file the recipe's nodes wrote (mesh GLBs; LOD chains, levels and ribbon variants as .gltf with
# external .bin and .png files). Reports go to
# OUT_DIR/<recipe>/lodcheck/.
# usage: run_lodcheck.sh SYLVA RECIPE OUT_DIR [DATA_FILE]
# Exits 77 (ctest: skipped) when DATA_FILE, third-party data the recipe reads, is missing.
set -u
sylva=$1 recipe=$2 out=$3
if [ $# -ge 4 ] && [ ! -e "$4" ]; then
  echo "skipped: $4 is missing (third-party test data, ../shared/data)"
  exit 77
fi
"$sylva" --out "$out" lodcheck "$recipe"
rc=$?
if [ $rc -ne 0 ]; then
  echo "lodcheck FAILED (exit $rc) for $recipe: see the table above and the images beside lodcheck.json" >&2
  exit $rc
fi
# Every glTF file of the recipe's outputs (OUT_DIR/<recipe name>/<node>/; other recipes sharing
# OUT_DIR are not this check's), with zero errors.
name=$(sh tests/recipe_name.sh "$recipe") || exit 1
glbs=$(find "$out/$name" -mindepth 2 -maxdepth 2 -type f \( -name '*.glb' -o -name '*.gltf' \) -not -path '*/lodcheck/*' | sort)
[ -n "$glbs" ] || { echo "no glTF file under $out/$name" >&2; exit 1; }
exec sh tests/validate_gltf.sh "the glTF files of $recipe" $glbs
