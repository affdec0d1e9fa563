// A pipe (scene.json environment.pipe): the bore of each piece, straight
// pieces as open cylinders, elbows as torus sections, a darker rim at every
// open end. The walls are HollowWalls: in 'cut' mode each section of a piece
// (at most 10 cm of a straight, 15 degrees of an elbow) has its own clipping
// plane through its axis, turned each frame so that its half towards the
// camera is open and the modules inside show. Tees are drawn as their two
// pieces (the openings they cut into each other are not cut in the drawing).
import * as THREE from 'three';
import { HollowWalls, facePlaneAway } from './environment.js';

export const PIPE_COLOR = '#3fa3b6';
const RIM_COLOR = '#1f5f6b';

const v3 = (a) => new THREE.Vector3(a[0], a[1], a[2]);

// a rotation matrix whose columns are x, y, z
function basis(x, y, z) {
  return new THREE.Matrix4().makeBasis(x, y, z);
}

export function buildPipe(env) {
  const pipe = env.pipe ?? {};
  const walls = new HollowWalls(PIPE_COLOR);
  const group = new THREE.Group();
  group.userData.label = `pipe, bore ${Math.round(2000 * (pipe.inner_radius_m ?? 0))} mm`;
  const sections = [];  // {point, tangent, plane}
  const axes = [];      // per piece: (q) => {point, tangent}
  const add = (geometry, matrix, point, tangent) => {
    const plane = new THREE.Plane();
    const mesh = new THREE.Mesh(geometry, walls.material(plane));
    mesh.applyMatrix4(matrix);
    mesh.receiveShadow = true;
    group.add(mesh);
    sections.push({ point, tangent, plane });
    return plane;
  };

  for (const p of pipe.pieces ?? []) {
    const r = p.inner_radius_m ?? pipe.inner_radius_m ?? 0.02;
    if (p.type === 'straight') {
      const a = v3(p.start_m), d = v3(p.direction).normalize(), len = p.length_m;
      const n = Math.max(1, Math.ceil(len / 0.1));
      const q = new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 1, 0), d);
      for (let k = 0; k < n; k++) {
        const c = a.clone().addScaledVector(d, ((k + 0.5) * len) / n);
        const m = new THREE.Matrix4().compose(c, q, new THREE.Vector3(1, 1, 1));
        add(new THREE.CylinderGeometry(r, r, len / n, 40, 1, true), m, c, d);
      }
      axes.push((x) => {
        const s = Math.max(0, Math.min(len, x.clone().sub(a).dot(d)));
        return { point: a.clone().addScaledVector(d, s), tangent: d.clone() };
      });
    } else if (p.type === 'elbow') {
      const c = v3(p.centre_m), u = v3(p.u).normalize(), v = v3(p.v).normalize();
      const w = new THREE.Vector3().crossVectors(u, v);
      const R = p.bend_radius_m, angle = p.angle_rad;
      const m = basis(u, v, w).setPosition(c);
      const at = (t) => ({
        point: c.clone().addScaledVector(u, R * Math.cos(t)).addScaledVector(v, R * Math.sin(t)),
        tangent: u.clone().multiplyScalar(-Math.sin(t)).addScaledVector(v, Math.cos(t)),
      });
      const n = Math.max(1, Math.ceil(angle / (Math.PI / 12)));
      for (let k = 0; k < n; k++) {
        const a0 = (k * angle) / n, a1 = ((k + 1) * angle) / n;
        const g = new THREE.TorusGeometry(R, r, 40, Math.max(4, Math.ceil((a1 - a0) / 0.05)), a1 - a0).rotateZ(a0);
        const mid = at(0.5 * (a0 + a1));
        add(g, m, mid.point, mid.tangent);
      }
      axes.push((x) => {
        const d = x.clone().sub(c);
        let t = Math.atan2(d.dot(v), d.dot(u));
        if (t < 0 && t < -(2 * Math.PI - angle) / 2) t += 2 * Math.PI;
        return at(Math.max(0, Math.min(angle, t)));
      });
    }
  }

  // a rim at every open end, clipped with the section it ends
  for (const e of pipe.open_ends ?? []) {
    const p = v3(e.point_m), d = v3(e.direction).normalize();
    const r = pipe.inner_radius_m ?? 0.02;
    let near = sections[0];
    for (const s of sections) if (s.point.distanceToSquared(p) < near.point.distanceToSquared(p)) near = s;
    if (!near) break;
    const q = new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 0, 1), d);
    const rim = new THREE.Mesh(new THREE.TorusGeometry(r * 1.04, r * 0.08, 8, 48), walls.material(near.plane, RIM_COLOR));
    rim.position.copy(p);
    rim.quaternion.copy(q);
    group.add(rim);
  }

  return {
    object: group,
    update(ctx) {
      for (const s of sections) facePlaneAway(s.plane, s.point, ctx.camera, s.tangent);
    },
    setWallMode: (mode) => walls.setMode(mode),
    axisAt(x) {
      let best = null;
      for (const f of axes) {
        const a = f(x);
        if (!best || a.point.distanceToSquared(x) < best.point.distanceToSquared(x)) best = a;
      }
      return best;
    },
  };
}
