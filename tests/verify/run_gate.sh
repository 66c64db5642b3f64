#!/bin/sh
# The reference-image regression gate (ctest verify_gate): runs `sylva verify` on a recipe with
# a fresh output directory and cache, so the current binary builds and renders everything.
# usage: run_gate.sh SYLVA RECIPE OUT_DIR [DATA_FILE]
# Exits 77 (ctest: skipped) when DATA_FILE, third-party data the recipe reads, is missing.
set -u
sylva=$1 recipe=$2 out=$3
if [ $# -ge 4 ] && [ ! -e "$4" ]; then
  echo "skipped: $4 is missing (third-party test data, ../shared/data)"
  exit 77
fi
rm -rf "$out"
"$sylva" --out "$out" verify "$recipe"
rc=$?
if [ $rc -ne 0 ]; then
  echo "verify gate FAILED (exit $rc) for $recipe." >&2
  echo "Open the report.html printed above. If the change is intended, accept the new images:" >&2
  echo "  $sylva --out out/gate verify $recipe --update-refs" >&2
  echo "then review and commit the changed files under the recipe's references directory." >&2
fi
exit $rc
