// The viewer page of `contactmap serve`: HiGlass over the server's own tiles.
//
// It asks the server (same origin) for its tilesets, builds a HiGlass view config from them and
// hands it to `hglib.viewer`:
// - each map (datatype "matrix") is a view: a `heatmap` in the centre, chromosome labels on top and
//   on the left; several maps stand side by side, those of one genome with zoom and location locked;
// - 1D tracks go with the maps of their coordinate system (with every map when none matches):
//   "vector" as a line on top and on the left, "bedlike" (BED domains) as intervals on top and on
//   the left, "2d-rectangle-domains" (BEDPE) as rectangles over the heatmap;
// - the normalisation switch sets the heatmaps' `dataTransform` option, which HiGlass appends to
//   each tile id (`UID.z.x.y.KR`); "default" appends nothing (the server's default: the `weight`
//   column when the map stores one), "None" asks for raw counts.
// `window.hgApi` is HiGlass' API object; `document.body.dataset.ready` is "1" once the tiles in
// view are loaded and drawn (the browser test waits for it), "0" while a change is loading;
// `window.whenTilesLoaded()` resolves when the tiles in view (after a zoom, say) are loaded and drawn.
import { viewer, waitForTilesLoaded } from 'higlass';

const API = `${window.location.origin}/api/v1`;

const message = document.getElementById('message');
const select = document.getElementById('transform');

function say(text, isError = false) {
  message.textContent = text;
  message.className = isError ? 'error' : '';
  message.hidden = !text;
}

async function getJson(url) {
  const response = await fetch(url);
  if (!response.ok) {
    throw new Error(`${url}: HTTP ${response.status} ${await response.text()}`);
  }
  return response.json();
}

/** A view config uid: HiGlass wants short names without dots (they separate the parts of tile ids). */
function uidOf(prefix, i) {
  return `${prefix}${i}`;
}

/** How each 1D datatype is drawn on top and on the left: track types, thickness, options. */
const ONE_D = {
  vector: {
    types: ['horizontal-line', 'vertical-line'],
    size: 40,
    options: { lineStrokeColor: '#1f4e9c' },
  },
  bedlike: {
    types: ['bedlike', 'vertical-bedlike'],
    size: 24,
    options: { fillColor: '#2a7d2e', fillOpacity: 0.6 },
  },
};

/** The 1D and overlay tracks of one map's view. */
function extraTracks(tilesets, viewIndex) {
  const top = [];
  const left = [];
  const center = [];
  tilesets.forEach((ts, i) => {
    const common = { server: API, tilesetUid: ts.uuid };
    const name = ts.name || ts.uuid;
    const oneD = ONE_D[ts.datatype];
    if (oneD) {
      const [topType, leftType] = oneD.types;
      top.push({
        ...common,
        uid: uidOf(`v${viewIndex}-top-${ts.datatype}`, i),
        type: topType,
        height: oneD.size,
        options: { name, labelPosition: ts.datatype === 'vector' ? 'topLeft' : 'hidden', ...oneD.options },
      });
      left.push({
        ...common,
        uid: uidOf(`v${viewIndex}-left-${ts.datatype}`, i),
        type: leftType,
        width: oneD.size,
        options: { name, labelPosition: 'hidden', ...oneD.options },
      });
    } else if (ts.datatype === '2d-rectangle-domains') {
      center.push({
        ...common,
        uid: uidOf(`v${viewIndex}-rect`, i),
        type: '2d-rectangle-domains',
        options: { name, rectangleDomainStrokeColor: '#1b3fd1', rectangleDomainOpacity: 0.8 },
      });
    }
  });
  return { top, left, center };
}

/**
 * The maps (indices) a 1D or overlay track goes with: those of its coordinate system, else those of
 * its chromosome sizes, else all of them.
 */
