// A real browser shows the exported tileset: Debian's chromium, headless (SwiftShader WebGL),
// driven by playwright-core, loads a page that runs CesiumJS (npm cesium) from a server on
// 127.0.0.1; every other host is unreachable (resolver rule + request filter), Cesium ion is off
// (empty token, no base layer, ellipsoid terrain). The page places the camera at a pose of the
// database's local frame (a camera path key: position, camera-to-world quaternion looking down -Z
// with +Y up, vertical field of view), waits until the tileset reports its tiles loaded, and the
// screenshot is compared with `hlod play --renderer gl` from the same pose: the model's coverage
// masks (pixels that differ from the shared background colour) must agree (IoU) and colours where
// both show the model must be close (mean absolute difference per channel).
//
// node view_cesium.mjs --tileset DIR --origin LAT,LON,H --camera "px py pz qx qy qz qw vfov"
//     --reference PLAY.png --out SHOT.png [--width 480 --height 360 --min-iou 0.9 --max-colour-diff 20]
// exit 0 pass, 1 fail, 2 usage, 77 skip (chromium or the npm packages missing).
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const args = Object.fromEntries(process.argv.slice(2).reduce((pairs, v, i, all) =>
  (i % 2 === 0 ? [...pairs, [v.replace(/^--/, ''), all[i + 1]]] : pairs), []));
for (const key of ['tileset', 'origin', 'camera', 'reference', 'out'])
  if (!args[key]) { console.error(`view_cesium: --${key} is required`); process.exit(2); }
const width = Number(args.width || 480), height = Number(args.height || 360);
const minIou = Number(args['min-iou'] || 0.9), maxColourDiff = Number(args['max-colour-diff'] || 20);
const chromium = args.chromium || '/usr/bin/chromium';
// `hlod play --renderer gl`'s clear colour (player/gl/gl_renderer.cpp kBackground), used by both.
const background = [0.53, 0.63, 0.75].map((c) => Math.round(c * 255));

let playwright, PNG;
try {
  playwright = await import('playwright-core');
  ({ PNG } = await import('pngjs'));
} catch {
  console.log('view_cesium: npm packages not installed (cd tests/export && npm ci): skipped');
  process.exit(77);
}
const cesiumDir = path.join(here, 'node_modules', 'cesium', 'Build', 'Cesium');
if (!fs.existsSync(cesiumDir) || !fs.existsSync(chromium)) {
  console.log(`view_cesium: ${fs.existsSync(chromium) ? 'cesium' : chromium} missing: skipped`);
  process.exit(77);
}

const page = `<!doctype html><html><head><meta charset="utf-8">
<script src="/cesium/Cesium.js"></script><link href="/cesium/Widgets/widgets.css" rel="stylesheet">
<style>html,body,#view{margin:0;width:100%;height:100%;overflow:hidden}#credits{display:none}</style></head>
<body><div id="view"></div><div id="credits"></div><script>
(async () => {
  const state = window.hlodState = { done: false };
  try {
    Cesium.Ion.defaultAccessToken = '';
    const bg = new Cesium.Color(${background.map((c) => c / 255).join(',')}, 1);
    const widget = new Cesium.CesiumWidget('view', {
      baseLayer: false, terrainProvider: new Cesium.EllipsoidTerrainProvider(), skyBox: false,
      skyAtmosphere: false, creditContainer: 'credits', requestRenderMode: false,
      contextOptions: { webgl: { preserveDrawingBuffer: true } } });
    const scene = widget.scene;
    scene.backgroundColor = bg;
    scene.globe.baseColor = bg;
    scene.globe.showGroundAtmosphere = false;
    scene.globe.enableLighting = false;
    scene.fog.enabled = false;
    if (scene.sun) scene.sun.show = false;
    if (scene.moon) scene.moon.show = false;
    const [lat, lon, h] = [${args.origin}];
    const [px, py, pz, qx, qy, qz, qw, vfov] = [${args.camera.trim().split(/\s+/).map(Number).join(',')}];
    const enu = Cesium.Transforms.eastNorthUpToFixedFrame(Cesium.Cartesian3.fromDegrees(lon, lat, h));
    const q = new Cesium.Quaternion(qx, qy, qz, qw);
    const r = Cesium.Matrix3.fromQuaternion(q);
    const local = (v) => Cesium.Matrix3.multiplyByVector(r, v, new Cesium.Cartesian3());
    const toWorld = (v) => Cesium.Matrix4.multiplyByPointAsVector(enu, v, new Cesium.Cartesian3());
    const camera = scene.camera;
    camera.frustum.near = 0.01;
    const aspect = ${width} / ${height};
    const v = vfov * Math.PI / 180;
    camera.frustum.fov = aspect > 1 ? 2 * Math.atan(Math.tan(v / 2) * aspect) : v;  // Cesium: fov of the larger side
    camera.setView({
      destination: Cesium.Matrix4.multiplyByPoint(enu, new Cesium.Cartesian3(px, py, pz), new Cesium.Cartesian3()),
      orientation: { direction: toWorld(local(new Cesium.Cartesian3(0, 0, -1))),
                     up: toWorld(local(new Cesium.Cartesian3(0, 1, 0))) } });
    const tileset = await Cesium.Cesium3DTileset.fromUrl('/tileset/tileset.json', { maximumScreenSpaceError: 2 });
    scene.primitives.add(tileset);
    let loaded = 0;
    tileset.tileLoad.addEventListener(() => { loaded += 1; });
    tileset.allTilesLoaded.addEventListener(() => {
      // a few more frames so the last loaded tiles are drawn, then report
      let frames = 0;
      const after = scene.postRender.addEventListener(() => {
        if (++frames < 10) return;
        after();
        Object.assign(state, { done: true, tilesLoaded: loaded, selected: tileset.statistics.selected,
                               triangles: tileset.statistics.numberOfTrianglesSelected });
      });
    });
  } catch (e) {
    Object.assign(state, { done: true, error: String(e && e.stack || e) });
  }
})();
</script></body></html>`;

