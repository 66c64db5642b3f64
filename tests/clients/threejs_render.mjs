#!/usr/bin/env node
// The second, independent renderer of the test suite: three.js (npm `three`, its stock
// GLTFLoader + DRACOLoader + MeshoptDecoder) in Debian's headless Chromium, driven by npm `playwright-core`.
// It renders glTF files exactly as a three.js user would load them, from cameras that sylva's
// renderer uses too (tests/clients/client_agreement.cpp compares the two), and checks with the
// MSFT_lod plugin of npm `three-gltf-extensions` which level a chain shows at given distances.
//
//   node tests/clients/threejs_render.mjs JOBS.json RESULT.json
//
// JOBS.json:
//   { "width": 512, "height": 512, "antialias": true,
//     "lighting": { "ambient": [r,g,b], "light_color": [r,g,b], "direction_to_light": [x,y,z] },
//     "renders": [ { "file": "/abs/x.gltf", "out": "/abs/x.png",
//                    "camera": { "eye": [..], "target": [..], "up": [..], "fov_y_deg": 45,
//                                "near": 0.1, "far": 100 } }, ... ],
//     "lod_checks": [ { "file": "/abs/lod.gltf", "fov_y_deg": 45, "radius": 24.0,
//                       "distances": [d, ...] }, ... ],
//     "load_checks": [ { "file": "/abs/oak.glb", "msft_lod": true }, ... ] }
// RESULT.json: { "renders": [{ "out", "ms" }], "lod_checks": [{ "file", "levels", "shown": [level per
//   distance] }], "load_checks": [{ "file", "levels": [{ "triangles", "lines", "points" }] }],
//   "renderer": "<WebGL renderer string>" }
// A load check loads the file as a three.js user would (with the MSFT_lod plugin when msft_lod:
// then one entry per LOD level the plugin made, else one for the whole scene) and counts the
// primitives three.js would draw.
//
// The page gets every file through Playwright request interception on a made-up origin
// (http://sylva.invalid/): no server, no network. Lighting matches libs/render's Lighting:
// three.js's physically based diffuse is albedo * irradiance / pi, so the lights get intensity
// pi * (sylva's value) (docs/clients.md, "The second renderer").
//
// Chromium: /usr/bin/chromium (or $SYLVA_CHROMIUM), started headless with a fresh profile and
// everything that could reach the network off; WebGL runs on SwiftShader (no GPU): the browser
// and the page's file serving are tests/clients/headless_chromium.mjs, shared with
// tests/forest/cesium_tileset.mjs.
// Exit codes: 0 done; 1 a render or check failed (message on stderr); 2 usage; 3 a tool is
// missing (playwright-core, three, or chromium) -- the C++ test turns 3 into a skip unless
// SYLVA_REQUIRE_CLIENTS=1.
import { readFile, writeFile } from 'node:fs/promises';
import path from 'node:path';

import { ORIGIN, openPage, requireTools } from './headless_chromium.mjs';

const args = process.argv.slice(2);
if (args.length !== 2) {
  process.stderr.write('usage: node tests/clients/threejs_render.mjs JOBS.json RESULT.json\n');
  process.exit(2);
}
requireTools('threejs_render', ['three', 'three-gltf-extensions']);

const jobs = JSON.parse(await readFile(args[0], 'utf8'));

