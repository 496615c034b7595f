// Colouring of the network: one colour per segment end, by conduit type, water type, flow,
// phase, zone, elevation or ensemble probability, and the legend that explains it.

import * as THREE from 'three';

const CONDUIT_TYPES = {
  epikarst: '#8c564b', tube: '#1f77b4', canyon: '#d62728', keyhole: '#9467bd',
  passage: '#2ca02c', bed: '#ff7f0e', chamber: '#e377c2',
};
// Emilien et al. 2015's running-water classes, then still and no water.
export const WATER_TYPES = {
  stream: '#9ecae1', river: '#3182bd', rapid: '#08519c', cascade: '#74c476', horsetail: '#31a354',
  block: '#006d2c', ribbon: '#fdae6b', plunge: '#e6550d', ledge: '#a63603', cataract: '#7f2704',
  sump: '#6a51a3', pool: '#9e9ac8', dry: '#bdbdbd',
};
const ZONES = { vadose: '#e8a33d', phreatic: '#2b6cb0' };
const PHASES = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf'];
const DRY = '#bdbdbd';

/** A ramp from dark blue through teal and yellow (viridis-like), t in [0, 1]. */
function ramp(t) {
  const stops = [[0.27, 0.0, 0.33], [0.23, 0.32, 0.55], [0.13, 0.57, 0.55], [0.37, 0.79, 0.38], [0.99, 0.91, 0.14]];
  const x = Math.min(Math.max(t, 0), 1) * (stops.length - 1);
  const i = Math.min(Math.floor(x), stops.length - 2);
  const f = x - i;
  return new THREE.Color(...[0, 1, 2].map((k) => stops[i][k] * (1 - f) + stops[i + 1][k] * f));
}

const rampCss = () => `linear-gradient(to right, ${[0, 0.25, 0.5, 0.75, 1].map((t) => `#${ramp(t).getHexString()}`).join(', ')})`;

/** The colouring modes this run supports: [value, label]. */
export function modes(data) {
  const m = [['type', 'conduit type']];
  if (data.hydro) m.push(['water', 'water type (Emilien 2015)'], ['flow', 'flow (log scale)']);
  m.push(['phase', 'phase'], ['zone', 'zone (vadose / phreatic)'], ['elevation', 'elevation']);
  if (data.ensemble) m.push(['probability', `ensemble probability (${data.ensemble.realizations} realizations)`]);
  return m;
}

/**
 * Colours of the two ends of every segment, and the legend, for `mode`. `segments` lists
 * {conduit, index, a, b} in drawing order.
 */
export function colouring(mode, data, segments) {
  const sk = data.skeleton;
  const colours = new Float32Array(segments.length * 6);
  const put = (i, end, c) => colours.set([c.r, c.g, c.b], i * 6 + end * 3);
  const used = new Set();
  const category = (table, key) => {
    used.add(key);
    return new THREE.Color(table[key] ?? DRY);
  };
  let legend;
  if (mode === 'elevation' || mode === 'flow' || mode === 'probability') {
    const value = {
      elevation: (s, end) => sk.nodes[end ? s.b : s.a].position[2],
      flow: (s) => data.hydro.conduits[s.conduit].segment_flow[s.index],
      probability: (s) => data.ensemble.segments[s.conduit][s.index],
    }[mode];
    const values = segments.flatMap((s) => [value(s, 0), value(s, 1)]).filter((v) => mode !== 'flow' || v > 0);
    let lo = mode === 'probability' ? 0 : Math.min(...values);
    let hi = mode === 'probability' ? 1 : Math.max(...values);
    if (!Number.isFinite(lo)) { lo = 0; hi = 1; }
    const scale = mode === 'flow' ? (v) => (Math.log(v) - Math.log(lo)) / ((Math.log(hi) - Math.log(lo)) || 1)
      : (v) => (v - lo) / ((hi - lo) || 1);
    segments.forEach((s, i) => {
      for (const end of [0, 1]) {
        const v = value(s, end);
        put(i, end, mode === 'flow' && !(v > 0) ? new THREE.Color(DRY) : ramp(scale(v)));
      }
    });
    const titles = {
      flow: 'flow (network units, log scale; grey: dry)',
      elevation: 'elevation (m)',
      probability: 'fraction of realizations with a conduit there',
    };
    legend = { title: titles[mode], ramp: rampCss(), lo, hi };
  } else {
    const table = { type: CONDUIT_TYPES, water: WATER_TYPES, zone: ZONES }[mode];
    segments.forEach((s, i) => {
      const c = sk.conduits[s.conduit];
      for (const end of [0, 1]) {
        let colour;
        if (mode === 'type') colour = category(CONDUIT_TYPES, c.types[s.index]);
        else if (mode === 'water') colour = category(WATER_TYPES, data.hydro.conduits[s.conduit].water[s.index]);
        else if (mode === 'zone') colour = category(ZONES, sk.nodes[end ? s.b : s.a].zone);
        else {
          used.add(c.phase ?? 0);
          colour = new THREE.Color(PHASES[(c.phase ?? 0) % PHASES.length]);
        }
        put(i, end, colour);
      }
    });
    const entries = mode === 'phase'
      ? [...used].sort((a, b) => a - b).map((p) => [`phase ${p}`, PHASES[p % PHASES.length]])
      : Object.entries(table).filter(([k]) => used.has(k));
    legend = { title: { type: 'conduit type', water: 'water type', zone: 'zone', phase: 'phase' }[mode], entries };
  }
  return { colours, legend };
}

/** Draws `legend` into the element. */
export function drawLegend(element, legend) {
  element.replaceChildren();
  const title = document.createElement('div');
  title.textContent = legend.title;
  element.append(title);
  if (legend.entries) {
    for (const [name, colour] of legend.entries) {
      const row = document.createElement('div');
      row.className = 'row';
      const swatch = document.createElement('span');
      swatch.className = 'swatch';
      swatch.style.background = colour;
      row.append(swatch, name);
      element.append(row);
    }
  } else {
    const bar = document.createElement('div');
    bar.className = 'ramp';
    bar.style.background = legend.ramp;
    const ends = document.createElement('div');
    ends.className = 'ends';
    const fmt = (v) => (Math.abs(v) >= 100 ? v.toFixed(0) : v.toPrecision(3));
    ends.innerHTML = `<span>${fmt(legend.lo)}</span><span>${fmt(legend.hi)}</span>`;
    element.append(bar, ends);
  }
}
