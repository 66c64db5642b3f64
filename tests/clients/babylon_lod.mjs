#!/usr/bin/env node
// Babylon.js's view of a pack's MSFT_lod chains (issue 14: "loadable in Babylon.js, MSFT_lod chain
// recognised"): npm @babylonjs/core + @babylonjs/loaders in node, on a NullEngine (no GPU, no
// browser), loading each species' <species>.glb as a Babylon.js user would (its stock glTF 2.0
// loader with the MSFT_lod, EXT_meshopt_compression, KHR_mesh_quantization, KHR_texture_transform
// and KHR_materials_unlit extensions).
//
//   node tests/clients/babylon_lod.mjs PACK_DIR
//
// What Babylon.js 9.28's MSFT_lod extension does (loaders/glTF/2.0/Extensions/MSFT_lod.pure.js,
// read for this check): it loads the chain PROGRESSIVELY -- the node's MSFT_lod `ids` are taken
// from the last (coarsest) to the first, at most `maxLODsToLoad` (default 10) of them plus the
// node itself; each level replaces the previous one when loaded (the previous level's nodes are
// disposed), and onNodeLODsLoadedObservable fires once per level, with index 0 = the coarsest.
// It does NOT read MSFT_screencoverage (no file of @babylonjs/loaders 9.28 names it) and does not
// build distance-based LODs (Mesh.addLODLevel); screen coverages are for other loaders
// (three.js's MSFT_lod plugin here). So this check asserts what Babylon.js does read:
//   - every file loads (meshopt decoded, quantised attributes, textures);
//   - the chain has exactly as many levels as lod.json lists (one LOD notification each);
//   - at each notification the enabled meshes draw exactly the triangles and lines of the
//     level lod.json says comes next in Babylon's order (the impostor first, level 0 last);
//   - after loading only level 0 is left (the finest), with lod.json's level-0 counts;
//   - when the pack carries a forest: every tile file draws every primitive of every node as many
//     times as the file instances it (EXT_mesh_gpu_instancing: thin instances), lines included.
// The meshopt decoder is npm meshoptimizer's (the module Babylon.js fetches from its CDN by
// default; here installed by tools/npm, no network).
// Exit codes: 0 every chain as lod.json says (and every tile as it instances); 1 some chain or tile differs or fails to load (stderr says
// which); 2 usage; 3 @babylonjs/* or meshoptimizer not installed (ctest: skipped unless
// SYLVA_REQUIRE_CLIENTS=1).
import { existsSync, readFileSync, readdirSync } from 'node:fs';
import { readFile } from 'node:fs/promises';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
const modules = path.join(process.env.SYLVA_NPM_DIR ?? path.join(repo, 'out', 'npm'), 'node_modules');
const args = process.argv.slice(2);
if (args.length !== 1) {
  process.stderr.write('usage: node tests/clients/babylon_lod.mjs PACK_DIR\n');
  process.exit(2);
}
for (const m of ['@babylonjs/core', '@babylonjs/loaders', 'meshoptimizer'])
  if (!existsSync(path.join(modules, m))) {
    process.stderr.write(`babylon_lod: the npm package ${m} is not installed in ${modules} (run tools/setup.sh)\n`);
    process.exit(process.env.SYLVA_REQUIRE_CLIENTS === '1' ? 1 : 3);
  }
const load = (p) => import(pathToFileURL(path.join(modules, p)).href);
const BABYLON = await load('@babylonjs/core/index.js');
await load('@babylonjs/loaders/glTF/2.0/index.js');
const { MeshoptDecoder } = await load('meshoptimizer/meshopt_decoder.mjs');
const { MeshoptCompression } = await load('@babylonjs/core/Meshes/Compression/meshoptCompression.js');

// Babylon.js loads its meshopt decoder as a <script> from its CDN; in node the same decoder comes
// from npm and is put where Babylon.js's MeshoptCompression expects it.
await MeshoptDecoder.ready;
MeshoptCompression._Default = {
  decodeGltfBufferAsync: async (source, count, stride, mode, filter) => {
    const out = new Uint8Array(count * stride);
    MeshoptDecoder.decodeGltfBuffer(out, count, stride, source, mode, filter);
    return out;
  },
  dispose() {},
};

// The chain's JSON: the level nodes' meshes in chain order and each primitive's mode.
function chainLevels(glb) {
  const n = glb.readUInt32LE(12);
  const j = JSON.parse(glb.subarray(20, 20 + n).toString('utf8'));
  const root = j.nodes[j.scenes[j.scene ?? 0].nodes[0]];
  const nodes = [root, ...(root.extensions?.MSFT_lod?.ids ?? []).map((i) => j.nodes[i])];
  return nodes.map((node) => ({ mesh: node.mesh, modes: j.meshes[node.mesh].primitives.map((p) => p.mode ?? 4) }));
}

