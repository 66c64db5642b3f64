#!/bin/sh
# Skeleton-aware LOD (sylva, Zhang et al. 2017) against a generic simplifier (gltfpack 0.18,
# meshoptimizer's simplifier) on the same tree, with the same budget, judged the same way.
#
#   tools/compare_gltfpack.sh [RECIPE] [LOD_NODE] [SYLVA]
#   defaults: configs/default.yaml lod_oak out/build/app/sylva
#
# 1. `sylva lodcheck --branches-only --write-full` builds the chain, writes the full-detail branch
#    mesh (epsilon = 0) and prints each level's primitives (triangles + line segments).
# 2. For each level i, gltfpack simplifies the full-detail mesh to that budget: ratio =
#    primitives_i / full triangles, once with -si alone (gltfpack stops where its error limit
#    says; it may keep more triangles than asked) and once with -sa (forced to the budget).
# 3. `sylva lodcheck --candidates` renders the gltfpack models and the sylva levels at each
#    level's switch distance against the full-detail branches and prints both rows per view.
# Work files and images: out/compare-gltfpack/<LOD_NODE>/. Needs gltfpack (cmake/apt-packages.txt).
set -eu
recipe=${1:-configs/default.yaml}
node=${2:-lod_oak}
sylva=${3:-out/build/app/sylva}
work=out/compare-gltfpack/$node
command -v gltfpack >/dev/null || { echo "gltfpack is not installed (apt-get install gltfpack)" >&2; exit 2; }
rm -rf "$work"
mkdir -p "$work/gltfpack" "$work/gltfpack-sa"

"$sylva" lodcheck "$recipe" --node "$node" --branches-only --no-images --write-full "$work/full.glb" \
  --report-dir "$work/sylva" >"$work/sylva.txt" || true
full=$(awk '/full detail:/ { print $3 }' "$work/sylva.txt")
[ -n "$full" ] || { cat "$work/sylva.txt" >&2; echo "lodcheck did not run" >&2; exit 1; }
# level -> primitives of the sylva level (first view's row)
awk '$1 == "sylva" && $2 ~ /^[0-9]+$/ && !seen[$2]++ { print $2, $6 }' "$work/sylva.txt" >"$work/budgets.txt"

while read -r level prims; do
  ratio=$(awk -v p="$prims" -v f="$full" 'BEGIN { r = p / f; if (r > 1) r = 1; printf "%.6f", r }')
  gltfpack -i "$work/full.glb" -o "$work/gltfpack/lod$level.glb" -si "$ratio" -km -noq >/dev/null
  gltfpack -i "$work/full.glb" -o "$work/gltfpack-sa/lod$level.glb" -si "$ratio" -sa -km -noq >/dev/null
done <"$work/budgets.txt"

for c in gltfpack gltfpack-sa; do
  "$sylva" lodcheck "$recipe" --node "$node" --branches-only --candidates "$work/$c" --candidate-label "$c" \
    --report-dir "$work/report-$c" >"$work/$c.txt" || true
done
echo "full-detail branches of $node: $full triangles; budgets per level (triangles + line segments):"
sed 's/^/  level /' "$work/budgets.txt"
head -3 "$work/gltfpack.txt"
grep -h -E '^  (sylva|gltfpack)' "$work/gltfpack.txt" "$work/gltfpack-sa.txt" | sort -s -k2,2n -k5,5 | uniq
echo "images: $work/report-gltfpack/, $work/report-gltfpack-sa/"
