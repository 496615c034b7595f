// Key points (sinks, springs, waypoints, dead ends): a marker each and a label that follows it
// on screen.

import * as THREE from 'three';

const COLOURS = { sink: 0x1565c0, spring: 0x0a8a45, waypoint: 0xb06a10, dead_end: 0x8a5a20 };

export class KeyPoints {
  constructor(data, viewer, labelLayer) {
    this.viewer = viewer;
    this.group = new THREE.Group();
    this.group.name = 'key points';
    viewer.world.add(this.group);
    const radius = Math.max(viewer.size() / 250, 0.5);
    const sphere = new THREE.SphereGeometry(radius, 16, 12);
    this.points = data.keypoints.map((k) => {
      const mesh = new THREE.Mesh(sphere, new THREE.MeshStandardMaterial({
        color: COLOURS[k.kind] ?? 0x555555, clippingPlanes: [viewer.sectionPlane],
      }));
      mesh.position.set(...k.position);
      this.group.add(mesh);
      const label = document.createElement('span');
      label.className = `label ${k.kind}`;
      label.textContent = k.name;
      labelLayer.append(label);
      return { keypoint: k, label };
    });
    viewer.onFrame(() => this.place());
  }

  setVisible(visible) {
    this.group.visible = visible;
    this.viewer.changed();
  }

  /** Moves every label next to its marker (hidden when off screen, cut or layer off). */
  place() {
    for (const { keypoint, label } of this.points) {
      const p = this.group.visible && keypoint.position[2] <= this.viewer.sectionZ ? this.viewer.project(keypoint.position) : null;
      const on = p && p.x >= 0 && p.y >= 0 && p.x <= this.viewer.canvas.clientWidth && p.y <= this.viewer.canvas.clientHeight;
      label.style.display = on ? '' : 'none';
      if (on) label.style.transform = `translate(${p.x + 6}px, ${p.y}px) translateY(-50%)`;
    }
  }
}