// Loads one chain; returns { lods: notifications, indices: Map("/meshes/k/primitives/p" -> index
// count Babylon.js held), final: Set of pointers still enabled after loading }.
async function loadChain(engine, bytes, skipMaterials, levelCount) {
  const scene = new BABYLON.Scene(engine);
  const out = { lods: [], indices: new Map(), final: new Set() };
  const pointer = (m) => (m._internalMetadata?.gltf?.pointers ?? [])[0];
  // The indices a mesh draws (its submeshes'), recorded before MSFT_lod disposes a level.
  const keep = (m) => {
    const p = pointer(m);
    if (p) out.indices.set(p, (m.subMeshes ?? []).reduce((s, sm) => s + sm.indexCount, 0));
  };
  const observer = BABYLON.SceneLoader.OnPluginActivatedObservable.add((plugin) => {
    plugin.skipMaterials = skipMaterials;
    plugin.onMeshLoadedObservable.add((m) => {
      const dispose = m.dispose.bind(m);
      m.dispose = (...a) => {
        keep(m);
        return dispose(...a);
      };
    });
    plugin.onExtensionLoadedObservable.add((ext) => {
      if (ext.name === 'MSFT_lod') ext.onNodeLODsLoadedObservable.add((i) => out.lods.push(i));
    });
  });
  try {
    await BABYLON.SceneLoader.ImportMeshAsync('', '', bytes, scene, null, '.glb');
    // The finer levels arrive after the import promise (progressive loading).
    for (let t = 0; t < 500 && out.lods.length < levelCount; ++t) await new Promise((r) => setTimeout(r, 20));
    for (const m of scene.meshes)
      if (pointer(m) && m.isEnabled()) {
        keep(m);
        out.final.add(pointer(m));
      }
  } finally {
    BABYLON.SceneLoader.OnPluginActivatedObservable.remove(observer);
    scene.dispose();
  }
  return out;
}

const dir = args[0];
const manifest = JSON.parse(await readFile(path.join(dir, 'manifest.json'), 'utf8'));
const engine = new BABYLON.NullEngine();
let failed = false;
for (const sp of manifest.species) {
  const lod = JSON.parse(await readFile(path.join(dir, sp.lod_json), 'utf8'));
  const glb = await readFile(path.join(dir, sp.chain));
  const levels = chainLevels(glb);
  // Geometry (skipMaterials): what is asserted. Babylon.js's level order is coarsest first.
  let r;
  try {
    r = await loadChain(engine, new Uint8Array(glb), true, levels.length);
  } catch (e) {
    console.log(`${sp.chain}: Babylon.js failed to load it: ${String(e).split('\n')[0]}`);
    failed = true;
    continue;
  }
  const rows = [];
  let ok = r.lods.length === lod.levels.length && r.lods.every((v, i) => v === i);
  levels.forEach((l, i) => {
    const c = { triangles: 0, lines: 0, missing: 0 };
    l.modes.forEach((mode, p) => {
      const n = r.indices.get(`/meshes/${l.mesh}/primitives/${p}`);
      if (n === undefined) c.missing += 1;
      else if (mode === 1) c.lines += n / 2;
      else c.triangles += n / 3;
    });
    const want = lod.levels[i] ?? {};
    const good = c.missing === 0 && c.triangles === want.triangles && c.lines === want.lines;
    ok &&= good;
    rows.push(`${i}:${c.triangles}t/${c.lines}l${good ? '' : ` (lod.json ${want.triangles}t/${want.lines}l` +
              `${c.missing ? `, ${c.missing} primitive(s) not loaded` : ''})`}`);
  });
  // After loading, only level 0 (the finest) is left enabled.
  const finest = levels[0].modes.map((_, p) => `/meshes/${levels[0].mesh}/primitives/${p}`);
  const finalOk = r.final.size === finest.length && finest.every((p) => r.final.has(p));
  ok &&= finalOk;
  // With materials (a user's default): reported, not asserted (docs/clients.md: a race in
  // Babylon.js's MSFT_lod when a finer level finishes loading before a coarser one).
  let withMaterials = 'loads';
  try {
    await loadChain(engine, new Uint8Array(glb), false, levels.length);
  } catch (e) {
    withMaterials = `FAILS (${String(e).split('\n')[0].replace(/^.*: /, '')})`;
  }
  console.log(`${sp.chain}: Babylon.js MSFT_lod: ${r.lods.length} level(s) (lod.json: ${lod.levels.length}), ` +
              `loaded coarsest first; per level ${rows.join(' ')}; afterwards ${finalOk ? 'only level 0' : 'NOT only level 0'} ` +
              `enabled; with materials: ${withMaterials}  ${ok ? 'ok' : 'WRONG'}`);
  failed ||= !ok;
}
// A forest's tiles (docs/clients.md "Forest tiles"), when the directory holds one (a pack's copy):
// each tile file, loaded as a Babylon.js user would (its EXT_mesh_gpu_instancing makes thin
// instances), must draw every primitive of every node as often as the file instances it --
// lines included. Babylon.js in node reads no external files, so each .gltf and the buffers it
// names become one GLB first (file-uri buffers concatenated into the binary chunk).
function gltfAsGlb(json, dir) {
  const j = structuredClone(json);
  const chunks = [];
  let length = 0;
  const moves = [];
  const kept = [{}];
  j.buffers.forEach((b, i) => {
    if (!b.uri || b.uri.startsWith('data:')) {
      moves[i] = { buffer: kept.length, shift: 0 };
      kept.push(b);
      return;
    }
    const bytes = readFileSync(path.join(dir, decodeURIComponent(b.uri))).subarray(0, b.byteLength);
    const pad = (4 - (length % 4)) % 4;
    if (pad) chunks.push(Buffer.alloc(pad));
    length += pad;
    moves[i] = { buffer: 0, shift: length };
    chunks.push(bytes);
    length += bytes.length;
  });
  const pad = (4 - (length % 4)) % 4;
  if (pad) chunks.push(Buffer.alloc(pad));
  length += pad;
  kept[0].byteLength = length;
  const move = (r) => {
    const m = moves[r.buffer ?? 0];
    r.buffer = m.buffer;
    if (m.shift) r.byteOffset = (r.byteOffset ?? 0) + m.shift;
  };
  for (const v of j.bufferViews ?? []) {
    move(v);
    if (v.extensions?.EXT_meshopt_compression) move(v.extensions.EXT_meshopt_compression);
  }
  j.buffers = kept;
  let text = Buffer.from(JSON.stringify(j), 'utf8');
  if (text.length % 4) text = Buffer.concat([text, Buffer.alloc(4 - (text.length % 4), 0x20)]);
  const header = Buffer.alloc(20);
  header.write('glTF', 0);
  header.writeUInt32LE(2, 4);
  header.writeUInt32LE(12 + 8 + text.length + 8 + length, 8);
  header.writeUInt32LE(text.length, 12);
  header.write('JSON', 16);
  const binHeader = Buffer.alloc(8);
  binHeader.writeUInt32LE(length, 0);
  binHeader.write('BIN\0', 4, 'latin1');
  return Buffer.concat([header, text, binHeader, ...chunks]);
}

