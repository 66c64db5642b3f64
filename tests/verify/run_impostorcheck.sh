#!/bin/sh
# ctest impostorcheck_default_recipe: `sylva impostorcheck` on the hemi-octahedral impostors and
# the billboards of a recipe in the verify gate's output directory (nodes impostor_* and
# billboards_*), each at the proven distance the recipe records for it (fails when one is judged
# at the error model's: for billboards a degenerate distance, docs/stages/impostor.md
# "Billboards"), then the Khronos glTF-Validator on every impostor GLB the recipe writes.
# usage: run_impostorcheck.sh SYLVA RECIPE OUT_DIR [DATA_FILE]
# Exits 77 (ctest: skipped) when DATA_FILE, third-party data the recipe reads, is missing.
set -u
sylva=$1 recipe=$2 out=$3
if [ $# -ge 4 ] && [ ! -e "$4" ]; then
  echo "skipped: $4 is missing (third-party test data, ../shared/data)"
  exit 77
fi
# Build the recipe (its impostor and billboards nodes), then check the nodes named impostor_*
# and billboards_* of its output directory (OUT_DIR/<recipe name>: other recipes may share OUT_DIR).
"$sylva" --out "$out" build "$recipe" -j 2 >/dev/null || exit 1
name=$(sh tests/recipe_name.sh "$recipe") || exit 1
args=""
for kind in impostor billboards; do
  n=0
  for d in "$out/$name"/"$kind"_*; do [ -d "$d" ] && args="$args --node $(basename "$d")" && n=$((n + 1)); done
  [ $n -gt 0 ] || { echo "no ${kind}_* node built under $out/$name" >&2; exit 1; }
done
report=$("$sylva" --out "$out" impostorcheck "$recipe" --no-images $args)
rc=$?
printf '%s\n' "$report"
# Every impostor_* and billboards_* node records the distance `sylva impostorcheck
# --search-distance` proved (the stage's switch_distance_m), so the check above judged it there,
# not at the error model's distance (docs/stages/impostor.md, "Proven distances", "Billboards").
unrecorded=$(printf '%s\n' "$report" | grep -E '^impostorcheck (impostor|billboards)_' | grep -v 'recorded by the recipe')
if [ -n "$unrecorded" ]; then
  echo "$recipe: these impostors are judged at the error model's distance; record their proven" >&2
  echo "distance (switch_distance_m, from sylva impostorcheck --search-distance):" >&2
  printf '%s\n' "$unrecorded" >&2
  exit 1
fi
if [ $rc -ne 0 ]; then
  echo "impostorcheck FAILED (exit $rc) for $recipe: see the table above" >&2
  exit $rc
fi
# Every checked node printed its table's header line.
headers=$(printf '%s\n' "$report" | grep -c -E '^impostorcheck (impostor|billboards)_')
checked=$(printf '%s\n' "$args" | grep -o -- '--node' | wc -l)
if [ "$headers" -ne "$checked" ]; then
  echo "$recipe: $checked nodes checked but $headers report headers (impostorcheck <node>: ...)" >&2
  exit 1
fi
glbs=$(find "$out/$name" -mindepth 2 -maxdepth 2 -name 'impostor.glb' | sort)
[ -n "$glbs" ] || { echo "no impostor.glb under $out/$name" >&2; exit 1; }
exec sh tests/validate_gltf.sh "the impostor GLBs of $recipe" $glbs
