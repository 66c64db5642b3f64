#!/bin/sh
# ctest clients_default_recipe: builds a recipe into the verify gate's output directory (its
# nodes are mostly cached by then), then compares every glTF file it wrote in sylva's renderer
# and in three.js (sylva_client_agreement; docs/clients.md). Report: REPORT_DIR (outside OUT_DIR,
# which lodcheck_default_recipe scans at the same time).
# usage: run_clients.sh SYLVA AGREEMENT RECIPE OUT_DIR REPORT_DIR [DATA_FILE]
# Exits 77 (ctest: skipped) when DATA_FILE, third-party data the recipe reads, is missing, or
# when three.js/Chromium are not installed and SYLVA_REQUIRE_CLIENTS is not 1.
set -u
sylva=$1 agreement=$2 recipe=$3 out=$4 report=$5
if [ $# -ge 6 ] && [ ! -e "$6" ]; then
  echo "skipped: $6 is missing (third-party test data, ../shared/data)"
  exit 77
fi
"$sylva" --out "$out" build "$recipe" || { echo "building $recipe failed" >&2; exit 1; }
name=$(sed -n 's/^name: *//p' "$recipe" | head -n 1)
"$agreement" "$out/$name" "$report"