// What the file says is drawn: per node with a mesh, each primitive's elements times the node's
// instances (EXT_mesh_gpu_instancing count, else 1).
function declared(j) {
  const c = { triangles: 0, lines: 0 };
  for (const n of j.nodes ?? []) {
    if (n.mesh === undefined) continue;
    const inst = n.extensions?.EXT_mesh_gpu_instancing?.attributes?.TRANSLATION;
    const times = inst === undefined ? 1 : j.accessors[inst].count;
    for (const p of j.meshes[n.mesh].primitives) {
      const count = p.indices !== undefined ? j.accessors[p.indices].count : j.accessors[p.attributes.POSITION].count;
      if ((p.mode ?? 4) === 1) c.lines += (count / 2) * times;
      else c.triangles += (count / 3) * times;
    }
  }
  return c;
}

async function loadTile(bytes, modes) {
  const scene = new BABYLON.Scene(engine);
  const c = { triangles: 0, lines: 0 };
  const observer = BABYLON.SceneLoader.OnPluginActivatedObservable.add((plugin) => {
    plugin.skipMaterials = true;
  });
  try {
    await BABYLON.SceneLoader.ImportMeshAsync('', '', bytes, scene, null, '.glb');
    for (const m of scene.meshes) {
      const pointers = m._internalMetadata?.gltf?.pointers ?? [];
      const mode = modes.get(pointers[0]);
      if (mode === undefined || !m.isEnabled()) continue;
      const times = (m.thinInstanceCount ?? 0) > 0 ? m.thinInstanceCount : 1;
      const n = (m.subMeshes ?? []).reduce((s, sm) => s + sm.indexCount, 0) * times;
      if (mode === 1) c.lines += n / 2;
      else c.triangles += n / 3;
    }
  } finally {
    BABYLON.SceneLoader.OnPluginActivatedObservable.remove(observer);
    scene.dispose();
  }
  return c;
}

if (existsSync(path.join(dir, 'instances.json')) && existsSync(path.join(dir, 'tileset.json'))) {
  const tiles = readdirSync(dir).filter((f) => /^tile_\d+_\d+_lod\d+\.gltf$/.test(f)).sort();
  let good = 0;
  for (const f of tiles) {
    const j = JSON.parse(readFileSync(path.join(dir, f), 'utf8'));
    const modes = new Map();
    j.meshes.forEach((m, k) => m.primitives.forEach((p, i) => modes.set(`/meshes/${k}/primitives/${i}`, p.mode ?? 4)));
    const want = declared(j);
    let got;
    try {
      got = await loadTile(new Uint8Array(gltfAsGlb(j, dir)), modes);
    } catch (e) {
      console.log(`${f}: Babylon.js failed to load it: ${String(e).split('\n')[0]}  WRONG`);
      failed = true;
      continue;
    }
    const ok = got.triangles === want.triangles && got.lines === want.lines;
    if (ok) ++good;
    else console.log(`${f}: Babylon.js draws ${got.triangles}t/${got.lines}l, the file instances ${want.triangles}t/${want.lines}l  WRONG`);
    failed ||= !ok;
  }
  console.log(`forest tiles: ${good} of ${tiles.length} draw in Babylon.js every primitive as often as the file instances it`);
  if (tiles.length === 0) failed = true;
}
engine.dispose();
process.exit(failed ? 1 : 0);
