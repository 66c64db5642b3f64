#!/bin/sh
# ctest lodcheck_default_recipe: `sylva lodcheck` on a recipe in the verify gate's output
# directory (its trees are already in that cache). Reports go to OUT_DIR/<recipe>/lodcheck/.
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
[ $rc -ne 0 ] && echo "lodcheck FAILED (exit $rc) for $recipe: see the table above and the images beside lodcheck.json" >&2
exit $rc
