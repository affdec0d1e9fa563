// The environment of a scene (scene.json "environment"), drawn behind the
// modules.
//
// EXTENSION POINT: each environment type is a builder registered here under
// the name scene.json gives it ({"type": "plane", ...}). A builder gets the
// environment object of scene.json and a context, and returns
//   { object: THREE.Object3D,            // added to the scene
//     update?(ctx),                      // before each render: ctx.focus is the
//                                        // chain's centre of mass, ctx.camera the
//                                        // camera, ctx.axis the chain's direction
//                                        // (unit THREE.Vector3s)
//     setWallMode?(mode),                // 'cut' | 'glass' | 'solid' (the UI toggle)
//     axisAt?(point),                    // {point, tangent}: the nearest point of
//                                        // a pipe's axis (the camera turns with it)
//     ready?: Promise }                  // resolves once drawn (meshes parse async)
// ctx of the builder: {note(text), files: the mesh files the page embeds}.
// The builders of pipe, terrain and mesh are in env_*.js (registered by
// environments.js).
// To add terrain, pipes (straight cylinders, tori for bends, meshes), or
// anything else: registerEnvironment('pipe', (env, ctx) => {...}). Hollow
// solids the chain crawls inside should be drawn see-through so the modules
// stay visible: use seeThroughMaterial() (transparent, both faces) or
// cutAwayMaterial() (the half facing the camera is clipped away); both are
// below. A composite environment ({"type": "group", "parts": [...]}) draws
// each part with its own builder.
import * as THREE from 'three';

const builders = new Map();

export function registerEnvironment(type, builder) {
  builders.set(type, builder);
}

// the wall of a pipe or a tunnel, half transparent, inside and outside
export function seeThroughMaterial(color = '#8fa3b8', opacity = 0.25) {
  return new THREE.MeshStandardMaterial({
    color, transparent: true, opacity, side: THREE.DoubleSide, depthWrite: false, roughness: 0.8,
  });
}

// a solid cut open by plane (e.g. a vertical plane through the pipe's axis,
// turned towards the camera each frame by the builder's update())
export function cutAwayMaterial(plane, color = '#8fa3b8') {
  return new THREE.MeshStandardMaterial({ color, side: THREE.DoubleSide, clippingPlanes: [plane], roughness: 0.8 });
}

// the walls of hollow solids (pipes, meshes) the chain moves inside, drawn in
// one of three modes: 'cut' (each part clipped by its own plane, turned
// towards the camera by the builder's update(), so the near half is open),
// 'glass' (transparent) or 'solid'. material(plane) gives a material that
// follows the mode; the builder keeps the plane up to date.
export const WALL_MODES = ['cut', 'glass', 'solid'];
export class HollowWalls {
  constructor(color) {
    this.color = color;
    this.mode = 'cut';
    this.items = [];
  }
  material(plane, color = this.color) {
    const mat = new THREE.MeshStandardMaterial({ color, side: THREE.DoubleSide, roughness: 0.7, metalness: 0 });
    this.items.push({ mat, plane });
    this.apply(this.items[this.items.length - 1]);
    return mat;
  }
  apply({ mat, plane }) {
    const glass = this.mode === 'glass';
    mat.clippingPlanes = this.mode === 'cut' && plane ? [plane] : null;
    mat.transparent = glass;
    mat.opacity = glass ? 0.28 : 1;
    mat.depthWrite = !glass;
    mat.needsUpdate = true;
  }
  setMode(mode) {
    this.mode = WALL_MODES.includes(mode) ? mode : 'cut';
    for (const it of this.items) this.apply(it);
  }
}

// plane through point containing the direction `along` (unit), its normal the
// part of (point - camera) across `along`: what is nearer to the camera than
// the plane is clipped away (without `along`: the plane faces the camera)
export function facePlaneAway(plane, point, camera, along) {
  const n = point.clone().sub(camera.position);
  if (along) n.addScaledVector(along, -n.dot(along));
  if (n.lengthSq() < 1e-12) n.set(0, 0, 1);
  plane.setFromNormalAndCoplanarPoint(n.normalize(), point);
}

// one metre of ground as a texture: 10 cm cells, a darker line every metre
// (a texture rather than line objects: lines that pass behind the camera are
// dropped by some WebGL implementations, e.g. the software one of headless Chromium)
export function gridTexture(base = '#dfe3e8', minor = '#c0c7cf', major = '#7d8996') {
  const n = 512, canvas = document.createElement('canvas');
  canvas.width = canvas.height = n;
  const g = canvas.getContext('2d');
  g.fillStyle = base;
  g.fillRect(0, 0, n, n);
  g.fillStyle = minor;
  for (let k = 1; k < 10; k++) {
    g.fillRect(Math.round((k * n) / 10) - 1, 0, 2, n);
    g.fillRect(0, Math.round((k * n) / 10) - 1, n, 2);
  }
  g.fillStyle = major;
  g.fillRect(0, 0, 3, n);
  g.fillRect(0, 0, n, 3);
  const tex = new THREE.CanvasTexture(canvas);
  tex.wrapS = tex.wrapT = THREE.RepeatWrapping;
  tex.colorSpace = THREE.SRGBColorSpace;
  tex.anisotropy = 8;
  return tex;
}

// the ground: a large plane with a 10 cm grid that moves along with the chain
// (by whole metres, so the grid stays put in the world)
registerEnvironment('plane', (env) => {
  const size = 40;
  const tex = gridTexture();
  tex.repeat.set(size, size);
  const ground = new THREE.Mesh(
    new THREE.PlaneGeometry(size, size),
    new THREE.MeshStandardMaterial({ map: tex, roughness: 0.95, metalness: 0 }),
  );
  ground.receiveShadow = true;
  const mu = env?.material?.mu;
  ground.userData.label = `plane${mu !== undefined ? `, mu ${mu}` : ''}`;
  return {
    object: ground,
    update(c) {
      ground.position.x = Math.round(c.focus.x);
      ground.position.y = Math.round(c.focus.y);
    },
  };
});

// several parts, each with its own builder
registerEnvironment('group', (env, ctx) => {
  const group = new THREE.Group();
  const parts = (env.parts ?? []).map((p) => buildEnvironment(p, ctx));
  for (const p of parts) group.add(p.object);
  return {
    object: group,
    update: (c) => parts.forEach((p) => p.update?.(c)),
    setWallMode: (m) => parts.forEach((p) => p.setWallMode?.(m)),
    axisAt: (q) => {
      let best = null;
      for (const p of parts) {
        const a = p.axisAt?.(q);
        if (a && (!best || a.point.distanceToSquared(q) < best.point.distanceToSquared(q))) best = a;
      }
      return best;
    },
    ready: Promise.all(parts.map((p) => p.ready)),
  };
});

// an environment this viewer does not know: nothing drawn, a note shown
export function buildEnvironment(env, ctx) {
  const type = env?.type ?? 'none';
  const b = builders.get(type);
  if (!b) {
    ctx.note?.(`environment "${type}" is not drawn by this viewer`);
    return { object: new THREE.Group() };
  }
  return b(env, ctx);
}
