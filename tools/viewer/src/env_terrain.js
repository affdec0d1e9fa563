// The undulating terrain (scene.json environment.terrain): the surface
// z = amplitude (1 - cos(2 pi x / wavelength)) over x_range x y_range with a
// 10 cm grid on it, and its walls (axis-aligned boxes) half transparent so
// that they do not hide the chain.
import * as THREE from 'three';
import { gridTexture } from './environment.js';

export const TERRAIN_COLOR = '#c8a86b';

export function buildTerrain(env) {
  const t = env.terrain ?? {};
  const A = t.amplitude_m ?? 0, lambda = t.wavelength_m || 1;
  const [x0, x1] = t.x_range_m ?? [-0.5 * (t.length_m ?? 2), 0.5 * (t.length_m ?? 2)];
  const [y0, y1] = t.y_range_m ?? [-0.5 * (t.width_m ?? 0.2), 0.5 * (t.width_m ?? 0.2)];
  const lx = x1 - x0, ly = y1 - y0;
  // about 4 mm between rows of vertices along x, at least 16 per wavelength
  const nx = Math.min(4000, Math.max(2, Math.ceil(lx / Math.min(0.004, lambda / 16))));
  const g = new THREE.PlaneGeometry(lx, ly, nx, 2);
  const pos = g.attributes.position;
  for (let i = 0; i < pos.count; i++) {
    const x = pos.getX(i) + 0.5 * (x0 + x1), y = pos.getY(i) + 0.5 * (y0 + y1);
    pos.setXYZ(i, x, y, A * (1 - Math.cos((2 * Math.PI * x) / lambda)));
  }
  g.computeVertexNormals();
  const tex = gridTexture('#e2cd9f', '#c9b080', '#8a6d3b');
  tex.repeat.set(lx, ly);
  tex.offset.set(x0 - Math.floor(x0), y0 - Math.floor(y0));  // grid lines on whole metres
  const surface = new THREE.Mesh(g, new THREE.MeshStandardMaterial({ color: TERRAIN_COLOR, map: tex, roughness: 0.95 }));
  surface.receiveShadow = true;
  const group = new THREE.Group();
  group.add(surface);
  const wallMat = new THREE.MeshStandardMaterial({
    color: '#7b8794', transparent: true, opacity: 0.16, depthWrite: false, side: THREE.DoubleSide, roughness: 0.8,
  });
  for (const w of t.walls ?? []) {
    const box = new THREE.Mesh(new THREE.BoxGeometry(...w.size_m), wallMat);
    box.position.set(...w.centre_m);
    group.add(box);
    const edges = new THREE.Mesh(new THREE.BoxGeometry(w.size_m[0], w.size_m[1] * 1.02, 0.002), new THREE.MeshStandardMaterial({ color: '#55606b' }));
    edges.position.set(w.centre_m[0], w.centre_m[1], w.centre_m[2] + 0.5 * w.size_m[2]);
    group.add(edges);  // the top edge, opaque, so the wall's height reads
  }
  group.userData.label = `terrain, amplitude ${Math.round(A * 1000)} mm, wavelength ${Math.round(lambda * 1000)} mm`;
  return { object: group };
}
