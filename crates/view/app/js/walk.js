// The first-person walk: the camera travels along a sink-to-spring route of the skeleton, at
// eye level on the conduits' axis, looking ahead, while the orbit controls rest.

import * as THREE from 'three';

export class Walk {
  constructor(data, viewer, hide) {
    this.data = data;
    this.viewer = viewer;
    this.hide = hide;
    this.speed = 12;
    this.curve = null;
    this.walking = false;
    viewer.onFrame(() => this.step());
  }

  /** Starts along route `r` (an index into skeleton.routes). */
  start(r) {
    const nodes = this.data.skeleton.nodes;
    const route = this.data.skeleton.routes[r];
    const points = route.nodes.map((n) => new THREE.Vector3(...nodes[n].position));
    const unique = points.filter((p, i) => i === 0 || p.distanceTo(points[i - 1]) > 1e-6);
    if (unique.length < 2) return false;
    this.curve = new THREE.CatmullRomCurve3(unique, false, 'centripetal');
    this.length = this.curve.getLength();
    this.travelled = 0;
    this.last = performance.now();
    this.walking = true;
    this.saved = { position: this.viewer.camera.position.clone(), target: this.viewer.controls.target.clone(), near: this.viewer.camera.near };
    this.viewer.controls.enabled = false;
    this.viewer.camera.near = 0.05;
    this.viewer.camera.updateProjectionMatrix();
    this.hide(true);
    this.viewer.changed();
    return true;
  }

  stop() {
    if (!this.walking) return;
    this.walking = false;
    const { camera, controls } = this.viewer;
    camera.position.copy(this.saved.position);
    controls.target.copy(this.saved.target);
    camera.near = this.saved.near;
    camera.updateProjectionMatrix();
    controls.enabled = true;
    controls.update();
    this.hide(false);
    this.viewer.changed();
  }

  step() {
    if (!this.walking) return;
    const now = performance.now();
    this.travelled += this.speed * (now - this.last) / 1000;
    this.last = now;
    if (this.travelled >= this.length) {
      this.stop();
      return;
    }
    const u = this.travelled / this.length;
    const ahead = Math.min(u + 4 / this.length, 1);
    const e = this.viewer.exaggeration;
    const here = this.curve.getPointAt(u);
    const there = this.curve.getPointAt(ahead);
    here.z *= e;
    there.z *= e;
    if (there.distanceTo(here) < 1e-6) there.x += 1e-3;
    this.viewer.camera.position.copy(here);
    this.viewer.camera.lookAt(there);
    this.viewer.changed();
  }
}
