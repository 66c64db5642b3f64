// The headless browser the client harnesses share (tests/clients/threejs_render.mjs,
// tests/forest/cesium_tileset.mjs): Debian's Chromium (/usr/bin/chromium, or $SYLVA_CHROMIUM)
// driven by npm `playwright-core` from the repository's npm directory (out/npm, or
// $SYLVA_NPM_DIR; tools/npm pins the versions), WebGL through SwiftShader, a fresh profile per
// run, and no network: the page is served from an invalid origin whose requests are answered
// here, `/` with the harness's HTML, `/npm/<path>` from node_modules and `/fs/<absolute path>`
// from the allowed directories only (anything else: 404; other origins: aborted).
import { createRequire } from 'node:module';
import { readFile, mkdtemp, rm } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
export const npmDir = process.env.SYLVA_NPM_DIR ?? path.join(repo, 'out', 'npm');
export const modules = path.join(npmDir, 'node_modules');
export const chromiumPath = process.env.SYLVA_CHROMIUM ?? '/usr/bin/chromium';
export const ORIGIN = 'http://sylva.invalid';

// Exits 3 ("a required tool is missing": the tests turn it into a skip unless
// SYLVA_REQUIRE_CLIENTS=1) when an npm package of `packages` or Chromium is missing; `name`
// prefixes the message.
export function requireTools(name, packages) {
  const missing = (what) => {
    process.stderr.write(`${name}: ${what} (run tools/setup.sh)\n`);
    process.exit(3);
  };
  for (const m of ['playwright-core', ...packages])
    if (!existsSync(path.join(modules, m))) missing(`the npm package ${m} is not installed in ${modules}`);
  if (!existsSync(chromiumPath)) missing(`chromium is not installed (${chromiumPath}; Debian package chromium)`);
}

export function contentType(p) {
  if (p.endsWith('.js') || p.endsWith('.mjs')) return 'text/javascript';
  if (p.endsWith('.wasm')) return 'application/wasm';
  if (p.endsWith('.png')) return 'image/png';
  if (p.endsWith('.jpg')) return 'image/jpeg';
  if (p.endsWith('.css')) return 'text/css';
  if (p.endsWith('.json') || p.endsWith('.gltf')) return 'application/json';
  return 'application/octet-stream';
}

// Starts Chromium and opens ORIGIN + '/' serving `html`. `roots`: directories whose files `/fs/`
// may serve (node_modules is always one). `viewport`: {width, height} or undefined (Playwright's
// default). `onFile(file, served, errors)`: called for every `/npm/` or `/fs/` request with the
// file it names and whether it is served; it may add to `errors`. Returns { page, errors, close }:
// `errors` collects the page's uncaught exceptions and console errors; close() stops the browser
// and removes the profile. Throws (after cleaning up) when Chromium does not start.
export async function openPage({ html, roots = [], viewport, onFile }) {
  const allowed = [modules, ...roots];
  const profile = await mkdtemp(path.join(os.tmpdir(), 'sylva-chromium-'));
  let browser = null;
  const close = async () => {
    if (browser) await browser.close();
    await rm(profile, { recursive: true, force: true });
  };
  try {
    const { chromium } = createRequire(import.meta.url)(path.join(modules, 'playwright-core'));
    // A persistent context is Playwright's way to pass a fresh --user-data-dir (the profile).
    browser = await chromium.launchPersistentContext(profile, {
      executablePath: chromiumPath,
      headless: true,
      ...(viewport ? { viewport } : {}),
      args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
             '--disable-background-networking', '--disable-component-update', '--disable-sync',
             '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
    });
    const page = browser.pages()[0] ?? await browser.newPage();
    const errors = [];
    page.on('pageerror', (e) => errors.push(String(e)));
    page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
    await page.route('**/*', async (route) => {
      const url = new URL(route.request().url());
      if (url.origin !== ORIGIN) return route.abort();
      if (url.pathname === '/') return route.fulfill({ body: html, contentType: 'text/html' });
      let file = null;
      if (url.pathname.startsWith('/npm/')) file = path.join(modules, decodeURIComponent(url.pathname.slice(5)));
      else if (url.pathname.startsWith('/fs/')) file = path.resolve('/' + decodeURIComponent(url.pathname.slice(4)));
      const served = file !== null && allowed.some((r) => file.startsWith(r + path.sep)) && existsSync(file);
      if (file !== null && onFile) onFile(file, served, errors);
      if (!served) return route.fulfill({ status: 404, body: 'not found' });
      return route.fulfill({ body: await readFile(file), contentType: contentType(file) });
    });
    return { page, errors, close };
  } catch (e) {
    await close();
    throw e;
  }
}
