// Registers the builders of environment.js's extension point for the types
// scene.json has besides "plane" and "group": pipe, terrain, mesh. Each is
// drawn with the ground plane too when the environment has "ground_plane".
import * as THREE from 'three';
import { registerEnvironment, buildEnvironment } from './environment.js';
import { buildPipe } from './env_pipe.js';
import { buildTerrain } from './env_terrain.js';
import { buildMesh } from './env_mesh.js';

function withGround(build) {
  return (env, ctx) => {
    const b = build(env, ctx);
    if (!env.ground_plane) return b;
    const ground = buildEnvironment({ type: 'plane', material: env.material }, ctx);
    const group = new THREE.Group();
    group.add(ground.object, b.object);
    return {
      ...b,
      object: group,
      update(c) {
        ground.update?.(c);
        b.update?.(c);
      },
    };
  };
}

registerEnvironment('pipe', withGround(buildPipe));
registerEnvironment('terrain', withGround(buildTerrain));
registerEnvironment('mesh', withGround(buildMesh));
