// A user mesh (scene.json environment.mesh): the file's bytes are embedded in
// the page by `chainsim view` (boot data "mesh_files", keyed by the mesh's
// "file", base64) and parsed here by three.js's loaders, chosen by the file's
// extension: .stl STLLoader, .obj OBJLoader, .ply PLYLoader, .glb/.gltf
// GLTFLoader (the external buffers and images of a .gltf are embedded too).
// Placed as the physics server places it: vertex' = Rz(yaw) Ry(pitch)
// Rx(roll) (scale vertex) + position. Its walls are HollowWalls with one
// clipping plane through the chain, along the chain, facing the camera.
import * as THREE from 'three';
import { STLLoader } from 'three/examples/jsm/loaders/STLLoader.js';
import { OBJLoader } from 'three/examples/jsm/loaders/OBJLoader.js';
import { PLYLoader } from 'three/examples/jsm/loaders/PLYLoader.js';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { HollowWalls, facePlaneAway } from './environment.js';
import { PIPE_COLOR } from './env_pipe.js';

function bytes(b64) {
  const s = atob(b64);
  const a = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) a[i] = s.charCodeAt(i);
  return a;
}

const ext = (f) => (/\.([A-Za-z0-9]+)$/.exec(f ?? '')?.[1] ?? '').toLowerCase();

// the file's content as a THREE.Object3D (a promise)
async function parseMesh(file, entry) {
  const data = bytes(entry.base64);
  const buf = data.buffer;
  const geometryMesh = (g) => {
    if (!g.attributes.normal) g.computeVertexNormals();
    return new THREE.Mesh(g);
  };
  switch (ext(file)) {
    case 'stl': return geometryMesh(new STLLoader().parse(buf));
    case 'ply': return geometryMesh(new PLYLoader().parse(buf));
    case 'obj': return new OBJLoader().parse(new TextDecoder().decode(data));
    case 'glb':
    case 'gltf': {
      const extra = entry.extra ?? {};
      const manager = new THREE.LoadingManager();
      manager.setURLModifier((url) =>
        extra[url] !== undefined ? `data:application/octet-stream;base64,${extra[url]}` : url);
      const gltf = await new GLTFLoader(manager).parseAsync(ext(file) === 'glb' ? buf : new TextDecoder().decode(data), '');
      return gltf.scene;
    }
    default: throw new Error(`mesh ${file}: unknown format (.stl, .obj, .ply, .glb, .gltf)`);
  }
}

export function buildMesh(env, ctx) {
  const m = env.mesh ?? {};
  const name = m.file_as_given ?? m.file;
  const walls = new HollowWalls(PIPE_COLOR);
  const plane = new THREE.Plane();
  const group = new THREE.Group();
  group.userData.label = `mesh ${name}`;
  const s = m.scale ?? 1;
  if (Array.isArray(s)) group.scale.set(s[0], s[1], s[2]);
  else group.scale.setScalar(s);
  const d = Math.PI / 180, rpy = m.rpy_deg ?? [0, 0, 0];
  group.rotation.set(rpy[0] * d, rpy[1] * d, rpy[2] * d, 'ZYX');  // Rz Ry Rx
  group.position.set(...(m.position_m ?? [0, 0, 0]));
  const entry = ctx.files?.[m.file];
  let ready = Promise.resolve();
  if (!entry || entry.base64 === undefined) {
    ctx.note?.(`mesh ${name} is not drawn: ${entry?.error ?? 'its file is not embedded in this page'}`);
  } else {
    const mat = walls.material(plane);
    ready = parseMesh(m.file, entry).then(
      (obj) => {
        obj.traverse((o) => {
          if (o.isMesh) {
            o.material = mat;
            o.castShadow = false;
            o.receiveShadow = true;
          }
        });
        group.add(obj);
      },
      (e) => ctx.note?.(`mesh ${name} is not drawn: ${e.message ?? e}`),
    );
  }
  return {
    object: group,
    ready,
    update(c) {
      facePlaneAway(plane, c.focus, c.camera, c.axis);
    },
    setWallMode: (mode) => walls.setMode(mode),
  };
}
