// The side panels: what the run lacks, the layer toggles, the colouring, the section and cut,
// the vertical exaggeration, the walk and the screenshot, and the selection's attributes.

import { drawLegend, modes } from './colours.js';

const $ = (id) => document.getElementById(id);

/** Lists the run's problems (missing or stale artifacts). */
export function showProblems(problems) {
  if (problems.length === 0) return;
  $('problems').hidden = false;
  for (const p of problems) {
    const li = document.createElement('li');
    li.textContent = `${p.file}: ${p.message}`;
    if (p.affects.length > 0) li.title = `leaves empty: ${p.affects.join(', ')}`;
    $('problem-list').append(li);
  }
}

/** One checkbox per layer: [{id, label, visible, set(visible)}]. */
export function layerToggles(layers, viewer) {
  const box = $('layers');
  for (const layer of layers) {
    const label = document.createElement('label');
    const input = document.createElement('input');
    input.type = 'checkbox';
    input.id = `layer-${layer.id}`;
    input.checked = layer.visible;
    input.disabled = layer.missing === true;
    input.addEventListener('change', () => {
      layer.set(input.checked);
      viewer.changed();
    });
    label.append(input, ` ${layer.label}`);
    if (layer.missing) label.title = 'not in this run';
    box.append(label);
  }
}

/** The colouring select and the legend. */
export function colourControls(data, network, viewer) {
  const select = $('colour-mode');
  for (const [value, label] of modes(data)) select.add(new Option(label, value));
  const apply = () => drawLegend($('network-legend'), network.colour(select.value));
  select.addEventListener('change', apply);
  apply();
  $('network-on-top').addEventListener('change', (e) => network.setOnTop(e.target.checked));
  const legend = $('network-legend');
  return (visible) => {
    legend.style.display = visible ? '' : 'none';
    viewer.changed();
  };
}

/** The horizontal section, the terrain cut and the vertical exaggeration. */
export function sectionControls(viewer) {
  const d = viewer.domain;
  const section = $('section');
  section.min = d.min[2];
  section.max = d.max[2];
  section.value = d.max[2];
  const showSection = () => {
    const z = Number(section.value);
    $('section-value').textContent = z >= d.max[2] ? 'everything' : `z ≤ ${z.toFixed(1)} m`;
    viewer.setSection(z);
  };
  section.addEventListener('input', showSection);
  showSection();
  const cut = () => viewer.setCut($('cut-axis').value, Number($('cut').value));
  $('cut-axis').addEventListener('change', cut);
  $('cut').addEventListener('input', cut);
  const exaggeration = $('exaggeration');
  exaggeration.addEventListener('input', () => {
    $('exaggeration-value').textContent = `${exaggeration.value}×`;
    viewer.setExaggeration(Number(exaggeration.value));
  });
}

/** The walk's route list, speed and button, and the screenshot button. */
export function walkControls(data, walk, viewer, run) {
  const select = $('walk-route');
  const routes = data.skeleton?.routes ?? [];
  routes.forEach((r, i) => select.add(new Option(`${r.sink} → ${r.spring}`, `${i}`)));
  const button = $('walk');
  button.disabled = routes.length === 0;
  const speed = $('walk-speed');
  const showSpeed = () => {
    walk.speed = Number(speed.value);
    $('walk-speed-value').textContent = `${speed.value} m/s`;
  };
  speed.addEventListener('input', showSpeed);
  showSpeed();
  button.addEventListener('click', () => {
    if (walk.inside) walk.stop();
    else walk.start(Number(select.value));
    button.textContent = walk.inside ? 'stop' : 'walk';
  });
  viewer.onFrame(() => {
    button.textContent = walk.inside ? 'stop' : 'walk';
  });
  $('screenshot').addEventListener('click', () => {
    const url = viewer.screenshot();
    window.karstView.lastScreenshot = url;
    const a = document.createElement('a');
    a.href = url;
    a.download = `karstgen-${run}.png`;
    a.click();
  });
}

const fmt = (v, unit = '') => (typeof v === 'number' ? `${Math.abs(v) >= 100 ? v.toFixed(1) : v.toPrecision(3)}${unit}` : '–');

function rows(list) {
  const t = document.createElement('table');
  for (const [k, v] of list) {
    const tr = t.insertRow();
    tr.insertCell().textContent = k;
    tr.insertCell().textContent = v;
  }
  return t;
}

/** Writes the picked segment's or node's attributes into the selection panel. */
export function showSelection(data, network, pick, route) {
  const info = $('info');
  info.replaceChildren();
  if (!pick) {
    info.textContent = 'click a conduit or a node';
    return;
  }
  const sk = data.skeleton;
  const h = data.hydro;
  const title = document.createElement('div');
  const spring = route.length > 1 && network.springs.has(route[route.length - 1])
    ? sk.nodes[route[route.length - 1]].keypoint ?? `node ${route[route.length - 1]}` : null;
  let list;
  if (pick.segment !== undefined) {
    const s = network.segments[pick.segment];
    const c = sk.conduits[s.conduit];
    const w = h?.conduits[s.conduit];
    const radius = w?.radius ?? c.radius;
    let length = 0;
    for (let i = 0; i + 1 < c.nodes.length; i += 1) {
      const [p, q] = [sk.nodes[c.nodes[i]].position, sk.nodes[c.nodes[i + 1]].position];
      length += Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
    }
    title.id = 'info-title';
    title.textContent = `Conduit ${s.conduit}, segment ${s.index + 1} of ${c.nodes.length - 1}`;
    list = [
      ['type', c.types[s.index]],
      ['radius', `${fmt(radius[s.index], ' m')} – ${fmt(radius[s.index + 1], ' m')}`],
      ['length', fmt(length, ' m')],
      ['nodes', `${s.a} → ${s.b}`],
      ['phase', `${c.phase ?? 0}`],
      ['zone', `${sk.nodes[s.a].zone} / ${sk.nodes[s.b].zone}`],
    ];
    if (w) {
      list.push(['flow', `${fmt(w.segment_flow[s.index])} units, ${fmt(w.discharge[s.index], ' m³/s')}`],
        ['water', w.water[s.index]], ['water depth', fmt(w.depth[s.index], ' m')]);
    }
    if (data.ensemble) {
      list.push(['ensemble probability', `${data.ensemble.segments[s.conduit][s.index].toFixed(2)} of ${data.ensemble.realizations}`]);
    }
    if (c.keypoints?.length) list.push(['ends at', c.keypoints.join(', ')]);
  } else {
    const n = sk.nodes[pick.node];
    title.id = 'info-title';
    title.textContent = `Node ${pick.node}${n.keypoint ? ` (${n.keypoint})` : ''}`;
    list = [
      ['position', n.position.map((v) => v.toFixed(1)).join(', ')],
      ['zone', n.zone],
      ['conduits', `${new Set(network.adjacency[pick.node].map((a) => network.segments[a.segment].conduit)).size}`],
    ];
    if (h) list.push(['role', h.nodes[pick.node].role], ['inflow', fmt(h.nodes[pick.node].inflow, ' units')]);
  }
  list.push(['route', spring ? `to ${spring}, ${route.length - 1} segments (yellow)` : 'reaches no spring']);
  info.append(title, rows(list));
}
