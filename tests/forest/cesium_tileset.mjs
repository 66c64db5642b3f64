#!/usr/bin/env node
// CesiumJS streams a forest's 3D Tiles 1.1 tileset with no conversion (issue 13 "Output";
// docs/stages/forest.md "tileset.json and the error model"): npm `cesium` (its stock
// Cesium3DTileset and glTF loader) in Debian's headless Chromium, driven by npm `playwright-core`,
// as tests/clients/threejs_render.mjs drives three.js.
//
//   node tests/forest/cesium_tileset.mjs FOREST_DIR RESULT.json [PNG_PREFIX]
//
// FOREST_DIR is a forest artifact (tileset.json, instances.json, the tile and level glTF files).
// Two views, both with maximumScreenSpaceError = the forest's pixel error delta, so Cesium's
// refinement test is sylva's switch-distance test (a tile of geometricError e is refined when
// e H / (d 2 tan(fovy/2)) > delta, Cesium's H and fovy):
//   - `far`: the forest seen from the range where Cesium must draw every tile at one coarse tile
//     level L and no other: the coarsest level whose range interval [e_L, e_{L+1}) x H / (delta
//     2 tan(fovy/2)), shrunk by the forest's size on both sides, is not empty and from which the
//     forest still spans >= 8 pixels (the last level, the impostors, when they are visible at all;
//     billboards are valid only from tens of km on, where the forest is sub-pixel, so then the lod
//     levels' coarsest);
//   - `near`: the eye a few metres above the forest's middle: Cesium must refine the tiles under
//     it to level 0 (full detail) and draw it.
// The last tile level's contents must have been requested and loaded (Cesium loads a chain's
// ancestors on its way down) even when no view shows them. The forest's ground (instances.json
// `ground`, a leaf tile under the root) must be drawn in both views; it is not a tile level.
// It fails (exit 1) when the tileset or any tile content fails to load, the page logs an error,
// a view draws nothing, or a view shows the wrong levels. RESULT.json records per view the tile
// levels drawn, the tiles loaded and the covered pixels; PNG_PREFIX<view>.png are the frames.
// Exit codes: 0 passed; 1 failed (message on stderr); 2 usage; 3 a tool is missing
// (playwright-core, cesium or chromium) -- the ctest skips (77) on 3 unless SYLVA_REQUIRE_CLIENTS=1.
//
// Everything is served through Playwright request interception on a made-up origin: no server,
// no network (no Cesium ion: no imagery layer, ellipsoid terrain). The browser and the serving
// are tests/clients/headless_chromium.mjs, shared with tests/clients/threejs_render.mjs.
import { readFile, writeFile } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import path from 'node:path';

import { ORIGIN, openPage, requireTools } from '../clients/headless_chromium.mjs';

const args = process.argv.slice(2);
if (args.length < 2 || args.length > 3) {
  process.stderr.write('usage: node tests/forest/cesium_tileset.mjs FOREST_DIR RESULT.json [PNG_PREFIX]\n');
  process.exit(2);
}
requireTools('cesium_tileset', ['cesium']);

const forestDir = path.resolve(args[0]);
const pngPrefix = args[2] ?? null;
const forest = JSON.parse(await readFile(path.join(forestDir, 'instances.json'), 'utf8'));
if (!existsSync(path.join(forestDir, 'tileset.json'))) {
  process.stderr.write(`cesium_tileset: ${forestDir}/tileset.json is missing\n`);
  process.exit(1);
}
// The forest's delta, its trees' height and its tile level count.
const delta = Math.max(...forest.species.map((s) => s.pixel_error_px));
let height = 1, levelCount = 1;
for (const s of forest.species) {
  const lv = s.levels;
  height = Math.max(height, s.bounds.max[1] - s.bounds.min[1]);
  levelCount = Math.max(levelCount, lv.length);
}
const size = Math.max(forest.extent_m.max[0] - forest.extent_m.min[0], forest.extent_m.max[1] - forest.extent_m.min[1]);
// Per tile level L: the smallest and largest geometricError of the tileset's tiles at L.
const tileset = JSON.parse(await readFile(path.join(forestDir, 'tileset.json'), 'utf8'));
const levelErrors = [];
(function walk(t) {
  const m = t.content ? /_lod(\d+)\.gltf$/.exec(t.content.uri) : null;
  if (m) {
    const l = Number(m[1]);
    const e = levelErrors[l] ?? { min: Infinity, max: 0 };
    levelErrors[l] = { min: Math.min(e.min, t.geometricError), max: Math.max(e.max, t.geometricError) };
  }
  for (const c of t.children ?? []) walk(c);
})(tileset.root);
const job = {
  tileset: `${ORIGIN}/fs${forestDir}/tileset.json`,
  mse: delta,
  width: 480,
  height: 270,
  lastLevel: levelCount - 1,
  ground: forest.ground ?? null,  // the ground tile's content: drawn in every view, not a tile level
  levelErrors,
  rootError: tileset.root.geometricError,
  margin: size + height,  // Cesium measures to each tile's box: within this of the forest's centre
  size,
  views: [
    { name: 'far', level: 'coarsest visible', pitchDeg: -30, headingDeg: 20 },
    { name: 'near', range: Math.max(3, 0.25 * height), pitchDeg: -60, headingDeg: 20 },
  ],
};

