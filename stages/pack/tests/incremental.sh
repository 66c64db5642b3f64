#!/bin/sh
# ctest pack_incremental (issue 14, "Incremental regeneration"): a three-species forest pack
# (stages/pack/tests/data/forest_three_species.yaml: young oak, birch and Scots pine through
# generate, lod and billboards, a forest of them, a pack node per species and one for the forest,
# and the pack that merges them), built from a copy of the recipe and the species presets in WORK_DIR; then ONE preset
# changes (birch's leaf colour), the recipe is rebuilt, and the script checks
#   - exactly tree_birch, lod_birch, billboards_birch, forest, pack_birch, pack_forest and pack
#     ran (every other node, pack_oak and pack_scots_pine included, came from the cache);
#   - the pack files whose bytes differ are birch's (its chain, levels, impostor and lod.json,
#     the forest's birch files) and the forest tiles that name a changed birch file (a tile
#     states each buffer's byteLength: the impostor tile level over birch's impostor buffer);
#     every other pack file (oak, pine, the other tiles, tileset, instances, cameras) is
#     byte-identical;
#   - `sylva pack diff` lists exactly those files as changed, nothing added or removed;
#   - every GLB and glTF file of both packs passes the Khronos glTF-Validator;
# and prints both builds' times (measured, not judged: docs/performance.md).
# usage: incremental.sh SYLVA WORK_DIR   (run from the repository root)
set -eu
sylva=$1 work=$2
rm -rf "$work"
mkdir -p "$work/presets"
cp stages/pack/tests/data/forest_three_species.yaml "$work/recipe.yaml"
cp configs/species/oak.yaml configs/species/birch.yaml configs/species/scots_pine.yaml "$work/presets/"
fail() { echo "pack_incremental: $*" >&2; exit 1; }

"$sylva" --out "$work/out" build "$work/recipe.yaml" --json > "$work/full.json" || fail "the first build failed"
pack2="$work/out/pack_forest/pack"
cp -R "$pack2" "$work/pack1"
# One preset changes: birch's leaf colour (a texture; its geometry and the forest layout stay).
sed -i 's/  leaf: { shape: ovate, color: \[0.33, 0.50, 0.16\]/  leaf: { shape: ovate, color: [0.30, 0.52, 0.16]/' \
  "$work/presets/birch.yaml"
cmp -s configs/species/birch.yaml "$work/presets/birch.yaml" && fail "the birch preset was not changed (sed pattern stale)"
"$sylva" --out "$work/out" build "$work/recipe.yaml" --json > "$work/incremental.json" || fail "the rebuild failed"

ran=$(node -e 'const j=require(process.argv[1]); console.log(j.nodes.filter(n=>n.status==="built").map(n=>n.name).sort().join(" "))' "$work/incremental.json")
want_ran="billboards_birch forest lod_birch pack pack_birch pack_forest tree_birch"
[ "$ran" = "$want_ran" ] || fail "the rebuild ran '$ran', expected '$want_ran'"

