#!/bin/sh
# ctest clients_babylon_pack: builds the default recipe's pack into the verify gate's output
# directory (its nodes are cached by then) and loads every species' MSFT_lod chain and every forest
# tile in Babylon.js (tests/clients/babylon_lod.mjs; docs/clients.md "Babylon.js").
# usage: run_babylon.sh SYLVA RECIPE OUT_DIR PACK_NODE
# Exits 77 (ctest: skipped) when the npm packages are not installed and SYLVA_REQUIRE_CLIENTS is not 1.
set -u
sylva=$1 recipe=$2 out=$3 node=$4
"$sylva" --out "$out" build "$recipe" --target "$node" >/dev/null || { echo "building $recipe failed" >&2; exit 1; }
name=$(sed -n 's/^name: *//p' "$recipe" | head -n 1)
node tests/clients/babylon_lod.mjs "$out/$name/$node"
rc=$?
[ $rc -eq 3 ] && exit 77
exit $rc
