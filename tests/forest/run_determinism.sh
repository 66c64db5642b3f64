#!/bin/sh
# ctest forest_determinism: builds RECIPE from scratch twice, with -j1 and with -j2, each into its
# own output directory and cache, and compares every published file of every node (and the nodes'
# action records) byte for byte.
# usage: run_determinism.sh SYLVA RECIPE WORK_DIR
set -u
sylva=$1 recipe=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
name=$(sed -n 's/^name: *//p' "$recipe" | head -n 1)
for j in 1 2; do
  "$sylva" --out "$work/j$j" --cache "$work/j$j/cache" build -j "$j" "$recipe" >"$work/j$j.log" 2>&1 || {
    cat "$work/j$j.log" >&2
    echo "building $recipe with -j$j failed" >&2
    exit 1
  }
done
a="$work/j1/$name" b="$work/j2/$name"
[ -f "$a/forest/instances.json" ] && [ -f "$a/forest/tileset.json" ] || {
  echo "the forest node wrote no instances.json/tileset.json under $a/forest" >&2
  exit 1
}
grep -q '"instance_count": [1-9]' "$a/forest/instances.json" || { echo "the forest has no tree" >&2; exit 1; }
# .sylva/digests is the engine's stat cache (absolute paths and mtimes), not an output.
(cd "$a" && find . -type f -not -path ./.sylva/digests | sort) >"$work/files.j1"
(cd "$b" && find . -type f -not -path ./.sylva/digests | sort) >"$work/files.j2"
diff "$work/files.j1" "$work/files.j2" >&2 || { echo "-j1 and -j2 published different file sets" >&2; exit 1; }
files=$(cat "$work/files.j1")
n=0 bad=0
for f in $files; do
  n=$((n + 1))
  cmp -s "$a/$f" "$b/$f" || { echo "differs between -j1 and -j2: $f" >&2; bad=$((bad + 1)); }
done
echo "$n files compared, $bad differ"
[ "$bad" -eq 0 ] || exit 1
rm -rf "$work"