const PAGE = `<!doctype html><html><head><meta charset="utf-8">
<script>window.CESIUM_BASE_URL = '${ORIGIN}/npm/cesium/Build/Cesium/';</script>
<script src="${ORIGIN}/npm/cesium/Build/Cesium/Cesium.js"></script>
<style>html, body, #c { margin: 0; width: ${job.width}px; height: ${job.height}px; overflow: hidden; }
#c canvas { width: 100%; height: 100%; display: block; }</style>
</head><body><div id="c"></div>
<script>
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
window.runJob = async (job) => {
  const widget = new Cesium.CesiumWidget('c', {
    baseLayer: false, terrainProvider: new Cesium.EllipsoidTerrainProvider(), skyBox: false,
    skyAtmosphere: false, useDefaultRenderLoop: false, requestRenderMode: false,
    contextOptions: { webgl: { preserveDrawingBuffer: true, alpha: false } },
  });
  const scene = widget.scene;
  scene.globe.baseColor = Cesium.Color.BLACK;
  scene.backgroundColor = Cesium.Color.BLACK;
  scene.fog.enabled = false;
  const failures = [];
  const tileset = await Cesium.Cesium3DTileset.fromUrl(job.tileset, { maximumScreenSpaceError: job.mse });
  tileset.tileFailed.addEventListener((e) => failures.push(String(e.url) + ': ' + String(e.message)));
  scene.primitives.add(tileset);
  const center = tileset.boundingSphere.center;
  const results = [];
  widget.resize();
  widget.render();
  for (const v of job.views) {
    let range = v.range, expected = null;
    if (v.level !== undefined) {
      // Cesium's distance per unit of error at the refinement threshold: d = e H / (delta den).
      const perError = scene.drawingBufferHeight / (job.mse * scene.camera.frustum.sseDenominator);
      const rootFrom = job.rootError * perError;  // beyond this Cesium draws nothing (root has no content)
      for (let l = job.levelErrors.length - 1; l >= 0 && expected === null; --l) {
        if (!job.levelErrors[l]) continue;
        const lo = 1.2 * job.levelErrors[l].max * perError + job.margin;
        const next = l + 1 < job.levelErrors.length ? job.levelErrors[l + 1].min * perError : rootFrom;
        const hi = 0.8 * Math.min(next, rootFrom) - job.margin;
        const pixels = job.size * scene.drawingBufferHeight / (lo * scene.camera.frustum.sseDenominator);
        if (lo < hi && pixels >= 8) { range = lo; expected = l; }
      }
      if (expected === null) throw new Error('view ' + v.name + ': no tile level is visible on its own');
    }
    widget.camera.lookAt(center, new Cesium.HeadingPitchRange(Cesium.Math.toRadians(v.headingDeg),
                                                              Cesium.Math.toRadians(v.pitchDeg), range));
    const shown = new Set();
    const listener = (tile) => { if (tile.content && tile.content.url) shown.add(tile.content.url); };
    let frames = 0;
    const t0 = Date.now();
    // Render until the tileset has loaded everything this view needs (and a few frames more).
    for (let settled = 0; frames < 600 && settled < 3 && Date.now() - t0 < 240000; ++frames) {
      widget.resize();
      widget.render();
      await sleep(frames < 5 ? 20 : 100);
      settled = tileset.tilesLoaded ? settled + 1 : 0;
    }
    tileset.tileVisible.addEventListener(listener);
    widget.render();
    tileset.tileVisible.removeEventListener(listener);
    const canvas = scene.canvas;
    const gl = scene.context._gl;
    const px = new Uint8Array(canvas.width * canvas.height * 4);
    gl.readPixels(0, 0, canvas.width, canvas.height, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let covered = 0;
    for (let i = 0; i < px.length; i += 4) if (px[i] + px[i + 1] + px[i + 2] > 12) ++covered;
    const ground = job.ground && [...shown].some((u) => u.endsWith(job.ground));
    const levels = [...shown].filter((u) => !job.ground || !u.endsWith(job.ground))
                     .map((u) => { const m = /_lod(\\d+)\\.gltf/.exec(u); return m ? Number(m[1]) : -1; });
    results.push({
      name: v.name, range, expected_level: expected, canvas: [canvas.width, canvas.height, canvas.clientWidth, canvas.clientHeight], frames, ms: Date.now() - t0, tiles_loaded: tileset.tilesLoaded,
      contents_shown: shown.size, ground_shown: ground, levels: [...new Set(levels)].sort((a, b) => a - b), covered_pixels: covered,
      png: canvas.toDataURL('image/png').split(',')[1],
      statistics: { visited: tileset.statistics.visited, selected: tileset.statistics.selected,
                    commands: tileset.statistics.numberOfCommands,
                    contents_ready: tileset.statistics.numberOfTilesWithContentReady },
    });
  }
  widget.destroy();
  return { failures, views: results };
};
window.ready = true;
</script></body></html>`;

