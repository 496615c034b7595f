// Entry point: reads data/run.json, builds the view and the panels, and exposes
// `window.karstView` (state and a few probes the browser tests and the benchmark read).

import { Viewer } from './viewer.js';
import { Surfaces } from './meshes.js';
import { Network } from './network.js';
import { SurfaceStreams } from './streams.js';
import { drawLegend } from './colours.js';
import { buildSurfaces } from './surfaces.js';
import { KeyPoints } from './keypoints.js';
import { overlays } from './overlay.js';
import { Walk } from './walk.js';
import { showMetrics } from './metrics.js';
import {
  colourControls, layerToggles, sectionControls, showProblems, showSelection, walkControls,
} from './panels.js';

const FORMAT = 'karstgen-view';
const VERSION = 2;
const status = document.getElementById('status');
window.karstView = { ready: false, settled: () => false };

function fail(message) {
  status.textContent = message;
  status.classList.add('error');
}

async function loadData() {
  const response = await fetch('data/run.json');
  if (!response.ok) throw new Error(`data/run.json: ${response.status} ${response.statusText}`);
  const data = await response.json();
  if (data.format !== FORMAT || data.version !== VERSION) {
    throw new Error(`data/run.json is ${data.format} version ${data.version}, this page reads ${FORMAT} ${VERSION}: write the view again`);
  }
  return data;
}

async function main() {
  const data = await loadData();
  performance.mark('karst:data');
  document.title = `${data.run} · karstgen viewer`;
  document.getElementById('title').textContent = `karstgen · ${data.run}`;
  showProblems(data.problems);
  if (!data.domain) {
    fail('This run has nothing to show yet: see "Missing from this run".');
    return;
  }
  const viewer = new Viewer(document.getElementById('canvas'), data.domain);
  const surfaces = new Surfaces(data.meshes, viewer);
  const network = data.skeleton ? new Network(data, viewer) : null;
  const streams = data.streams?.segments.length ? new SurfaceStreams(data, viewer) : null;
  const streamLegend = document.getElementById('stream-legend');
  if (streams) drawLegend(streamLegend, streams.legend());
  document.getElementById('network-on-top').addEventListener('change', (e) => streams?.setOnTop(e.target.checked));
  const keypoints = new KeyPoints(data, viewer, document.getElementById('labels'));
  const geology = buildSurfaces(data, viewer);
  overlays(viewer);

  const meshLayer = (name, label) => {
    const s = surfaces.byName(name);
    return { id: name, label, visible: true, missing: !s, set: (v) => { if (s) s.group.visible = v; } };
  };
  const kinds = (kind) => geology.filter((g) => g.kind === kind);
  const geologyLayer = (id, kind, label) => ({
    id, label, visible: true, missing: kinds(kind).length === 0,
    set: (v) => kinds(kind).forEach((g) => { g.mesh.visible = v; }),
  });
  const legendVisible = network ? colourControls(data, network, viewer) : () => {};
  const layers = [
    meshLayer('terrain', 'terrain (translucent)'),
    meshLayer('cave', 'cave'),
    meshLayer('water', 'water'),
    { id: 'network', label: 'network (lines)', visible: true, missing: !network,
      set: (v) => { if (network) network.lines.visible = v; legendVisible(v); } },
    { id: 'streams', label: 'surface streams (lines, water type)', visible: true, missing: !streams,
      set: (v) => { streams?.setVisible(v); streamLegend.style.display = v ? '' : 'none'; } },
    { id: 'keypoints', label: 'key points and labels', visible: true, missing: data.keypoints.length === 0,
      set: (v) => keypoints.setVisible(v) },
    geologyLayer('water-tables', 'water table', 'water tables'),
    geologyLayer('horizons', 'horizon', 'horizons'),
  ];
  layerToggles(layers, viewer);
  sectionControls(viewer);
  // The walk shows the cave, the water and the network alone; the layers come back after it.
  const outside = layers.filter((l) => ['terrain', 'streams', 'water-tables', 'horizons', 'keypoints'].includes(l.id));
  const walk = new Walk(data, viewer, (walking) => {
    for (const l of outside) l.set(!walking && document.getElementById(`layer-${l.id}`).checked);
  });
  walkControls(data, walk, viewer, data.run);
  showMetrics(document.getElementById('metrics-body'), data);
  if (network) pickOnClick(data, viewer, network, surfaces);

  Object.assign(window.karstView, {
    data,
    viewer,
    settled: () => surfaces.settled(),
    walking: () => walk.walking,
    standAt: (from, to) => walk.standAt(from, to),
    cameraPosition: () => viewer.camera.position.toArray(),
    projectNodes: () => (data.skeleton?.nodes ?? []).map((n) => viewer.project(n.position)),
    streams: () => streams?.probe() ?? [],
    pixelsAt: (points) => pixelsAt(viewer, points),
    triangles: () => Object.fromEntries(surfaces.surfaces.map((s) => [s.name, s.triangles()])),
    sample: (columns = 160, rows = 100) => sample(viewer, columns, rows),
  });
  performance.mark('karst:built');
  status.textContent = 'loading meshes…';
  await surfaces.start();
  performance.mark('karst:meshes');
  status.textContent = '';
  await viewer.start();
  performance.mark('karst:drawn');
  const viewpoint = standingPoint(location.hash);
  if (viewpoint) walk.standAt(viewpoint.from, viewpoint.to);
  window.karstView.readyAt = performance.now();
  window.karstView.ready = true;
}

