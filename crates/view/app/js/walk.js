// The first-person views: the walk, where the camera travels along a sink-to-spring route of
// the skeleton, at eye level on the conduits' axis, looking ahead, and the standing view, where
// it stands at one point of the cave looking at another (`#from=x,y,z&to=x,y,z` in the page's
// address, in the skeleton's coordinates: a viewpoint to share, and how the pictures from
// inside in docs/viewer.md are made). The orbit controls rest meanwhile.

import * as THREE from 'three';

export class Walk {
  constructor(data, viewer, hide) {
    this.data = data;
    this.viewer = viewer;
    this.hide = hide;
    this.speed = 12;
    this.curve = null;
    this.walking = false;
    this.inside = false;
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
    this.enter();
    this.walking = true;
    return true;
  }

  /** Stands at `from` looking at `to` (skeleton coordinates), until `stop`. */
  standAt(from, to) {
    if (!this.inside) this.enter();
    const e = this.viewer.exaggeration;
    const [here, there] = [from, to].map((p) => new THREE.Vector3(p[0], p[1], p[2] * e));
    if (there.distanceTo(here) < 1e-6) there.x += 1e-3;
    this.viewer.camera.position.copy(here);
    this.viewer.camera.lookAt(there);
    this.viewer.changed();
  }

  /** Leaves the orbit view for a first-person one: near clipping plane, outside layers hidden. */
  enter() {
    if (this.inside) return;
    this.inside = true;
    const { camera, controls } = this.viewer;
    this.saved = { position: camera.position.clone(), target: controls.target.clone(), near: camera.near, fov: camera.fov };
    controls.enabled = false;
    // A person's field of view in a passage, wider than the orbit view's 45°.
    camera.fov = 70;
    camera.near = 0.05;
    camera.updateProjectionMatrix();
    this.hide(true);
    this.viewer.changed();
  }

  stop() {
    if (!this.inside) return;
    this.walking = false;
    this.inside = false;
    const { camera, controls } = this.viewer;
    camera.position.copy(this.saved.position);
    controls.target.copy(this.saved.target);
    camera.near = this.saved.near;
    camera.fov = this.saved.fov;
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
