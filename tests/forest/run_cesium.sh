#!/bin/sh
# ctest forest_cesium_tileset: CesiumJS (npm cesium, headless Chromium) loads FOREST_DIR/tileset.json
# (tests/forest/cesium_tileset.mjs). Result and frames go to REPORT_DIR. Exits 77 (ctest: skipped)
# when cesium, playwright-core or chromium is missing and SYLVA_REQUIRE_CLIENTS is not 1.
# usage: run_cesium.sh FOREST_DIR REPORT_DIR
set -u
forest=$1 report=$2
[ -f "$forest/tileset.json" ] || { echo "no $forest/tileset.json (the verify gate builds it)" >&2; exit 1; }
rm -rf "$report"
mkdir -p "$report"
node tests/forest/cesium_tileset.mjs "$forest" "$report/result.json" "$report/"
rc=$?
if [ $rc -eq 3 ]; then
  [ "${SYLVA_REQUIRE_CLIENTS:-0}" = 1 ] && { echo "cesium_tileset: a required tool is missing" >&2; exit 1; }
  exit 77
fi
exit $rc
