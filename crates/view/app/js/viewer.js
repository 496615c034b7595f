// The 3D view: renderer, camera, orbit controls, lights, the world group (scene coordinates,
// z up, scaled by the vertical exaggeration) and the clipping planes shared by the layers.
// Frames are drawn on demand: anything that changes the picture calls `viewer.changed()`.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

export class Viewer {
  constructor(canvas, domain) {
    this.canvas = canvas;
    this.domain = domain;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.renderer.localClippingEnabled = true;
    this.renderer.setClearColor(0xdfe3e8);
    this.scene = new THREE.Scene();
    this.world = new THREE.Group();
    this.scene.add(this.world);
    const size = this.size();
    this.camera = new THREE.PerspectiveCamera(45, 1, Math.max(size / 5000, 0.05), size * 20);
    this.camera.up.set(0, 0, 1);
    this.scene.add(this.camera);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x606070, 1.4));
    const headlight = new THREE.DirectionalLight(0xffffff, 1.6);
    headlight.position.set(0.3, 0.5, 1);
    this.camera.add(headlight);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener('change', () => this.changed());
    // Clipping: the horizontal section keeps what lies below `section` (every layer); the cut
    // keeps the terrain on one side of a vertical plane.
    this.sectionPlane = new THREE.Plane(new THREE.Vector3(0, 0, -1), Infinity);
    this.cutPlane = new THREE.Plane(new THREE.Vector3(1, 0, 0), Infinity);
    this.exaggeration = 1;
    this.sectionZ = domain.max[2];
    this.listeners = [];
    this.dirty = true;
    this.frames = 0;
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
    this.home();
    // Frames wait until the first complete picture (`start()`): drawing half-loaded surfaces
    // would only slow the loading down.
    this.started = false;
    const loop = () => {
      if (this.dirty && this.started) {
        this.dirty = false;
        this.draw();
      }
      requestAnimationFrame(loop);
    };
    requestAnimationFrame(loop);
  }

  /** The longest side of the domain, metres. */
  size() {
    const d = this.domain;
    return Math.max(d.max[0] - d.min[0], d.max[1] - d.min[1], d.max[2] - d.min[2], 1);
  }

  /** The domain's centre in world coordinates. */
  centre() {
    const d = this.domain;
    return new THREE.Vector3(...[0, 1, 2].map((a) => (d.min[a] + d.max[a]) / 2));
  }

  /** The camera south-east of the domain and above it, looking at its centre, the whole domain in view. */
  home() {
    const d = this.domain;
    const c = this.centre();
    c.z *= this.exaggeration;
    const radius = 0.5 * Math.hypot(d.max[0] - d.min[0], d.max[1] - d.min[1], (d.max[2] - d.min[2]) * this.exaggeration);
    const vertical = THREE.MathUtils.degToRad(this.camera.fov) / 2;
    const horizontal = Math.atan(Math.tan(vertical) * this.camera.aspect);
    const distance = 0.95 * radius / Math.sin(Math.min(vertical, horizontal));
    this.controls.target.copy(c);
    this.camera.position.copy(c).add(new THREE.Vector3(0.45, -0.75, 0.5).normalize().multiplyScalar(distance));
    this.controls.update();
    this.changed();
  }

  /** Compiles the shaders, then draws from now on. */
  async start() {
    await this.renderer.compileAsync(this.scene, this.camera);
    this.started = true;
    this.draw();
  }

  /** Calls `f()` before each frame is drawn (LOD, labels, overlays). */
  onFrame(f) {
    this.listeners.push(f);
  }

  changed() {
    this.dirty = true;
  }

  draw() {
    for (const f of this.listeners) f();
    this.renderer.render(this.scene, this.camera);
    this.frames += 1;
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.canvas;
    if (w === 0 || h === 0) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.changed();
  }

  setExaggeration(e) {
    const ratio = e / this.exaggeration;
    this.exaggeration = e;
    this.world.scale.set(1, 1, e);
    this.world.updateMatrixWorld(true);
    this.controls.target.z *= ratio;
    this.camera.position.z *= ratio;
    this.controls.update();
    this.setSection(this.sectionZ);
  }

  /** Keeps what lies below elevation z (scene metres). */
  setSection(z) {
    this.sectionZ = z;
    this.sectionPlane.constant = z >= this.domain.max[2] ? Infinity : z * this.exaggeration;
    this.changed();
  }

  /** Cuts the terrain along a vertical plane across `axis` ('x', 'y' or 'none') at `t` in [0, 1]. */
  setCut(axis, t) {
    if (axis === 'none') {
      this.cutPlane.constant = Infinity;
    } else {
      const a = axis === 'x' ? 0 : 1;
      const at = this.domain.min[a] + t * (this.domain.max[a] - this.domain.min[a]);
      this.cutPlane.normal.set(a === 0 ? 1 : 0, a === 1 ? 1 : 0, 0);
      this.cutPlane.constant = -at;
    }
    this.changed();
  }

  /** Screen position (CSS pixels in the canvas) of a scene point, or null behind the camera. */
  project(p) {
    const v = new THREE.Vector3(p[0], p[1], p[2] * this.exaggeration).project(this.camera);
    if (v.z > 1 || v.z < -1) return null;
    return { x: (v.x + 1) / 2 * this.canvas.clientWidth, y: (1 - v.y) / 2 * this.canvas.clientHeight };
  }

  /** Metres per CSS pixel at the orbit target. */
  metresPerPixel() {
    const d = this.camera.position.distanceTo(this.controls.target);
    return 2 * d * Math.tan(THREE.MathUtils.degToRad(this.camera.fov) / 2) / this.canvas.clientHeight;
  }

  /** A picking ray through the canvas point (CSS pixels). */
  raycaster(x, y) {
    const ndc = new THREE.Vector2(x / this.canvas.clientWidth * 2 - 1, 1 - y / this.canvas.clientHeight * 2);
    const r = new THREE.Raycaster();
    r.setFromCamera(ndc, this.camera);
    return r;
  }

  /** The picture as a PNG data URL. */
  screenshot() {
    this.draw();
    return this.canvas.toDataURL('image/png');
  }
}
