// Water tables and horizons: translucent surfaces from the elevation grids of run.json,
// clipped to the domain box (and by the horizontal section).

import * as THREE from 'three';

const COLOURS = { 'water table': 0x2a8cff, horizon: 0x7a5a2a };

/** One mesh per surface, added to the viewer's world; returns [{name, kind, mesh}]. */
export function buildSurfaces(data, viewer) {
  const d = data.domain;
  const box = [
    new THREE.Plane(new THREE.Vector3(1, 0, 0), -d.min[0]), new THREE.Plane(new THREE.Vector3(-1, 0, 0), d.max[0]),
    new THREE.Plane(new THREE.Vector3(0, 1, 0), -d.min[1]), new THREE.Plane(new THREE.Vector3(0, -1, 0), d.max[1]),
  ];
  return data.surfaces.map((s) => {
    const geometry = new THREE.PlaneGeometry(s.max[0] - s.min[0], s.max[1] - s.min[1], s.nx - 1, s.ny - 1);
    const position = geometry.getAttribute('position');
    // PlaneGeometry's rows run from +y to −y; the grid's from min y up.
    for (let j = 0; j < s.ny; j += 1) {
      for (let i = 0; i < s.nx; i += 1) {
        const v = (s.ny - 1 - j) * s.nx + i;
        position.setXYZ(v, s.min[0] + (s.max[0] - s.min[0]) * i / (s.nx - 1),
          s.min[1] + (s.max[1] - s.min[1]) * j / (s.ny - 1), s.z[j * s.nx + i]);
      }
    }
    geometry.computeVertexNormals();
    const material = new THREE.MeshStandardMaterial({
      color: COLOURS[s.kind] ?? 0x888888, transparent: true, opacity: 0.18, side: THREE.DoubleSide, depthWrite: false,
      clippingPlanes: [...box, viewer.sectionPlane],
    });
    const mesh = new THREE.Mesh(geometry, material);
    mesh.name = `${s.kind} ${s.name}`;
    viewer.world.add(mesh);
    return { name: s.name, kind: s.kind, mesh };
  });
}
