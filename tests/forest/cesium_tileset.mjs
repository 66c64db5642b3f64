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
// refinement test is sylva's switch-distance test:
//   - `far`: the forest seen from beyond every species' last switch distance: every tile Cesium
//     draws must be at the last tile level (the impostors, when the species have them);
//   - `near`: the eye a few metres above the forest's middle: Cesium must refine the tiles under
//     it to level 0 (full detail) and draw it.
// It fails (exit 1) when the tileset or any tile content fails to load, the page logs an error,
// a view draws nothing, or a view shows the wrong levels. RESULT.json records per view the tile
// levels drawn, the tiles loaded and the covered pixels; PNG_PREFIX<view>.png are the frames.
// Exit codes: 0 passed; 1 failed (message on stderr); 2 usage; 3 a tool is missing
// (playwright-core, cesium or chromium) -- the ctest skips (77) on 3 unless SYLVA_REQUIRE_CLIENTS=1.
//
// Everything is served through Playwright request interception on a made-up origin: no server,
// no network (no Cesium ion: no imagery layer, ellipsoid terrain).
import { createRequire } from 'node:module';
import { readFile, writeFile, mkdtemp, rm } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const scriptDir = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(scriptDir, '..', '..');
const npmDir = process.env.SYLVA_NPM_DIR ?? path.join(repo, 'out', 'npm');
const modules = path.join(npmDir, 'node_modules');
const chromiumPath = process.env.SYLVA_CHROMIUM ?? '/usr/bin/chromium';
const ORIGIN = 'http://sylva.invalid';

function missing(what) {
  process.stderr.write(`cesium_tileset: ${what} (run tools/setup.sh)\n`);
  process.exit(3);
}

const args = process.argv.slice(2);
if (args.length < 2 || args.length > 3) {
  process.stderr.write('usage: node tests/forest/cesium_tileset.mjs FOREST_DIR RESULT.json [PNG_PREFIX]\n');
  process.exit(2);
}
for (const m of ['playwright-core', 'cesium'])
  if (!existsSync(path.join(modules, m))) missing(`the npm package ${m} is not installed in ${modules}`);
if (!existsSync(chromiumPath)) missing(`chromium is not installed (${chromiumPath}; Debian package chromium)`);

const forestDir = path.resolve(args[0]);
const pngPrefix = args[2] ?? null;
const forest = JSON.parse(await readFile(path.join(forestDir, 'instances.json'), 'utf8'));
if (!existsSync(path.join(forestDir, 'tileset.json'))) {
  process.stderr.write(`cesium_tileset: ${forestDir}/tileset.json is missing\n`);
  process.exit(1);
}
// The forest's delta, its size, and the farthest last-level switch distance of its species.
const delta = Math.max(...forest.species.map((s) => s.pixel_error_px));
let lastSwitch = 0, height = 1, levelCount = 1;
for (const s of forest.species) {
  const lv = s.levels;
  lastSwitch = Math.max(lastSwitch, lv[lv.length - 1].switch_distance_m);
  height = Math.max(height, s.bounds.max[1] - s.bounds.min[1]);
  levelCount = Math.max(levelCount, lv.length);
}
const size = Math.max(forest.extent_m.max[0] - forest.extent_m.min[0], forest.extent_m.max[1] - forest.extent_m.min[1]);
const job = {
  tileset: `${ORIGIN}/fs${forestDir}/tileset.json`,
  mse: delta,
  width: 480,
  height: 270,
  lastLevel: levelCount - 1,
  views: [
    // Far enough that every tree is beyond its last switch distance (Cesium measures to the tile's box).
    { name: 'far', range: 1.5 * lastSwitch + size, pitchDeg: -30, headingDeg: 20 },
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
  for (const v of job.views) {
    widget.camera.lookAt(center, new Cesium.HeadingPitchRange(Cesium.Math.toRadians(v.headingDeg),
                                                              Cesium.Math.toRadians(v.pitchDeg), v.range));
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
    const levels = [...shown].map((u) => { const m = /_lod(\\d+)\\.gltf/.exec(u); return m ? Number(m[1]) : -1; });
    results.push({
      name: v.name, canvas: [canvas.width, canvas.height, canvas.clientWidth, canvas.clientHeight], frames, ms: Date.now() - t0, tiles_loaded: tileset.tilesLoaded,
      contents_shown: shown.size, levels: [...new Set(levels)].sort((a, b) => a - b), covered_pixels: covered,
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

function contentType(p) {
  if (p.endsWith('.js') || p.endsWith('.mjs')) return 'text/javascript';
  if (p.endsWith('.wasm')) return 'application/wasm';
  if (p.endsWith('.png')) return 'image/png';
  if (p.endsWith('.jpg')) return 'image/jpeg';
  if (p.endsWith('.css')) return 'text/css';
  if (p.endsWith('.json') || p.endsWith('.gltf')) return 'application/json';
  return 'application/octet-stream';
}

const roots = [modules, forestDir];
const profile = await mkdtemp(path.join(os.tmpdir(), 'sylva-chromium-'));
let browser = null;
let failed = false;
const fail = (m) => { process.stderr.write(`cesium_tileset: ${m}\n`); failed = true; };
try {
  browser = await (createRequire(import.meta.url)(path.join(modules, 'playwright-core'))).chromium.launchPersistentContext(profile, {
    executablePath: chromiumPath,
    headless: true,
    viewport: { width: job.width, height: job.height },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
  });
  const page = browser.pages()[0] ?? await browser.newPage();
  const errors = [];
  const requested = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  await page.route('**/*', async (route) => {
    const url = new URL(route.request().url());
    if (url.origin !== ORIGIN) return route.abort();
    if (url.pathname === '/') return route.fulfill({ body: PAGE, contentType: 'text/html' });
    let file = null;
    if (url.pathname.startsWith('/npm/')) file = path.join(modules, decodeURIComponent(url.pathname.slice(5)));
    else if (url.pathname.startsWith('/fs/')) file = path.resolve('/' + decodeURIComponent(url.pathname.slice(4)));
    if (file && file.startsWith(forestDir + path.sep)) requested.push(path.basename(file));
    if (!file || !roots.some((r) => file.startsWith(r + path.sep)) || !existsSync(file)) {
      if (file && file.startsWith(forestDir + path.sep)) errors.push(`requested a file the forest does not have: ${file}`);
      return route.fulfill({ status: 404, body: 'not found' });
    }
    return route.fulfill({ body: await readFile(file), contentType: contentType(file) });
  });
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
  if (far.levels.some((l) => l !== job.lastLevel))
    fail(`view far: levels ${far.levels.join(',')} drawn beyond every switch distance, expected only ${job.lastLevel}`);
  if (!near.levels.includes(0)) fail(`view near: levels ${near.levels.join(',')} drawn, level 0 (full detail) missing`);
  process.stdout.write(`cesium_tileset: far levels [${far.levels}] (${far.contents_shown} contents, ` +
                       `${far.covered_pixels} px), near levels [${near.levels}] (${near.contents_shown} contents, ` +
                       `${near.covered_pixels} px); ${out.files_requested.length} files requested\n`);
} catch (e) {
  fail(String(e).split('\n')[0]);
} finally {
  if (browser) await browser.close();
  await rm(profile, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