let session = null;
let failed = false;
const fail = (m) => { process.stderr.write(`cesium_tileset: ${m}\n`); failed = true; };
try {
  const requested = [];
  session = await openPage({
    html: PAGE,
    roots: [forestDir],
    viewport: { width: job.width, height: job.height },
    onFile: (file, served, errors) => {
      if (!file.startsWith(forestDir + path.sep)) return;
      requested.push(path.basename(file));
      if (!served) errors.push(`requested a file the forest does not have: ${file}`);
    },
  });
  const { page, errors } = session;
  page.setDefaultTimeout(600000);
  await page.goto(ORIGIN + '/');
  await page.waitForFunction(() => window.ready === true && typeof Cesium !== 'undefined', null, { timeout: 120000 });
  const r = await page.evaluate((job) => window.runJob(job), job);
  const out = { cesium: 'npm cesium', tileset: path.join(forestDir, 'tileset.json'), maximum_screen_space_error: job.mse,
                last_level: job.lastLevel, failures: r.failures, page_errors: errors,
                files_requested: [...new Set(requested)].sort(), views: [] };
  for (const v of r.views) {
    if (pngPrefix) await writeFile(`${pngPrefix}${v.name}.png`, Buffer.from(v.png, 'base64'));
    const { png, ...rest } = v;
    out.views.push(rest);
  }
  await writeFile(args[1], JSON.stringify(out, null, 2) + '\n');
  for (const f of r.failures) fail(`a tile failed to load: ${f}`);
  for (const e of errors) fail(`page error: ${e}`);
  for (const v of out.views) {
    if (!v.tiles_loaded) fail(`view ${v.name}: the tileset did not finish loading`);
    if (v.contents_shown === 0 || v.covered_pixels === 0)
      fail(`view ${v.name}: nothing drawn (${v.contents_shown} contents, ${v.covered_pixels} covered pixels)`);
  }
  const far = out.views.find((v) => v.name === 'far'), near = out.views.find((v) => v.name === 'near');
  if (far.levels.some((l) => l !== far.expected_level))
    fail(`view far: levels ${far.levels.join(',')} drawn at ${far.range.toFixed(0)} m, expected only ${far.expected_level}`);
  if (!out.files_requested.some((f) => f.endsWith(`_lod${job.lastLevel}.gltf`)))
    fail(`the last tile level's contents (_lod${job.lastLevel}.gltf) were never requested`);
  if (job.ground && !(far.ground_shown && near.ground_shown))
    fail(`the ground (${job.ground}) was not drawn in both views (far ${far.ground_shown}, near ${near.ground_shown})`);
  if (!near.levels.includes(0)) fail(`view near: levels ${near.levels.join(',')} drawn, level 0 (full detail) missing`);
  process.stdout.write(`cesium_tileset: far (${far.range.toFixed(0)} m) levels [${far.levels}] (${far.contents_shown} contents, ` +
                       `${far.covered_pixels} px), near levels [${near.levels}] (${near.contents_shown} contents, ` +
                       `${near.covered_pixels} px); ${out.files_requested.length} files requested\n`);
} catch (e) {
  fail(String(e).split('\n')[0]);
} finally {
  if (session) await session.close();
}
process.exit(failed ? 1 : 0);
