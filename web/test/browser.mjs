// The viewer page in a real browser (headless Chromium through playwright-core): opens the page of
// a running `contactmap serve`, waits for the heatmap, reads the rendered pixels back and drives it.
//
//   node web/test/browser.mjs URL [--chromium PATH] [--track bedlike] [--screenshot FILE]
//
// Checks: the page loads and every tile request is answered 200; the heatmap is drawn and darker
// along the diagonal than off it; a BED domain track (--track bedlike) is drawn; the mouse wheel over
// the heatmap zooms in and the tiles of deeper zoom levels are requested and served; with two maps,
// the second view follows the first (locked zoom and location); the normalisation switch asks for
// tiles with the chosen transform. Prints one line per check and `N passed, N failed`; exit 1 when
// one failed, 2 when the browser or the page could not be started.
import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';

const args = process.argv.slice(2);
const opt = (name) => {
  const i = args.indexOf(name);
  return i >= 0 ? args[i + 1] : undefined;
};
const url = args.find((a, i) => !a.startsWith('--') && (i === 0 || !args[i - 1].startsWith('--')));
if (!url) {
  console.error('usage: node web/test/browser.mjs URL [--chromium PATH] [--track bedlike] [--screenshot FILE]');
  process.exit(2);
}
const executablePath = opt('--chromium') || process.env.CHROMIUM || '/usr/bin/chromium';
const expectTrack = opt('--track');
const screenshotPath = opt('--screenshot');
const TIMEOUT = Number(process.env.BROWSER_TEST_TIMEOUT_MS || 60000);

const T0 = Date.now();
let passed = 0;
let failed = 0;
function check(ok, what, detail = '') {
  if (ok) passed += 1;
  else failed += 1;
  const t = ((Date.now() - T0) / 1000).toFixed(1).padStart(5);
  console.log(`${t}s ${ok ? 'ok    ' : 'FAILED'} ${what}${detail ? `: ${detail}` : ''}`);
  return ok;
}

/** Tile ids of a /api/v1/tiles/ request. */
function tileIds(requestUrl) {
  return new URL(requestUrl).searchParams.getAll('d');
}

const browser = await chromium
  .launch({
    executablePath,
    headless: true,
    // pixi.js draws with WebGL: on a machine without a GPU that is SwiftShader. No sandbox as
    // root; no background connections (the test machines reach no network).
    args: [
      '--use-angle=swiftshader',
      '--enable-unsafe-swiftshader',
      '--no-sandbox',
      '--disable-quic',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
      '--no-first-run',
    ],
  })
  .catch((e) => {
    console.error(`browser test: could not start ${executablePath}: ${e.message}`);
    process.exit(2);
  });