# The files whose bytes changed, by comparison (not by the manifest).
changed=""
for f in "$work"/pack1/*; do
  n=$(basename "$f")
  [ "$n" = manifest.json ] && continue
  [ -e "$pack2/$n" ] || fail "$n disappeared from the pack"
  cmp -s "$f" "$pack2/$n" || changed="$changed $n"
done
[ "$(ls "$pack2" | wc -l)" = "$(ls "$work/pack1" | wc -l)" ] || fail "the rebuilt pack has another number of files"
# Every changed file is birch's, or a forest tile that names one of birch's changed files (a tile
# declares each buffer's byteLength, so a tile over birch's impostor buffer changes with it);
# birch's own chain, levels, impostor, lod.json and the forest's birch atlas do change.
node -e '
const fs = require("fs"), path = require("path");
const dir = process.argv[1], changed = new Set(process.argv[2].trim().split(/\s+/).filter(Boolean));
const bad = [];
for (const n of changed) {
  if (n.startsWith("birch")) continue;
  let names = [];
  if (/^tile_.*\.gltf$/.test(n)) {
    const j = JSON.parse(fs.readFileSync(path.join(dir, n), "utf8"));
    names = [...(j.buffers ?? []), ...(j.images ?? [])].map((x) => x.uri).filter(Boolean);
  }
  if (!names.some((u) => u.startsWith("birch") && changed.has(u))) bad.push(n);
}
if (bad.length) { console.error("changed although only the birch preset did: " + bad.join(" ")); process.exit(1); }
for (const n of ["birch.glb", "birch.lod.json", "birch_lod0.glb", "birch_impostor.glb", "birch_leaves.png"])
  if (!changed.has(n)) { console.error(n + " did not change although birch\u2019s leaf colour did"); process.exit(1); }
const tiles = [...changed].filter((n) => n.startsWith("tile_"));
// Exactly: every one of the birch chain files (chain, kept levels, lod.json), the forest birch
// files the leaf colour reaches and the 4 impostor-level tiles that name the birch impostor buffer.
const m = JSON.parse(fs.readFileSync(path.join(dir, "manifest.json"), "utf8"));
const birch = m.species.find((s) => s.name === "birch");
const own = new Set([birch.chain, birch.lod_json, ...birch.levels.map((l) => l.file)]);
const forestBirch = [...changed].filter((n) => n.startsWith("birch") && !own.has(n));
const got = { own: [...changed].filter((n) => own.has(n)).length, forest: forestBirch.length, tiles: tiles.length };
const want = { own: own.size, forest: 3, tiles: 4 };
if (JSON.stringify(got) !== JSON.stringify(want)) {
  console.error(`changed ${JSON.stringify(got)}, expected ${JSON.stringify(want)}: ${[...changed].join(" ")}`);
  process.exit(1);
}
console.log(`changed: ${changed.size} files (${own.size} of the birch chain, ${forestBirch.join(" ")}, ${tiles.length} forest tiles, each naming a changed birch buffer)`);
' "$pack2" "$changed" || fail "the changed files are not exactly birch's and what names them"

# The manifest states every level's numbers exactly as the species' lod.json does, each with the
# image error the pack measured (its measured level choice); every forest
# .gltf is meshopt-compressed (its shared .bin buffers: EXT_meshopt_compression).
node -e '
const fs = require("fs"), path = require("path");
const dir = process.argv[1];
const m = JSON.parse(fs.readFileSync(path.join(dir, "manifest.json"), "utf8"));
if (m.version !== 4) { console.error("manifest version " + m.version + ", expected 4"); process.exit(1); }
if (m.species.length !== 3) { console.error("manifest lists " + m.species.length + " species, expected 3"); process.exit(1); }
for (const s of m.species) {
  const lod = JSON.parse(fs.readFileSync(path.join(dir, s.lod_json), "utf8"));
  if (JSON.stringify(s.levels) !== JSON.stringify(lod.levels)) {
    console.error(s.name + ": manifest levels " + JSON.stringify(s.levels) + " are not lod.json levels " + JSON.stringify(lod.levels));
    process.exit(1);
  }
  for (const l of s.levels)
    if (!(l.epsilon_m > 0 && l.switch_distance_m > 0 && l.primitives > 0 && l.bytes === m.files.find((f) => f.path === l.file).size &&
          l.measured && l.measured.failing_fraction >= 0 && l.measured.coverage_mean_error >= 0 && typeof l.measured.passed === "boolean")) {
      console.error(s.name + ": level " + l.file + " lacks its numbers: " + JSON.stringify(l)); process.exit(1);
    }
}
const gltfs = m.forests[0].files.filter((n) => n.endsWith(".gltf"));
const plain = gltfs.filter((n) => !(JSON.parse(fs.readFileSync(path.join(dir, n), "utf8")).extensionsRequired ?? []).includes("EXT_meshopt_compression"));
if (plain.length) { console.error("forest glTF files not compressed: " + plain.join(" ")); process.exit(1); }
console.log(`manifest: ${m.species.map((s) => s.levels.length).join("+")} levels with their numbers; ${gltfs.length} forest glTF files meshopt-compressed`);
' "$pack2" || fail "the manifest's levels or the forest's compression are wrong"

"$sylva" pack diff "$work/pack1/manifest.json" "$pack2/manifest.json" --json > "$work/diff.json"
node -e '
const d = require(process.argv[1]);
const want = process.argv[2].trim().split(/\s+/).sort();
const ok = d.added.length === 0 && d.removed.length === 0 && JSON.stringify(d.changed) === JSON.stringify(want);
if (!ok) { console.error("pack diff: " + JSON.stringify(d) + ", expected changed " + JSON.stringify(want)); process.exit(1); }
console.log("pack diff: " + d.changed.length + " changed (exactly the files whose bytes differ), none added or removed");
' "$work/diff.json" "$changed" || fail "the manifest diff is not exactly the changed files"

vrc=0
node tools/validate_gltf.mjs --max-warnings 0 "$work"/pack1/*.glb "$work"/pack1/*.gltf "$pack2"/*.glb "$pack2"/*.gltf \
  > "$work/validator.txt" || vrc=$?
if [ $vrc -eq 3 ] && [ "${SYLVA_REQUIRE_GLTF_VALIDATOR:-0}" != 1 ]; then
  echo "note: the glTF-Validator is not installed (tools/setup.sh); glTF files not validated"
elif [ $vrc -ne 0 ]; then
  grep -v ': 0 errors, 0 warnings' "$work/validator.txt" >&2 || true
  fail "glTF-Validator: some pack glTF file has errors or warnings (exit $vrc)"
fi
node -e '
const a = require(process.argv[1]), b = require(process.argv[2]);
const t = j => j.nodes.filter(n => n.status === "built").reduce((s, n) => s + n.seconds, 0);
const built = (j, f) => j.nodes.filter(n => n.status === "built" && f(n.name)).reduce((s, n) => s + n.seconds, 0);
const packs = j => built(j, n => n.startsWith("pack_")).toFixed(2), merge = j => built(j, n => n === "pack").toFixed(2);
console.log(`full build ${a.seconds.toFixed(2)} s (node time ${t(a).toFixed(2)} s, pack_* ${packs(a)} s, merge ${merge(a)} s), ` +
            `incremental ${b.seconds.toFixed(2)} s (node time ${t(b).toFixed(2)} s, pack_* ${packs(b)} s, merge ${merge(b)} s)`);
' "$work/full.json" "$work/incremental.json"
echo "changed:$changed"
echo "pack: $(ls "$pack2" | wc -l) files, $(du -sb "$pack2" | cut -f1) bytes"
rm -rf "$work"
echo "pack_incremental: passed"
