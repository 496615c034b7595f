// The surface streams (streams.json: Emilien et al. 2015's waterfall network on the terrain)
// as lines, coloured by their Table 1 type with the palette of the network's water colouring;
// a free fall follows its parabola. Their own legend sits under the network's.

import * as THREE from 'three';
import { WATER_TYPES } from './colours.js';

const OTHER = '#bdbdbd';

export class SurfaceStreams {
  constructor(data, viewer) {
    this.viewer = viewer;
    this.segments = data.streams.segments;
    const pieces = this.segments.flatMap((s) => s.points.slice(1).map((q, i) => [s.points[i], q, s.water]));
    const positions = new Float32Array(pieces.length * 6);
    const colours = new Float32Array(pieces.length * 6);
    this.used = new Set();
    pieces.forEach(([p, q, water], i) => {
      positions.set(p, i * 6);
      positions.set(q, i * 6 + 3);
      const c = new THREE.Color(WATER_TYPES[water] ?? OTHER);
      colours.set([c.r, c.g, c.b, c.r, c.g, c.b], i * 6);
      this.used.add(water);
    });
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    this.material = new THREE.LineBasicMaterial({ vertexColors: true, clippingPlanes: [viewer.sectionPlane] });
    this.lines = new THREE.LineSegments(geometry, this.material);
    this.lines.name = 'surface streams';
    viewer.world.add(this.lines);
    this.setOnTop(true);
  }

  /** Over everything (above the network's lines), or hidden by the rock and the water. */
  setOnTop(onTop) {
    this.material.depthTest = !onTop;
    this.lines.renderOrder = onTop ? 2.5 : 0;
    this.material.needsUpdate = true;
    this.viewer.changed();
  }

  setVisible(visible) {
    this.lines.visible = visible;
    this.viewer.changed();
  }

  /** The types drawn, in Table 1's order, with their colours. */
  legend() {
    return {
      title: 'surface water type (Emilien 2015)',
      entries: Object.entries(WATER_TYPES).filter(([k]) => this.used.has(k)),
    };
  }

  /** Each segment's midpoint on screen (CSS pixels) with its type's colour (0–255), for probes. */
  probe() {
    return this.segments.map((s) => {
      const [p, q] = [s.points[Math.floor((s.points.length - 1) / 2)], s.points[Math.ceil((s.points.length - 1) / 2)]];
      const mid = p === q ? p : p.map((v, k) => (v + q[k]) / 2);
      const hex = new THREE.Color(WATER_TYPES[s.water] ?? OTHER).getHex();
      return { water: s.water, at: this.viewer.project(mid), colour: [hex >> 16, (hex >> 8) & 255, hex & 255] };
    });
  }
}