/** `#from=x,y,z&to=x,y,z` of the page's address, or null when absent or malformed. */
function standingPoint(hash) {
  const params = new URLSearchParams(hash.replace(/^#/, ''));
  const point = (key) => {
    const v = (params.get(key) ?? '').split(',').map(Number);
    return v.length === 3 && v.every(Number.isFinite) ? v : null;
  };
  const [from, to] = [point('from'), point('to')];
  return from && to ? { from, to } : null;
}

/** A click (not a drag) on the canvas picks a node or segment and shows its route. */
function pickOnClick(data, viewer, network, surfaces) {
  let down = null;
  viewer.canvas.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
  viewer.canvas.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    const rect = viewer.canvas.getBoundingClientRect();
    const pick = network.pick(e.clientX - rect.left, e.clientY - rect.top, surfaces.meshes('cave'));
    let route = [];
    if (pick?.node !== undefined) route = network.routeToSpring(pick.node);
    if (pick?.segment !== undefined) {
      const s = network.segments[pick.segment];
      const forward = data.hydro?.conduits[s.conduit].downstream[s.index] ?? true;
      route = [forward ? s.a : s.b, ...network.routeToSpring(forward ? s.b : s.a)];
    }
    network.show(pick?.segment ?? null, route);
    showSelection(data, network, pick, route);
    window.karstView.selection = pick;
  });
}

/** The picture at canvas points (CSS pixels), RGB, drawn now. */
function pixelsAt(viewer, points) {
  viewer.draw();
  const gl = viewer.renderer.getContext();
  const [w, h] = [gl.drawingBufferWidth, gl.drawingBufferHeight];
  const scale = w / viewer.canvas.clientWidth;
  const pixel = new Uint8Array(4);
  return points.map(({ x, y }) => {
    gl.readPixels(Math.floor(x * scale), h - 1 - Math.floor(y * scale), 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    return [pixel[0], pixel[1], pixel[2]];
  });
}

/** The picture on a grid of columns × rows points, RGB, drawn now. */
function sample(viewer, columns, rows) {
  viewer.draw();
  const gl = viewer.renderer.getContext();
  const [w, h] = [gl.drawingBufferWidth, gl.drawingBufferHeight];
  const pixels = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
  const out = [];
  for (let j = 0; j < rows; j += 1) {
    for (let i = 0; i < columns; i += 1) {
      const x = Math.floor((i + 0.5) * w / columns);
      const y = h - 1 - Math.floor((j + 0.5) * h / rows);
      const k = (y * w + x) * 4;
      out.push([pixels[k], pixels[k + 1], pixels[k + 2]]);
    }
  }
  return out;
}

main().catch((e) => {
  fail(`The view cannot start: ${e.message}`);
  console.error(e);
});
