// The scale bar (a round length at the orbit target's distance) and the north arrow (the
// direction of +y on screen), updated every frame.

import * as THREE from 'three';

/** The largest 1, 2 or 5 × 10ⁿ not above x. */
function roundDown(x) {
  const p = 10 ** Math.floor(Math.log10(x));
  return [5, 2, 1].map((m) => m * p).find((v) => v <= x) ?? p;
}

export function overlays(viewer) {
  const bar = document.getElementById('scale-bar');
  const text = document.getElementById('scale-text');
  const arrow = document.getElementById('north-arrow');
  const scale = document.getElementById('scale');
  viewer.onFrame(() => {
    // The bar measures at the orbit target: meaningless during a walk.
    scale.style.display = viewer.controls.enabled ? '' : 'none';
    const mpp = viewer.metresPerPixel();
    const length = roundDown(mpp * 120);
    bar.style.width = `${length / mpp}px`;
    text.textContent = length >= 1000 ? `${length / 1000} km` : `${length} m`;
    const t = viewer.controls.target;
    const a = new THREE.Vector3().copy(t).project(viewer.camera);
    const b = new THREE.Vector3(t.x, t.y + 1, t.z).project(viewer.camera);
    const angle = Math.atan2(b.x - a.x, b.y - a.y);
    arrow.setAttribute('transform', `rotate(${THREE.MathUtils.radToDeg(angle)})`);
  });
}