const responses = [];
const pageErrors = [];
let exitCode = 0;
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 800 }, deviceScaleFactor: 1 });
  page.on('pageerror', (e) => pageErrors.push(String(e)));
  page.on('console', (m) => {
    if (m.type() === 'error') pageErrors.push(`console: ${m.text()}`);
  });
  page.on('response', (r) => {
    if (r.url().includes('/api/v1/tiles/')) responses.push({ url: r.url(), status: r.status() });
  });

  const started = Date.now();
  await page.goto(url, { waitUntil: 'load', timeout: TIMEOUT });
  const ready = await page
    .waitForFunction(() => ['1', 'error'].includes(document.body.dataset.ready), null, { timeout: TIMEOUT })
    .then(() => page.evaluate(() => document.body.dataset.ready))
    .catch(() => 'timeout');
  if (!check(ready === '1', 'page loaded and first tiles drawn', `${ready} after ${Date.now() - started} ms`)) {
    console.log(await page.evaluate(() => document.getElementById('message')?.textContent));
    throw new Error('page not ready');
  }

  // Where the tracks are on the page, and the heatmap's scales (genome position -> pixel).
  const layout = () =>
    page.evaluate(() => {
      const api = window.hgApi;
      const canvas = document.querySelector('#viewer canvas');
      const c = canvas.getBoundingClientRect();
      const config = api.getViewConfig();
      const views = config.views.map((view) => {
        const tracks = [];
        for (const pos of ['top', 'left', 'center']) {
          for (const t of view.tracks[pos] || []) {
            for (const inner of t.contents || [t]) {
              const obj = api.getTrackObject(view.uid, inner.uid);
              if (!obj) continue;
              const track = obj.originalTrack || obj;
              tracks.push({
                uid: inner.uid,
                type: inner.type,
                pos,
                x: c.left + obj.position[0],
                y: c.top + obj.position[1],
                w: obj.dimensions[0],
                h: obj.dimensions[1],
                xDomain: track._xScale ? track._xScale.domain() : null,
                xRange: track._xScale ? track._xScale.range() : null,
                yDomain: track._yScale ? track._yScale.domain() : null,
                yRange: track._yScale ? track._yScale.range() : null,
              });
            }
          }
        }
        return { uid: view.uid, tracks, location: api.getLocation(view.uid) };
      });
      const select = document.getElementById('transform');
      return { views, transforms: [...select.options].map((o) => o.value) };
    });

  const shot = async () => PNG.sync.read(await page.screenshot({ type: 'png' }));
  const darkness = (png, x, y) => {
    const xi = Math.round(x);
    const yi = Math.round(y);
    if (xi < 0 || yi < 0 || xi >= png.width || yi >= png.height) return null;
    const i = (yi * png.width + xi) * 4;
    return 255 - (0.299 * png.data[i] + 0.587 * png.data[i + 1] + 0.114 * png.data[i + 2]);
  };
  const lin = (domain, range, v) => range[0] + ((v - domain[0]) / (domain[1] - domain[0])) * (range[1] - range[0]);

  let info = await layout();
  const heatmap = info.views[0].tracks.find((t) => t.type === 'heatmap');
  check(Boolean(heatmap), 'heatmap track created', heatmap ? `${heatmap.w}x${heatmap.h} px` : 'none');

  // Pixels along the diagonal against pixels a quarter of the view away from it.
  let png = await shot();
  {
    const [g0, g1] = heatmap.xDomain;
    const diag = [];
    const off = [];
    for (let k = 1; k < 40; k += 1) {
      const g = g0 + ((g1 - g0) * k) / 40;
      const x = heatmap.x + lin(heatmap.xDomain, heatmap.xRange, g);
      const yd = heatmap.y + lin(heatmap.yDomain, heatmap.yRange, g);
      const d = darkness(png, x, yd);
      if (d !== null && yd > heatmap.y && yd < heatmap.y + heatmap.h) diag.push(d);
      for (const shift of [0.25, -0.25]) {
        const yo = heatmap.y + lin(heatmap.yDomain, heatmap.yRange, g + (g1 - g0) * shift);
        const o = darkness(png, x, yo);
        if (o !== null && yo > heatmap.y && yo < heatmap.y + heatmap.h) off.push(o);
      }
    }
    const mean = (a) => a.reduce((s, v) => s + v, 0) / Math.max(1, a.length);
    const nonBlank = diag.filter((d) => d > 10).length;
    check(nonBlank > diag.length / 2, 'heatmap drawn (diagonal pixels not blank)', `${nonBlank}/${diag.length}`);
    check(
      mean(diag) > mean(off) + 20,
      'diagonal darker than off it',
      `mean darkness ${mean(diag).toFixed(1)} on the diagonal, ${mean(off).toFixed(1)} a quarter off (${diag.length} / ${off.length} pixels)`,
    );
  }

  if (expectTrack) {
    const tracks = info.views[0].tracks.filter((t) => t.type.endsWith(expectTrack));
    check(tracks.length > 0, `${expectTrack} track created`, tracks.map((t) => `${t.pos} ${t.w}x${t.h}`).join(', '));
    for (const t of tracks) {
      // Count coloured pixels (the track's green) inside the track's box.
      let coloured = 0;
      let total = 0;
      for (let y = Math.ceil(t.y); y < t.y + t.h; y += 1) {
        for (let x = Math.ceil(t.x); x < t.x + t.w; x += 1) {
          const i = (y * png.width + x) * 4;
          const [r, g, b] = [png.data[i], png.data[i + 1], png.data[i + 2]];
          total += 1;
          if (g > r + 20 && g > b + 20) coloured += 1;
        }
      }
      check(coloured > total * 0.05, `${t.pos} ${expectTrack} track drawn`, `${coloured} of ${total} pixels coloured`);
    }
  }

  const firstTiles = responses.slice();
  check(
    firstTiles.length > 0 && firstTiles.every((r) => r.status === 200),
    'first tile requests served',
    `${firstTiles.length} requests, statuses ${[...new Set(firstTiles.map((r) => r.status))].join(',')}`,
  );
  const zoomOf = (id) => Number(id.split('.')[1]);
  const heatmapUid = await page.evaluate(() => window.hgApi.getViewConfig().views[0].tracks.center[0].contents[0].tilesetUid);
  const mapZooms = (rs) =>
    rs.flatMap((r) => tileIds(r.url)).filter((id) => id.startsWith(`${heatmapUid}.`)).map(zoomOf);
  const firstZoom = Math.max(...mapZooms(firstTiles));

  // Zoom in with the mouse wheel over the heatmap's centre.
  const before = responses.length;
  const location0 = info.views[0].location;
  await page.mouse.move(heatmap.x + heatmap.w / 2, heatmap.y + heatmap.h / 2);
  // d3-zoom: each wheel event scales by 2^(-deltaY * 0.002); three of -600 zoom in about 12x.
  for (let i = 0; i < 3; i += 1) {
    await page.mouse.wheel(0, -600);
    await page.waitForTimeout(200);
  }
  await page.evaluate(() => window.whenTilesLoaded());
  const zoomed = responses.slice(before);
  const zooms = mapZooms(zoomed);
  info = await layout();
  const location1 = info.views[0].location;
  const width0 = location0.xDomain[1] - location0.xDomain[0];
  const width1 = location1.xDomain[1] - location1.xDomain[0];
  check(width1 < width0 / 2, 'mouse wheel zoomed in', `x domain ${(width0 / 1e6).toFixed(1)} Mb -> ${(width1 / 1e6).toFixed(2)} Mb`);
  check(
    zooms.length > 0 && Math.max(...zooms) > firstZoom && zoomed.every((r) => r.status === 200),
    'new tiles requested and served after zooming',
    `${zoomed.length} requests (${zooms.length} map tiles), zoom levels ${firstZoom} -> ${zooms.length ? Math.max(...zooms) : 'none'}, statuses ${[...new Set(zoomed.map((r) => r.status))].join(',')}`,
  );

  if (info.views.length > 1) {
    const other = info.views[1].location;
    const w2 = other.xDomain[1] - other.xDomain[0];
    check(
      Math.abs(w2 - width1) / width1 < 0.01 && Math.abs(other.xDomain[0] - location1.xDomain[0]) < width1 * 0.01,
      'second view follows the first (locked zoom and location)',
      `view 1 x ${location1.xDomain.map((v) => Math.round(v)).join('-')}, view 2 x ${other.xDomain.map((v) => Math.round(v)).join('-')}`,
    );
  }

  // The normalisation switch: the last option (a stored transform, else "None" = raw counts).
  const choice = info.transforms[info.transforms.length - 1];
  const beforeSwitch = responses.length;
  await page.waitForFunction(() => !document.getElementById('transform').disabled, null, { timeout: TIMEOUT });
  await page.selectOption('#transform', choice);
  const switched = await page
    .waitForFunction(() => document.body.dataset.ready === '1' && !document.getElementById('transform').disabled, null, {
      timeout: TIMEOUT,
    })
    .then(() => true)
    .catch(() => false);
  const after = responses.slice(beforeSwitch);
  const withSuffix = after.flatMap((r) => tileIds(r.url)).filter((id) => id.startsWith(`${heatmapUid}.`) && id.endsWith(`.${choice}`));
  info = await layout();
  const location2 = info.views[0].location;
  check(
    switched && withSuffix.length > 0 && after.every((r) => r.status === 200),
    `normalisation switch (${info.transforms.join(' / ')}) -> ${choice}`,
    `${withSuffix.length} tiles asked as ${withSuffix[0] || '(none)'}, statuses ${[...new Set(after.map((r) => r.status))].join(',')}`,
  );
  check(
    Math.abs(location2.xDomain[0] - location1.xDomain[0]) < width1 * 0.01,
    'the switch keeps the view where it was',
    `${location1.xDomain.map((v) => Math.round(v)).join('-')} -> ${location2.xDomain.map((v) => Math.round(v)).join('-')}`,
  );

  if (screenshotPath) {
    // For the docs: the default normalisation, the first chromosome filling the view.
    await page.selectOption('#transform', 'default');
    await page.waitForFunction(() => document.body.dataset.ready === '1', null, { timeout: TIMEOUT });
    await page.evaluate(async (uid) => {
      const sizes = await (await fetch(`/api/v1/chrom-sizes/?id=${encodeURIComponent(uid)}`)).text();
      const length = Number(sizes.split('\n')[0].split('\t')[1]);
      window.hgApi.zoomTo('view0', 0, length, 0, length, 0);
      await new Promise((resolve) => setTimeout(resolve, 500));
      await window.whenTilesLoaded();
    }, heatmapUid);
    await page.screenshot({ path: screenshotPath, type: 'png' });
    console.log(`screenshot: ${screenshotPath}`);
  }
} catch (e) {
  if (String(e.message) !== 'page not ready') {
    check(false, 'browser test ran to the end', e.stack || String(e));
  }
} finally {
  for (const e of pageErrors.slice(0, 10)) console.log(`page: ${e}`);
  await browser.close();
}
console.log(`browser: ${passed} passed, ${failed} failed`);
exitCode = failed ? 1 : 0;
process.exit(exitCode);
