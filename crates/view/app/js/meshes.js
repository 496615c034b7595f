// The chunked, multi-resolution surfaces (terrain, cave, water) of data/run.json's `meshes`.
//
// Every chunk first loads its coarsest level, so the whole surface appears quickly. Then, each
// frame, a chunk in view asks for the coarsest level whose geometric error projects to at most
// ERROR_PIXELS on screen; the loads run FETCHES at a time, the chunks with the largest error on
// screen first. A chunk shows the loaded level closest to the one it wants (a finer one when
// tied). Chunks out of view keep what they have.

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';

const ERROR_PIXELS = 1.5;
const FETCHES = 4;

const loader = new GLTFLoader();
loader.setMeshoptDecoder(MeshoptDecoder);

/** The materials of the three surfaces. */
function material(name, viewer) {
  const section = [viewer.sectionPlane];
  switch (name) {
    case 'terrain':
      return new THREE.MeshStandardMaterial({
        color: 0xb9a888, roughness: 0.95, transparent: true, opacity: 0.28, depthWrite: false,
        side: THREE.DoubleSide, clippingPlanes: [viewer.sectionPlane, viewer.cutPlane],
      });
    case 'cave':
      return new THREE.MeshStandardMaterial({ color: 0xd9823b, roughness: 0.8, side: THREE.DoubleSide, clippingPlanes: section });
    default:
      return new THREE.MeshStandardMaterial({
        color: 0x2f7fe0, roughness: 0.3, transparent: true, opacity: 0.75, side: THREE.DoubleSide, clippingPlanes: section,
      });
  }
}

/** A queue of level loads, FETCHES at a time, the most urgent first. */
class Loads {
  constructor(onLoaded) {
    this.waiting = [];
    this.running = 0;
    this.onLoaded = onLoaded;
  }

  add(job) {
    this.waiting.push(job);
  }

  pump() {
    this.waiting.sort((a, b) => b.urgency - a.urgency);
    while (this.running < FETCHES && this.waiting.length > 0) {
      const job = this.waiting.shift();
      this.running += 1;
      loader.loadAsync(job.url).then((gltf) => {
        job.done(gltf);
      }, (e) => {
        job.failed(e);
      }).finally(() => {
        this.running -= 1;
        this.onLoaded();
        this.pump();
      });
    }
  }

  busy() {
    return this.running > 0 || this.waiting.length > 0;
  }
}

/** One surface: its chunks, each a mesh whose geometry is the level it shows. */
export class ChunkedSurface {
  constructor(manifest, viewer, loads) {
    this.name = manifest.name;
    this.viewer = viewer;
    this.loads = loads;
    this.material = material(this.name, viewer);
    // glTF is Y-up: the files carry the turn from the scene's Z-up; this group turns it back.
    this.group = new THREE.Group();
    this.group.rotation.x = Math.PI / 2;
    this.group.name = this.name;
    viewer.world.add(this.group);
    this.chunks = manifest.chunks.map((c) => ({
      manifest: c,
      levels: new Array(c.levels.length).fill(null),
      pending: new Set(),
      mesh: null,
      box: new THREE.Box3(new THREE.Vector3(...c.min), new THREE.Vector3(...c.max)),
    }));
    this.errors = 0;
  }

  /** Loads the coarsest level of every chunk; resolves when all are in. */
  loadCoarsest() {
    return Promise.all(this.chunks.map((c) => new Promise((resolve) => {
      this.request(c, c.levels.length - 1, Infinity, resolve);
    })));
  }

  request(chunk, level, urgency, resolve = () => {}) {
    if (chunk.levels[level] || chunk.pending.has(level)) return resolve();
    chunk.pending.add(level);
    this.loads.add({
      url: chunk.manifest.levels[level].file,
      urgency,
      done: (gltf) => {
        chunk.pending.delete(level);
        const node = gltf.scene.getObjectByProperty('isMesh', true);
        chunk.levels[level] = node;
        this.show(chunk);
        resolve();
      },
      failed: (e) => {
        chunk.pending.delete(level);
        this.errors += 1;
        console.error(`${chunk.manifest.levels[level].file}: ${e.message ?? e}`);
        resolve();
      },
    });
  }

