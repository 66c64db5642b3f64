#!/bin/sh
# ctest forest_celba_nodes_match_default: configs/forest_celba.yaml's species nodes (tree_*, lod_*,
# impostor_* of the oak, birch and Scots pine) are the default recipe's, parameter for parameter,
# so that both recipes share their cache entries. Builds the default recipe's impostor nodes (and
# what they need) into OUT_DIR (cached after the verify gate), then dry-runs forest_celba's with
# the same cache: every one of its nine species nodes must be up to date, none would build.
# usage: run_celba_nodes.sh SYLVA OUT_DIR
set -u
sylva=$1 out=$2
"$sylva" --out "$out" build configs/default.yaml -j 2 --target impostor_oak --target impostor_birch \
  --target impostor_scots_pine >/dev/null || { echo "building the default recipe's impostors failed" >&2; exit 1; }
json=$("$sylva" --out "$out" build configs/forest_celba.yaml -n --json --target 'impostor_*') || exit 1
if printf '%s\n' "$json" | grep -q '"would_build": 0,' && printf '%s\n' "$json" | grep -q '"up_to_date": 9,'; then
  echo "forest_celba's 9 species nodes are the default recipe's (all up to date in its cache)"
  exit 0
fi
echo "forest_celba's species nodes differ from the default recipe's (these would build):" >&2
"$sylva" --out "$out" build configs/forest_celba.yaml -n --target 'impostor_*' >&2
exit 1