const types = { '.js': 'text/javascript', '.css': 'text/css', '.json': 'application/json', '.glb': 'model/gltf-binary',
                '.wasm': 'application/wasm', '.png': 'image/png', '.jpg': 'image/jpeg', '.svg': 'image/svg+xml' };
const serveFrom = (root, rel, res) => {
  const file = path.join(root, rel);
  if (!file.startsWith(root) || !fs.existsSync(file) || !fs.statSync(file).isFile()) { res.writeHead(404); res.end(); return; }
  res.writeHead(200, { 'Content-Type': types[path.extname(file)] || 'application/octet-stream' });
  fs.createReadStream(file).pipe(res);
};
const tilesetDir = path.resolve(args.tileset);
const server = http.createServer((req, res) => {
  const url = decodeURIComponent(new URL(req.url, 'http://127.0.0.1').pathname);
  if (url === '/page.html') { res.writeHead(200, { 'Content-Type': 'text/html' }); res.end(page); }
  else if (url.startsWith('/cesium/')) serveFrom(cesiumDir, url.slice(8), res);
  else if (url.startsWith('/tileset/')) serveFrom(tilesetDir, url.slice(9), res);
  else { res.writeHead(404); res.end(); }
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
const port = server.address().port;

const browser = await playwright.chromium.launch({
  executablePath: chromium, headless: true,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-background-networking',
         '--disable-component-update', '--no-first-run', '--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1'] });
let status = 1;
try {
  const tab = await browser.newPage({ viewport: { width, height } });
  const outside = [];
  await tab.route('**/*', (route) => {
    const host = new URL(route.request().url()).hostname;
    if (host === '127.0.0.1' || route.request().url().startsWith('data:') || route.request().url().startsWith('blob:'))
      return route.continue();
    outside.push(route.request().url());
    return route.abort();
  });
  const errors = [];
  tab.on('pageerror', (e) => errors.push(String(e)));
  const start = Date.now();
  await tab.goto(`http://127.0.0.1:${port}/page.html`);
  await tab.waitForFunction(() => window.hlodState && window.hlodState.done, null, { timeout: 240000, polling: 500 });
  const state = await tab.evaluate(() => window.hlodState);
  if (state.error) throw new Error(`page: ${state.error}`);
  await tab.screenshot({ path: args.out });
  console.log(`view_cesium: ${state.tilesLoaded} tiles loaded, ${state.selected} selected, ${state.triangles} triangles, ` +
              `${((Date.now() - start) / 1000).toFixed(1)} s; requests outside 127.0.0.1 blocked: ${outside.length}; page errors: ${errors.length}`);

  const a = PNG.sync.read(fs.readFileSync(args.out)), b = PNG.sync.read(fs.readFileSync(args.reference));
  if (a.width !== b.width || a.height !== b.height) throw new Error(`sizes differ: ${a.width}x${a.height} vs ${b.width}x${b.height}`);
  const isModel = (img, i) => Math.max(...[0, 1, 2].map((c) => Math.abs(img.data[i + c] - background[c]))) > 10;
  let inter = 0, union = 0, inA = 0, inB = 0, diff = 0;
  for (let i = 0; i < a.data.length; i += 4) {
    const ma = isModel(a, i), mb = isModel(b, i);
    inA += ma; inB += mb;
    if (ma || mb) union += 1;
    if (ma && mb) {
      inter += 1;
      for (let c = 0; c < 3; ++c) diff += Math.abs(a.data[i + c] - b.data[i + c]);
    }
  }
  const iou = union ? inter / union : 1, colourDiff = inter ? diff / (3 * inter) : 0;
  console.log(`view_cesium: model covers ${inA} px in CesiumJS, ${inB} px in hlod play; IoU ${iou.toFixed(3)} ` +
              `(need >= ${minIou}); mean colour difference ${colourDiff.toFixed(1)}/255 (need <= ${maxColourDiff})`);
  if (inB === 0) console.log('view_cesium: the reference frame shows no model');
  else if (outside.length) console.log(`view_cesium: the page asked for ${outside[0]}`);
  else status = iou >= minIou && colourDiff <= maxColourDiff ? 0 : 1;
} catch (e) {
  console.log(`view_cesium: ${e.message.split('\n')[0]}`);
} finally {
  await browser.close();
  server.close();
}
process.exit(status);