  /** Shows the loaded level closest to the wanted one. */
  show(chunk) {
    const want = chunk.want ?? chunk.levels.length - 1;
    let best = -1;
    for (let k = 0; k < chunk.levels.length; k += 1) {
      if (chunk.levels[k] && (best < 0 || Math.abs(k - want) < Math.abs(best - want)
        || (Math.abs(k - want) === Math.abs(best - want) && k < best))) best = k;
    }
    if (best < 0) return;
    const node = chunk.levels[best];
    if (!chunk.mesh) {
      chunk.mesh = new THREE.Mesh(node.geometry, this.material);
      chunk.mesh.userData.surface = this.name;
      this.group.add(chunk.mesh);
    }
    chunk.mesh.geometry = node.geometry;
    chunk.mesh.position.copy(node.position);
    chunk.mesh.quaternion.copy(node.quaternion);
    chunk.mesh.scale.copy(node.scale);
    chunk.shown = best;
    this.viewer.changed();
  }

  /** Chooses the wanted level of every chunk in view and queues the loads. */
  update(frustum, camera, pixelsPerRadian) {
    if (!this.group.visible) return;
    const e = this.viewer.exaggeration;
    for (const chunk of this.chunks) {
      const box = chunk.box.clone();
      box.min.z *= e;
      box.max.z *= e;
      if (!frustum.intersectsBox(box)) continue;
      const distance = Math.max(box.distanceToPoint(camera.position), 1e-3);
      const levels = chunk.manifest.levels;
      let want = 0;
      for (let k = levels.length - 1; k > 0; k -= 1) {
        if (levels[k].error * pixelsPerRadian / distance <= ERROR_PIXELS) { want = k; break; }
      }
      chunk.want = want;
      if (chunk.shown !== undefined && chunk.shown !== want && chunk.levels[want]) this.show(chunk);
      const urgency = levels[chunk.shown ?? levels.length - 1].error * pixelsPerRadian / distance;
      this.request(chunk, want, urgency);
    }
  }

  /** Triangles drawn now. */
  triangles() {
    return this.chunks.reduce((n, c) => n + (c.shown === undefined ? 0 : c.manifest.levels[c.shown].triangles), 0);
  }
}

/** All surfaces of the run, refined together each frame. */
export class Surfaces {
  constructor(manifests, viewer) {
    this.viewer = viewer;
    this.loads = new Loads(() => viewer.changed());
    this.surfaces = manifests.map((m) => new ChunkedSurface(m, viewer, this.loads));
    this.refining = false;
    viewer.onFrame(() => {
      if (this.refining) this.update();
    });
  }

  byName(name) {
    return this.surfaces.find((s) => s.name === name);
  }

  /** Loads every surface's coarsest levels, then turns on refinement. */
  async start() {
    const all = Promise.all(this.surfaces.map((s) => s.loadCoarsest()));
    this.loads.pump();
    await all;
    this.refining = true;
    this.viewer.changed();
  }

  update() {
    const { camera, canvas } = this.viewer;
    camera.updateMatrixWorld();
    const frustum = new THREE.Frustum().setFromProjectionMatrix(
      new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse));
    const pixelsPerRadian = canvas.clientHeight / (2 * Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2));
    for (const s of this.surfaces) s.update(frustum, camera, pixelsPerRadian);
    this.loads.pump();
  }

  /** True when every wanted level is loaded. */
  settled() {
    return this.refining && !this.loads.busy();
  }

  /** The cave or water surfaces' meshes, for picking. */
  meshes(name) {
    const s = this.byName(name);
    return s && s.group.visible ? s.chunks.map((c) => c.mesh).filter(Boolean) : [];
  }
}
