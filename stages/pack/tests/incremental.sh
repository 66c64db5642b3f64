#!/bin/sh
# ctest pack_incremental (issue 14, "Incremental regeneration"): build a two-species pack, change
# one species' seed, rebuild, and check
#   - exactly tree_birch, lod_birch and pack ran (oak's chain came from the cache);
#   - `sylva pack diff` lists exactly birch's files as changed, nothing added or removed;
#   - every oak file is byte-identical;
#   - every GLB of both packs passes the Khronos glTF-Validator;
# and print both builds' times (measured, not judged: docs/performance.md).
# usage: incremental.sh SYLVA WORK_DIR   (run from the repository root)
set -eu
sylva=$1 work=$2
rm -rf "$work"
mkdir -p "$work"
recipe=stages/pack/tests/data/two_species.yaml
v2=stages/pack/tests/data/.two_species_v2.yaml
trap 'rm -f "$v2"' EXIT
sed '/tree_birch:/,/lod_oak:/ s/seed: 7/seed: 8/' "$recipe" > "$v2"
fail() { echo "pack_incremental: $*" >&2; exit 1; }

"$sylva" --out "$work/out" build "$recipe" --json > "$work/full.json" || fail "the first build failed"
cp -R "$work/out/pack_two_species/pack" "$work/pack1"
"$sylva" --out "$work/out" build "$v2" --json > "$work/incremental.json" || fail "the rebuild failed"
pack2="$work/out/pack_two_species/pack"

ran=$(node -e 'const j=require(process.argv[1]); console.log(j.nodes.filter(n=>n.status==="built").map(n=>n.name).sort().join(" "))' "$work/incremental.json")
[ "$ran" = "lod_birch pack tree_birch" ] || fail "the rebuild ran '$ran', expected 'lod_birch pack tree_birch'"

"$sylva" pack diff "$work/pack1/manifest.json" "$pack2/manifest.json" --json > "$work/diff.json"
node -e '
const d = require(process.argv[1]);
const want = ["birch.glb", "birch.lod.json", "birch_lod0.glb", "birch_lod1.glb", "birch_lod2.glb",
              "birch_lod3.glb", "birch_lod4.glb", "birch_lod5.glb"];
const ok = d.added.length === 0 && d.removed.length === 0 && JSON.stringify(d.changed) === JSON.stringify(want);
if (!ok) { console.error("pack diff: " + JSON.stringify(d) + ", expected changed " + JSON.stringify(want)); process.exit(1); }
' "$work/diff.json" || fail "the manifest diff is not exactly birch's files"
for f in "$work"/pack1/oak*; do
  cmp -s "$f" "$pack2/$(basename "$f")" || fail "$(basename "$f") changed although oak did not"
done

vrc=0
node tools/validate_gltf.mjs --max-warnings 0 "$work"/pack1/*.glb "$pack2"/*.glb || vrc=$?
if [ $vrc -eq 3 ] && [ "${SYLVA_REQUIRE_GLTF_VALIDATOR:-0}" != 1 ]; then
  echo "note: the glTF-Validator is not installed (tools/setup.sh); GLBs not validated"
elif [ $vrc -ne 0 ]; then
  fail "glTF-Validator: some pack GLB has errors (exit $vrc)"
fi
node -e '
const a = require(process.argv[1]), b = require(process.argv[2]);
const t = j => j.nodes.filter(n => n.status === "built").reduce((s, n) => s + n.seconds, 0);
console.log(`full build ${a.seconds.toFixed(2)} s (node time ${t(a).toFixed(2)} s), ` +
            `incremental ${b.seconds.toFixed(2)} s (node time ${t(b).toFixed(2)} s)`);
' "$work/full.json" "$work/incremental.json"
du -b "$pack2"/* | sort -k2
rm -rf "$work"
echo "pack_incremental: passed"