const PAGE = `<!doctype html><html><head><meta charset="utf-8">
<script type="importmap">{ "imports": {
  "three": "${ORIGIN}/npm/three/build/three.module.js",
  "three/addons/": "${ORIGIN}/npm/three/examples/jsm/",
  "three-gltf-extensions/": "${ORIGIN}/npm/three-gltf-extensions/" } }</script>
</head><body style="margin:0">
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import GLTFLodExtension from 'three-gltf-extensions/loaders/MSFT_lod/MSFT_lod.js';

let renderer = null;
function setup(o) {
  const canvas = document.createElement('canvas');
  canvas.width = o.width; canvas.height = o.height;
  document.body.appendChild(canvas);
  renderer = new THREE.WebGLRenderer({ canvas, antialias: o.antialias, alpha: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(o.width, o.height, false);
  renderer.setClearColor(0x000000, 0);  // transparent: alpha is the coverage
  const gl = renderer.getContext();
  const dbg = gl.getExtension('WEBGL_debug_renderer_info');
  return dbg ? gl.getParameter(dbg.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
}

function loader(plugins) {
  const l = new GLTFLoader();
  const draco = new DRACOLoader();
  draco.setDecoderPath('${ORIGIN}/npm/three/examples/jsm/libs/draco/');
  l.setDRACOLoader(draco);
  l.setMeshoptDecoder(MeshoptDecoder);
  for (const p of plugins) l.register(p);
  return l;
}

function lights(scene, li) {
  scene.add(new THREE.AmbientLight(new THREE.Color(...li.ambient), Math.PI));
  const sun = new THREE.DirectionalLight(new THREE.Color(...li.light_color), Math.PI);
  sun.position.set(...li.direction_to_light);
  scene.add(sun);  // target at the origin: light travels along -direction_to_light
}

window.renderJob = async (o, job) => {
  const gltf = await loader([]).loadAsync('${ORIGIN}/fs' + job.file);
  const scene = new THREE.Scene();
  scene.add(gltf.scene);
  lights(scene, o.lighting);
  const c = job.camera;
  const cam = new THREE.PerspectiveCamera(c.fov_y_deg, o.width / o.height, c.near, c.far);
  cam.position.set(...c.eye);
  cam.up.set(...c.up);
  cam.lookAt(new THREE.Vector3(...c.target));
  renderer.render(scene, cam);
  const url = renderer.domElement.toDataURL('image/png');
  scene.traverse((x) => { if (x.geometry) x.geometry.dispose(); if (x.material) x.material.dispose(); });
  renderer.renderLists.dispose();
  return url.slice(url.indexOf(',') + 1);
};

// MSFT_lod with the plugin's calculateDistance hook inverting sylva's documented coverage:
// level L >= 1 is shown from d = R sqrt(pi) / (2 tan(fov/2) sqrt(c[L-1])).
window.lodJob = async (o, job) => {
  const t = Math.tan(job.fov_y_deg * Math.PI / 360);
  const distance = (level, lowest, coverages) =>
    level === 0 ? 0 : job.radius * Math.sqrt(Math.PI) / (2 * t * Math.sqrt(coverages[level - 1]));
  const gltf = await loader([(p) => new GLTFLodExtension(p, { calculateDistance: distance })])
      .loadAsync('${ORIGIN}/fs' + job.file);
  let lod = null;
  gltf.scene.traverse((x) => { if (x.isLOD && !lod) lod = x; });
  if (!lod) throw new Error(job.file + ': the MSFT_lod plugin made no LOD object');
  gltf.scene.updateMatrixWorld(true);
  const cam = new THREE.PerspectiveCamera(job.fov_y_deg, 1, 0.1, 1e6);
  const shown = job.distances.map((d) => {
    cam.position.set(0, 0, d);  // three.js measures from the LOD object's origin
    cam.updateMatrixWorld(true);
    lod.update(cam);
    return lod.getCurrentLevel();
  });
  return { levels: lod.levels.length, level_distances: lod.levels.map((l) => l.distance), shown };
};
// Triangles, line segments and points three.js draws for the objects under root (an
// InstancedMesh's once per instance).
function counts(root) {
  const c = { triangles: 0, lines: 0, points: 0 };
  root.traverse((x) => {
    const g = x.geometry;
    if (!g) return;
    const n = (g.index ? g.index.count : g.attributes.position.count) * (x.isInstancedMesh ? x.count : 1);
    if (x.isLineSegments) c.lines += n / 2;
    else if (x.isLine) c.lines += Math.max(0, n - 1);
    else if (x.isPoints) c.points += n;
    else if (x.isMesh) c.triangles += n / 3;
  });
  return c;
}

window.loadJob = async (o, job) => {
  const url = '${ORIGIN}/fs' + job.file;
  if (!job.msft_lod) return { levels: [counts((await loader([]).loadAsync(url)).scene)] };
  const gltf = await loader([(p) => new GLTFLodExtension(p, { calculateDistance: (level) => level })])
      .loadAsync(url);
  let lod = null;
  gltf.scene.traverse((x) => { if (x.isLOD && !lod) lod = x; });
  if (!lod) throw new Error(job.file + ': the MSFT_lod plugin made no LOD object');
  return { levels: lod.levels.map((l) => counts(l.object)) };
};
window.setupRenderer = setup;
window.ready = true;
</script></body></html>`;

const roots = [];
for (const j of [...(jobs.renders ?? []), ...(jobs.lod_checks ?? []), ...(jobs.load_checks ?? [])]) roots.push(path.dirname(path.resolve(j.file)));

let session = null;
let failed = false;
try {
  session = await openPage({ html: PAGE, roots });
  const { page, errors } = session;
  await page.goto(ORIGIN + '/');
  await page.waitForFunction(() => window.ready === true, null, { timeout: 60000 });
  const o = { width: jobs.width, height: jobs.height, antialias: jobs.antialias ?? true, lighting: jobs.lighting };
  const result = { renderer: await page.evaluate((o) => window.setupRenderer(o), o), renders: [], lod_checks: [], load_checks: [] };
  for (const job of jobs.renders ?? []) {
    const t0 = Date.now();
    try {
      const b64 = await page.evaluate(([o, job]) => window.renderJob(o, job), [o, job]);
      await writeFile(job.out, Buffer.from(b64, 'base64'));
      result.renders.push({ out: job.out, ms: Date.now() - t0 });
    } catch (e) {
      process.stderr.write(`threejs_render: ${job.file}: ${String(e).split('\n')[0]}\n`);
      result.renders.push({ out: job.out, error: String(e).split('\n')[0] });
      failed = true;
    }
  }
  for (const job of jobs.lod_checks ?? []) {
    try {
      const r = await page.evaluate(([o, job]) => window.lodJob(o, job), [o, job]);
      result.lod_checks.push({ file: job.file, ...r });
    } catch (e) {
      process.stderr.write(`threejs_render: ${job.file}: ${String(e).split('\n')[0]}\n`);
      result.lod_checks.push({ file: job.file, error: String(e).split('\n')[0] });
      failed = true;
    }
  }
  for (const job of jobs.load_checks ?? []) {
    try {
      const r = await page.evaluate(([o, job]) => window.loadJob(o, job), [o, job]);
      result.load_checks.push({ file: job.file, ...r });
    } catch (e) {
      process.stderr.write(`threejs_render: ${job.file}: ${String(e).split('\n')[0]}\n`);
      result.load_checks.push({ file: job.file, error: String(e).split('\n')[0] });
      failed = true;
    }
  }
  if (errors.length) process.stderr.write(`threejs_render: page errors: ${errors.join(' | ')}\n`);
  await writeFile(args[1], JSON.stringify(result, null, 2) + '\n');
} catch (e) {
  process.stderr.write(`threejs_render: ${String(e).split('\n')[0]}\n`);
  failed = true;
} finally {
  if (session) await session.close();
}
process.exit(failed ? 1 : 0);
