// The metrics panel: karstnet's ten statistics of the network, each on the band of values
// observed over real caves (metrics.json's `karstnet`, Collon et al. 2017), then the counts,
// the lengths per zone, conduit type and water type, and the springs' discharges.

// characterize_graph()'s keys, in karstnet's order.
const KEYS = ['mean length', 'cv length', 'length entropy', 'tortuosity', 'orientation entropy', 'aspl', 'cpd',
  'mean degree', 'cv degree', 'correlation vertex degree'];

/** The text of a metric value, as the test and metrics.json agree on it. */
export function formatMetric(value) {
  return value === null || value === undefined || Number.isNaN(value) ? 'undefined' : value.toFixed(3);
}

const metres = (v) => `${v.toFixed(0)} m`;

function table(rows) {
  const t = document.createElement('table');
  for (const [name, value, key] of rows) {
    const tr = t.insertRow();
    tr.insertCell().textContent = name;
    const cell = tr.insertCell();
    cell.textContent = value;
    if (key) cell.dataset.count = key;
  }
  return t;
}

function heading(text) {
  const h = document.createElement('h2');
  h.textContent = text;
  return h;
}

/** One metric on its band: the real-cave range in green, the value as a mark. */
function band(key, compared) {
  const { value, real_caves: range, inside } = compared;
  const div = document.createElement('div');
  div.className = 'metric';
  div.dataset.metric = key;
  const name = document.createElement('div');
  name.className = 'name';
  const label = document.createElement('span');
  label.textContent = key;
  const shown = document.createElement('span');
  shown.className = `value${inside ? '' : ' out'}`;
  shown.textContent = formatMetric(value);
  shown.title = `real caves: ${range.min.toFixed(3)} (${range.min_network}) – ${range.max.toFixed(3)} (${range.max_network}), ${range.n} networks`;
  name.append(label, shown);
  const bar = document.createElement('div');
  bar.className = 'band';
  const defined = typeof value === 'number';
  const lo = Math.min(range.min, defined ? value : range.min);
  const hi = Math.max(range.max, defined ? value : range.max);
  const pad = 0.12 * ((hi - lo) || 1);
  const at = (v) => `${(100 * (v - lo + pad)) / (hi - lo + 2 * pad)}%`;
  const inner = document.createElement('div');
  inner.className = 'inside';
  inner.style.left = at(range.min);
  inner.style.width = `calc(${at(range.max)} - ${at(range.min)})`;
  bar.append(inner);
  if (defined) {
    const mark = document.createElement('div');
    mark.className = `mark${inside ? '' : ' out'}`;
    mark.style.left = `calc(${at(value)} - 1px)`;
    bar.append(mark);
  }
  div.append(name, bar);
  return div;
}

/** Fills the panel from run.json's metrics (and the springs of hydro). */
export function showMetrics(element, data) {
  const m = data.metrics;
  if (!m) return;
  element.replaceChildren();
  const inside = KEYS.filter((k) => m.karstnet[k]?.inside).length;
  const summary = document.createElement('div');
  summary.textContent = `${inside} of ${KEYS.length} metrics within the real-cave ranges (green)`;
  element.append(summary);
  for (const key of KEYS) if (m.karstnet[key]) element.append(band(key, m.karstnet[key]));
  const n = m.network;
  element.append(heading('Counts'), table([
    ['nodes', `${n.n_nodes_full}`, 'n_nodes_full'], ['branches', `${n.n_branches}`, 'n_branches'],
    ['cycles', `${n.n_cycles}`, 'n_cycles'], ['components', `${n.n_components_full}`, 'n_components_full'],
    ['total length', metres(n.total_length), 'total_length'],
  ]));
  element.append(heading('Length per zone'), table([
    ['vadose', metres(m.zones.vadose)], ['phreatic', metres(m.zones.phreatic)],
  ]));
  const nonzero = (lengths) => Object.entries(lengths).filter(([, v]) => v > 0).map(([k, v]) => [k, metres(v)]);
  element.append(heading('Length per conduit type'), table(nonzero(m.conduit_types)));
  if (Object.keys(m.water_types ?? {}).length > 0) {
    element.append(heading('Length per water type'), table(nonzero(m.water_types)));
  }
  if (data.hydro) element.append(heading('Springs'), table(springRows(data)));
}

/** Each spring's discharge: network units and m³/s (the flow of the segments ending there). */
function springRows(data) {
  const sk = data.skeleton;
  return data.hydro.springs.map((s) => {
    let discharge = 0;
    sk.conduits.forEach((c, ci) => {
      const w = data.hydro.conduits[ci];
      for (let i = 0; i + 1 < c.nodes.length; i += 1) {
        const to = w.downstream[i] ? c.nodes[i + 1] : c.nodes[i];
        if (to === s.node && w.segment_flow[i] > 0) discharge += w.discharge[i];
      }
    });
    return [s.name, `${s.flow.toPrecision(4)} units, ${discharge.toPrecision(3)} m³/s`];
  });
}
