// The conduit network as lines, its colouring, picking (a node or a conduit segment under the
// pointer) and the route from the picked place to a spring, drawn as a tube over everything.

import * as THREE from 'three';
import { colouring } from './colours.js';

/** Pixels within which a click picks a node rather than a segment. */
const NODE_PICK_PIXELS = 6;
/** Pixels within which a click picks a segment. */
const SEGMENT_PICK_PIXELS = 5;

export class Network {
  constructor(data, viewer) {
    this.data = data;
    this.viewer = viewer;
    const sk = data.skeleton;
    this.segments = [];
    sk.conduits.forEach((c, conduit) => {
      for (let index = 0; index + 1 < c.nodes.length; index += 1) {
        this.segments.push({ conduit, index, a: c.nodes[index], b: c.nodes[index + 1] });
      }
    });
    const positions = new Float32Array(this.segments.length * 6);
    this.segments.forEach((s, i) => {
      positions.set(sk.nodes[s.a].position, i * 6);
      positions.set(sk.nodes[s.b].position, i * 6 + 3);
    });
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(positions.length), 3));
    this.material = new THREE.LineBasicMaterial({ vertexColors: true, clippingPlanes: [viewer.sectionPlane] });
    this.lines = new THREE.LineSegments(geometry, this.material);
    this.lines.name = 'network';
    viewer.world.add(this.lines);
    this.setOnTop(true);
    this.highlight = new THREE.Group();
    viewer.world.add(this.highlight);
    this.springs = new Set((data.hydro?.springs ?? []).map((s) => s.node));
    for (const k of data.keypoints) if (k.kind === 'spring' && k.node !== undefined) this.springs.add(k.node);
    this.adjacency = this.buildAdjacency();
  }

  setOnTop(onTop) {
    this.material.depthTest = !onTop;
    this.lines.renderOrder = onTop ? 2 : 0;
    this.material.needsUpdate = true;
    this.viewer.changed();
  }

  /** Colours the lines by `mode`; returns the legend. */
  colour(mode) {
    const { colours, legend } = colouring(mode, this.data, this.segments);
    const attribute = this.lines.geometry.getAttribute('color');
    attribute.array.set(colours);
    attribute.needsUpdate = true;
    this.viewer.changed();
    return legend;
  }

  /** For every node, its segments: {segment, other node}. */
  buildAdjacency() {
    const adjacency = this.data.skeleton.nodes.map(() => []);
    this.segments.forEach((s, i) => {
      adjacency[s.a].push({ segment: i, to: s.b });
      adjacency[s.b].push({ segment: i, to: s.a });
    });
    return adjacency;
  }

  /** Whether water runs along segment i from node `from`, and how much. */
  downstreamFlow(i, from) {
    const h = this.data.hydro;
    if (!h) return 0;
    const s = this.segments[i];
    const w = h.conduits[s.conduit];
    const flow = w.segment_flow[s.index];
    if (!(flow > 0)) return 0;
    const forward = w.downstream[s.index];
    return (forward ? s.a : s.b) === from ? flow : 0;
  }

  /**
   * The nodes from `start` to a spring: downstream along the largest flow while there is water,
   * else the shortest way (in metres) through the network to the nearest spring.
   */
  routeToSpring(start) {
    const route = [start];
    const seen = new Set(route);
    let node = start;
    while (!this.springs.has(node)) {
      let best = null;
      for (const { segment, to } of this.adjacency[node]) {
        const q = this.downstreamFlow(segment, node);
        if (q > 0 && !seen.has(to) && (!best || q > best.q)) best = { q, to };
      }
      if (!best) break;
      node = best.to;
      route.push(node);
      seen.add(node);
    }
    if (this.springs.has(node)) return route;
    const rest = this.shortestToSpring(node);
    return rest ? route.concat(rest.slice(1)) : route;
  }

  /** Dijkstra from `start` to the nearest spring node, or null. */
  shortestToSpring(start) {
    const nodes = this.data.skeleton.nodes;
    const distance = new Map([[start, 0]]);
    const previous = new Map();
    const open = [[0, start]];
    while (open.length > 0) {
      open.sort((a, b) => b[0] - a[0]);
      const [d, node] = open.pop();
      if (d > distance.get(node)) continue;
      if (this.springs.has(node)) {
        const path = [node];
        while (previous.has(path[0])) path.unshift(previous.get(path[0]));
        return path;
      }
      for (const { to } of this.adjacency[node]) {
        const nd = d + new THREE.Vector3(...nodes[node].position).distanceTo(new THREE.Vector3(...nodes[to].position));
        if (nd < (distance.get(to) ?? Infinity)) {
          distance.set(to, nd);
          previous.set(to, node);
          open.push([nd, to]);
        }
      }
    }
    return null;
  }

  /** The node or segment under the canvas point, or null. */
  pick(x, y, caveMeshes) {
    const nodes = this.data.skeleton.nodes;
    let best = null;
    nodes.forEach((n, i) => {
      if (n.position[2] > this.viewer.sectionZ) return;
      const p = this.viewer.project(n.position);
      if (!p) return;
      const d = Math.hypot(p.x - x, p.y - y);
      if (d <= NODE_PICK_PIXELS && (!best || d < best.d) && (this.adjacency[i].length !== 2 || n.keypoint)) {
        best = { d, node: i };
      }
    });
    if (best) return { node: best.node };
    const segment = this.nearestSegmentOnScreen(x, y);
    if (segment !== null) return { segment };
    const hit = this.viewer.raycaster(x, y).intersectObjects(caveMeshes, false)[0];
    return hit ? { segment: this.nearestSegmentTo(hit.point) } : null;
  }

  /** The segment drawn nearest the canvas point, within SEGMENT_PICK_PIXELS. */
  nearestSegmentOnScreen(x, y) {
    if (!this.lines.visible) return null;
    const nodes = this.data.skeleton.nodes;
    const screen = nodes.map((n) => (n.position[2] > this.viewer.sectionZ ? null : this.viewer.project(n.position)));
    let best = null;
    this.segments.forEach((s, i) => {
      const [p, q] = [screen[s.a], screen[s.b]];
      if (!p || !q) return;
      const d = pointToSegment(x, y, p, q);
      if (d <= SEGMENT_PICK_PIXELS && (!best || d < best.d)) best = { d, i };
    });
    return best ? best.i : null;
  }

  /** The segment nearest a world point (on the cave's wall). */
  nearestSegmentTo(point) {
    const nodes = this.data.skeleton.nodes;
    const e = this.viewer.exaggeration;
    const p = new THREE.Vector3(point.x, point.y, point.z / e);
    let best = null;
    this.segments.forEach((s, i) => {
      const line = new THREE.Line3(new THREE.Vector3(...nodes[s.a].position), new THREE.Vector3(...nodes[s.b].position));
      const d = line.closestPointToPoint(p, true, new THREE.Vector3()).distanceTo(p);
      if (!best || d < best.d) best = { d, i };
    });
    return best.i;
  }

  /** Draws the picked segment and the route (nodes) as tubes over everything. */
  show(segment, route) {
    for (const child of [...this.highlight.children]) {
      child.geometry.dispose();
      this.highlight.remove(child);
    }
    const nodes = this.data.skeleton.nodes;
    const radius = Math.max(this.viewer.size() / 600, 0.3);
    const tube = (path, colour, r) => {
      if (path.length < 2) return;
      const curve = new THREE.CurvePath();
      for (let i = 0; i + 1 < path.length; i += 1) {
        curve.add(new THREE.LineCurve3(new THREE.Vector3(...nodes[path[i]].position), new THREE.Vector3(...nodes[path[i + 1]].position)));
      }
      const mesh = new THREE.Mesh(new THREE.TubeGeometry(curve, Math.max(path.length * 2, 8), r, 6, false),
        new THREE.MeshBasicMaterial({ color: colour, depthTest: false, transparent: true, opacity: 0.85 }));
      mesh.renderOrder = 3;
      this.highlight.add(mesh);
    };
    tube(route, 0xffd21f, radius);
    if (segment !== null) tube([this.segments[segment].a, this.segments[segment].b], 0xff1fd2, radius * 1.8);
    this.viewer.changed();
  }
}

function pointToSegment(x, y, p, q) {
  const dx = q.x - p.x;
  const dy = q.y - p.y;
  const l2 = dx * dx + dy * dy;
  const t = l2 > 0 ? Math.min(Math.max(((x - p.x) * dx + (y - p.y) * dy) / l2, 0), 1) : 0;
  return Math.hypot(x - (p.x + t * dx), y - (p.y + t * dy));
}