function mapsOf(track, maps, infos, otherInfos) {
  const all = maps.map((_, i) => i);
  const byCoords = all.filter((i) => track.coordSystem && maps[i].coordSystem === track.coordSystem);
  if (byCoords.length) return byCoords;
  const sizes = otherInfos[track.uuid]?.chromsizes;
  const bySizes = all.filter((i) => sizes && JSON.stringify(infos[i].chromsizes) === JSON.stringify(sizes));
  return bySizes.length ? bySizes : all;
}

/** The view config: one view per map, side by side; those of one genome locked together. */
function buildViewConfig(maps, infos, others, otherInfos, size, transform = 'default') {
  const width = Math.max(1, Math.floor(12 / maps.length));
  const views = maps.map((map, i) => {
    const info = infos[i];
    const lo = info.min_pos?.[0] ?? 0;
    const hi = info.max_pos?.[0] ?? 1;
    const extra = extraTracks(
      others.filter((t) => mapsOf(t, maps, infos, otherInfos).includes(i)),
      i,
    );
    // HiGlass fits the x domain to the heatmap's width and gives y the same scale: on a wide
    // screen, widen x so that the whole genome fits vertically too.
    const heatmapWidth = size.width / maps.length - 30 - extra.left.reduce((s, t) => s + t.width, 0);
    const heatmapHeight = size.height - 30 - extra.top.reduce((s, t) => s + t.height, 0);
    const ratio = Math.max(1, heatmapWidth / Math.max(1, heatmapHeight));
    const xDomain = [(lo + hi) / 2 - ((hi - lo) / 2) * ratio, (lo + hi) / 2 + ((hi - lo) / 2) * ratio];
    const chromInfoPath = `${API}/chrom-sizes/?id=${encodeURIComponent(map.uuid)}`;
    return {
      uid: uidOf('view', i),
      layout: { w: width, h: 12, x: i * width, y: 0, moved: false, static: false },
      initialXDomain: xDomain,
      initialYDomain: [lo, hi],
      tracks: {
        top: [
          {
            uid: uidOf('top-chroms', i),
            type: 'horizontal-chromosome-labels',
            height: 30,
            chromInfoPath,
            options: {},
          },
          ...extra.top,
        ],
        left: [
          {
            uid: uidOf('left-chroms', i),
            type: 'vertical-chromosome-labels',
            width: 30,
            chromInfoPath,
            options: {},
          },
          ...extra.left,
        ],
        center: [
          {
            uid: uidOf('center', i),
            type: 'combined',
            contents: [
              {
                uid: uidOf('heatmap', i),
                type: 'heatmap',
                server: API,
                tilesetUid: map.uuid,
                options: {
                  name: map.name || map.uuid,
                  dataTransform: transform,
                  labelPosition: 'bottomRight',
                  colorbarPosition: 'topRight',
                },
              },
              ...extra.center,
            ],
          },
        ],
        right: [],
        bottom: [],
        whole: [],
        gallery: [],
      },
    };
  });

  const viewConfig = { editable: false, zoomFixed: false, trackSourceServers: [API], views };
  // Maps of the same genome (equal chromsizes) are locked together: zoom and location. Each view's
  // entry is [centre x, centre y, zoom scale]; equal entries lock the views one to one.
  const groups = new Map();
  views.forEach((view, i) => {
    const key = JSON.stringify(infos[i].chromsizes || infos[i].max_pos || i);
    groups.set(key, [...(groups.get(key) || []), i]);
  });
  for (const kind of ['zoomLocks', 'locationLocks']) {
    viewConfig[kind] = { locksByViewUid: {}, locksDict: {} };
  }
  [...groups.values()]
    .filter((members) => members.length > 1)
    .forEach((members, g) => {
      const lo = infos[members[0]].min_pos?.[0] ?? 0;
      const hi = infos[members[0]].max_pos?.[0] ?? 1;
      for (const kind of ['zoomLocks', 'locationLocks']) {
        const lockUid = `${kind}${g}`;
        const lock = { uid: lockUid };
        for (const i of members) {
          lock[views[i].uid] = [(lo + hi) / 2, (lo + hi) / 2, 1];
          viewConfig[kind].locksByViewUid[views[i].uid] = lockUid;
        }
        viewConfig[kind].locksDict[lockUid] = lock;
      }
    });
  return viewConfig;
}

/** Resolve once the tiles in view are loaded, then after two frames (drawn). */
function tilesLoaded(api) {
  return new Promise((resolve) => {
    // Tracks are created after the first render: wait for every heatmap's track object first.
    const poll = () => {
      const hgc = api.getComponent();
      const config = api.getViewConfig();
      const heatmaps = [];
      for (const view of config.views) {
        for (const center of view.tracks.center || []) {
          for (const t of center.contents || [center]) {
            if (t.type === 'heatmap') heatmaps.push([view.uid, t.uid]);
          }
        }
      }
      const ready = heatmaps.every(([v, t]) => {
        const track = api.getTrackObject(v, t);
        return track && track.tilesetInfo && Object.keys(track.fetchedTiles || {}).length > 0;
      });
      if (!ready) {
        setTimeout(poll, 50);
        return;
      }
      waitForTilesLoaded(hgc, () => {
        requestAnimationFrame(() => requestAnimationFrame(resolve));
      });
    };
    poll();
  });
}

async function main() {
  const list = await getJson(`${API}/tilesets/`);
  const tilesets = list.results || [];
  const maps = tilesets.filter((t) => t.datatype === 'matrix');
  if (!maps.length) {
    say('The server has no contact map to show (datatype "matrix").', true);
    return;
  }
  const others = tilesets.filter((t) => t.datatype !== 'matrix');
  const query = tilesets.map((t) => `d=${encodeURIComponent(t.uuid)}`).join('&');
  const infoByUid = await getJson(`${API}/tileset_info/?${query}`);
  const infos = maps.map((m) => infoByUid[m.uuid] || {});
  for (const [i, info] of infos.entries()) {
    if (info.error) throw new Error(`${maps[i].uuid}: ${info.error}`);
  }

  document.getElementById('files').textContent = tilesets.map((t) => t.name || t.uuid).join(' · ');
  document.title = `contactmap serve: ${maps.map((m) => m.name || m.uuid).join(', ')}`;

  // The switch lists the normalisations every map stores (tileset_info's `transforms`).
  const transforms = new Map();
  for (const info of infos) {
    for (const t of info.transforms || []) {
      if (infos.every((other) => (other.transforms || []).some((o) => o.value === t.value))) {
        transforms.set(t.value, t.name);
      }
    }
  }
  for (const [value, name] of transforms) {
    const option = document.createElement('option');
    option.value = value;
    option.textContent = name === value ? name : `${name} (${value})`;
    select.append(option);
  }

  say('');
  const element = document.getElementById('viewer');
  const { width, height } = element.getBoundingClientRect();
  const viewConfig = buildViewConfig(maps, infos, others, infoByUid, { width, height });
  const api = await viewer(element, viewConfig, { bounded: true, editable: false });
  window.hgApi = api;
  // For the browser test: a promise that resolves once the tiles in view are loaded and drawn.
  window.whenTilesLoaded = () => tilesLoaded(api);
  await tilesLoaded(api);
  document.body.dataset.ready = '1';

  select.disabled = false;
  select.addEventListener('change', async () => {
    document.body.dataset.ready = '0';
    select.disabled = true;
    // The current config keeps where the user is (initial domains = the views' current ones).
    const config = api.getViewConfig();
    for (const view of config.views) {
      for (const center of view.tracks.center || []) {
        for (const t of center.contents || [center]) {
          if (t.type === 'heatmap') t.options = { ...t.options, dataTransform: select.value };
        }
      }
    }
    await api.setViewConfig(config);
    await tilesLoaded(api);
    select.disabled = false;
    document.body.dataset.ready = '1';
  });
}

main().catch((error) => {
  console.error(error);
  say(`Could not load the viewer: ${error.message}`, true);
  document.body.dataset.ready = 'error';
});
