// The 3-D view: the environment, every module body posed from the trace at the
// replay time, an orbit camera that can follow the chain, and the module
// highlights (fault: red and flashing; touch: green glow).
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { buildEnvironment } from './environment.js';
import './environments.js';

const FAULT_COLOR = new THREE.Color('#ff1a1a');
const TOUCH_COLOR = new THREE.Color('#2ecc40');

// THREE geometry of one body of scene.json; capsule and cylinder axes are the
// body's local z (three.js builds them along y)
function bodyGeometry(b) {
  let g;
  switch (b.shape) {
    case 'capsule': g = new THREE.CapsuleGeometry(b.radius_m, b.length_m, 6, 20); break;
    case 'cylinder': g = new THREE.CylinderGeometry(b.radius_m, b.radius_m, b.length_m, 24); break;
    case 'box': return new THREE.BoxGeometry(...b.box_m);
    case 'sphere': return new THREE.SphereGeometry(b.radius_m, 20, 14);
    default: return new THREE.SphereGeometry(0.005, 8, 6);
  }
  return g.rotateX(Math.PI / 2);
}

export class Scene3D {
  constructor(container, { preserveDrawingBuffer = false, note } = {}) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.shadowMap.enabled = true;
    this.renderer.localClippingEnabled = true;  // for cut-away environments
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color('#f4f6f8');
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.002, 200);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.controls.addEventListener('change', () => (this.dirty = true));
    this.follow = true;
    this.note = note;
    this.scene.add(new THREE.HemisphereLight('#ffffff', '#8a8f99', 1.6));
    this.sun = new THREE.DirectionalLight('#ffffff', 1.8);
    this.sun.castShadow = true;
    this.sun.shadow.mapSize.set(2048, 2048);
    const sc = this.sun.shadow.camera;
    sc.left = sc.bottom = -1; sc.right = sc.top = 1; sc.near = 0.1; sc.far = 10;
    this.scene.add(this.sun, this.sun.target);
    this.focus = new THREE.Vector3();
    this.axis = new THREE.Vector3(1, 0, 0);  // the chain's direction, tail to head
    this.heading = null;                    // of the pipe at the chain (rad), when in a pipe
    this.wallMode = 'cut';
    this.modules = [];
    this.env = null;
    this.dirty = true;
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }

  resize() {
    const w = this.container.clientWidth || 1, h = this.container.clientHeight || 1;
    this.renderer.setSize(w, h, false);
    this.renderer.domElement.style.width = '100%';
    this.renderer.domElement.style.height = '100%';
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }

  // (re)build the environment and the module meshes from scene.json
  // (files: the mesh files embedded in the page); envReady resolves once the
  // environment is drawn
  build(sceneJson, files = {}) {
    if (this.env) this.scene.remove(this.env.object);
    this.env = buildEnvironment(sceneJson.environment, { note: this.note, files });
    this.env.setWallMode?.(this.wallMode);
    this.scene.add(this.env.object);
    this.envReady = Promise.resolve(this.env.ready).then(() => (this.dirty = true));
    this.heading = null;
    for (const m of this.modules) this.scene.remove(m.group);
    this.modules = (sceneJson.modules ?? []).map((m) => {
      const group = new THREE.Group();
      const base = new THREE.Color(m.color ?? '#cccccc');
      const bodies = m.bodies.map((b, k) => {
        // the end plates a little darker than the shell, so the joints show
        const color = b.shape === 'cylinder' && m.bodies.length > 1 ? base.clone().multiplyScalar(0.72) : base.clone();
        const mat = new THREE.MeshStandardMaterial({ color, roughness: 0.55, metalness: 0.05 });
        const mesh = new THREE.Mesh(bodyGeometry(b), mat);
        mesh.castShadow = mesh.receiveShadow = true;
        mesh.userData = { module: m.index, body: b.name, base: color.clone(), k };
        group.add(mesh);
        return { mesh, prefix: `m${m.index}.${b.name}.`, up: b.up };
      });
      this.scene.add(group);
      return { index: m.index, type: m.type, group, bodies, state: 'ok' };
    });
    this.stripes = false;
    this.buildLegend(sceneJson.modules ?? []);
    this.dirty = true;
  }

  // the module types of the chain with their colours, over the view (and in
  // pictures): every type a colour of its own, the user's types too
  buildLegend(modules) {
    this.legend?.remove();
    const types = new Map();
    for (const m of modules) {
      const k = types.get(m.type) ?? { color: m.color ?? '#cccccc', n: 0 };
      k.n++;
      types.set(m.type, k);
    }
    this.legend = document.createElement('div');
    this.legend.className = 'cs-legend';
    for (const [type, { color, n }] of types) {
      const row = document.createElement('div');
      const sw = document.createElement('span');
      sw.className = 'sw';
      sw.style.background = color;
      row.append(sw, `${type} \u00d7${n}`);
      this.legend.append(row);
    }
    this.container.append(this.legend);
  }

  // a dark stripe along each module's top (the side of its up, on its largest
  // body): a chain rolled onto its side shows it, round modules too
  addStripes() {
    const mat = new THREE.MeshStandardMaterial({ color: '#1b1b1b', roughness: 0.8 });
    const up = new THREE.Vector3(0, 0, 1), q = new THREE.Quaternion();
    const sizeOf = (b) => {
      b.mesh.geometry.computeBoundingBox();
      return b.mesh.geometry.boundingBox.getSize(new THREE.Vector3());
    };
    for (const m of this.modules) {
      // the module's largest body (its shell), not its end plates
      let b = null, most = -1;
      for (const c of m.bodies) {
        const s = sizeOf(c), v = s.x * s.y * s.z;
        if (v > most) { most = v; b = c; }
      }
      if (b) {
        const size = sizeOf(b);
        // the module's up in the body's frame (scene.json), else the body's
        // axis that points up at the trace's first row
        let local;
        if (b.up) {
          local = new THREE.Vector3(...b.up);
        } else {
          const c = b.cols;
          if (c) q.set(c[4].a[0], c[5].a[0], c[6].a[0], c[3].a[0]);
          else q.copy(b.mesh.quaternion);
          local = up.clone().applyQuaternion(q.invert());
        }
        const k = [0, 1, 2].reduce((best, i) => (Math.abs(local.getComponent(i)) > Math.abs(local.getComponent(best)) ? i : best), 0);
        const s = Math.sign(local.getComponent(k)) || 1;
        // a thin box on that face, as long as the body along its longest other axis
        const dims = [size.x, size.y, size.z];
        const other = [0, 1, 2].filter((i) => i !== k);
        const long = dims[other[0]] >= dims[other[1]] ? other[0] : other[1];
        const sd = [0, 0, 0];
        sd[k] = Math.max(dims[k] * 0.06, 0.0008);
        sd[long] = dims[long] * 0.8;
        sd[3 - k - long] = Math.max(dims[3 - k - long] * 0.18, 0.001);
        const stripe = new THREE.Mesh(new THREE.BoxGeometry(...sd), mat);
        stripe.position.setComponent(k, s * (dims[k] / 2));
        stripe.userData = { stripe: true };
        b.mesh.add(stripe);
      }
    }
    this.stripes = true;
  }

  // pose every body at time t from data (a RunData)
  pose(data, t) {
    const br = data.bracket(t);
    if (!br) return;
    const { i, j, f } = br;
    const qa = new THREE.Quaternion(), qb = new THREE.Quaternion();
    for (const m of this.modules)
      for (const b of m.bodies) {
        if (b.cols === undefined) {
          const idx = ['x', 'y', 'z', 'qw', 'qx', 'qy', 'qz'].map((s) => data.index.get(b.prefix + s));
          b.cols = idx.every((v) => v !== undefined) ? idx.map((k) => data.col[k]) : null;
        }
        const c = b.cols;
        if (!c) { b.mesh.visible = false; continue; }
        const v = (k, r) => c[k].a[r];
        b.mesh.position.set(
          v(0, i) + f * (v(0, j) - v(0, i)), v(1, i) + f * (v(1, j) - v(1, i)), v(2, i) + f * (v(2, j) - v(2, i)));
        qa.set(v(4, i), v(5, i), v(6, i), v(3, i));
        qb.set(v(4, j), v(5, j), v(6, j), v(3, j));
        b.mesh.quaternion.slerpQuaternions(qa, qb, f);
      }
    if (!this.stripes && this.modules.length) this.addStripes();
    const r = f < 0.5 ? i : j;
    const c = data.comAt(r);
    const next = new THREE.Vector3(c[0], c[1], c[2]);
    // the chain's direction: from the last module's first body to the first's
    const ends = [this.modules[this.modules.length - 1], this.modules[0]].map((m) => m?.bodies[0]?.mesh);
    if (ends[0] && ends[1] && ends[0] !== ends[1]) {
      const a = ends[1].position.clone().sub(ends[0].position);
      if (a.lengthSq() > 1e-10) this.axis.copy(a.normalize());
    }
    if (this.follow) {
      const d = next.clone().sub(this.focus);
      this.camera.position.add(d);
      this.controls.target.add(d);
      // in a pipe, the camera turns with the pipe: it keeps its offset in the
      // pipe's frame (seen from the same side when the pipe bends)
      const h = this.pipeHeading(next);
      if (h !== null && this.heading !== null) {
        let dh = h - this.heading;
        dh = Math.atan2(Math.sin(dh), Math.cos(dh));
        const off = this.camera.position.clone().sub(this.controls.target);
        off.applyAxisAngle(new THREE.Vector3(0, 0, 1), dh);
        this.camera.position.copy(this.controls.target).add(off);
        this.camera.lookAt(this.controls.target);
      }
      if (h !== null) this.heading = h;
    }
    this.focus.copy(next);
    this.sun.position.set(next.x + 1.5, next.y - 1.0, next.z + 3);
    this.sun.target.position.copy(next);
    this.dirty = true;
  }

  // highlight per module: 'ok' | 'fault' | 'touch'; phase flashes faults
  highlight(states, phase) {
    for (const m of this.modules) {
      const s = states[m.index] ?? 'ok';
      for (const b of m.bodies) {
        const mat = b.mesh.material;
        if (s === 'fault') {
          mat.color.copy(FAULT_COLOR);
          mat.emissive.copy(FAULT_COLOR).multiplyScalar(phase);
        } else if (s === 'touch') {
          mat.color.copy(b.mesh.userData.base);
          mat.emissive.copy(TOUCH_COLOR).multiplyScalar(0.6);
        } else {
          mat.color.copy(b.mesh.userData.base);
          mat.emissive.setRGB(0, 0, 0);
        }
      }
      m.state = s;
    }
    this.dirty = true;
  }

  // a camera that sees the whole chain from behind and above, about
  // `span` metres across
  // (in a pipe: turned with the pipe's heading there, from behind and to the right)
  resetCamera(span) {
    const d = Math.max(0.2, span) * 0.95;
    this.controls.target.copy(this.focus);
    const off = new THREE.Vector3(-0.55 * d, -0.9 * d, 0.6 * d);
    const h = this.pipeHeading(this.focus);
    if (h !== null) {
      off.applyAxisAngle(new THREE.Vector3(0, 0, 1), h);
      this.heading = h;
    }
    this.camera.position.copy(this.focus).add(off);
    this.camera.near = d / 200;
    this.camera.far = d * 60;
    this.camera.updateProjectionMatrix();
    const sc = this.sun.shadow.camera;
    sc.left = sc.bottom = -d; sc.right = sc.top = d;
    sc.updateProjectionMatrix();
    this.controls.update();
    this.dirty = true;
  }

  // the chain's extent now (m)
  span() {
    const box = new THREE.Box3();
    for (const m of this.modules) box.expandByObject(m.group);
    return box.isEmpty() ? 0.3 : box.getSize(new THREE.Vector3()).length();
  }

  // the horizontal direction (rad from +x) of the pipe's axis nearest to p, or
  // null (not a pipe, or the pipe is about vertical there)
  pipeHeading(p) {
    const a = this.env?.axisAt?.(p);
    if (!a || Math.hypot(a.tangent.x, a.tangent.y) < 0.25) return null;
    return Math.atan2(a.tangent.y, a.tangent.x);
  }

  // 'cut' | 'glass' | 'solid': how pipe and mesh walls are drawn
  setWallMode(mode) {
    this.wallMode = mode;
    this.env?.setWallMode?.(mode);
    this.dirty = true;
  }

  render(force = false) {
    if (!this.dirty && !force) return;
    this.env?.update?.({ focus: this.focus, camera: this.camera, axis: this.axis });
    this.renderer.render(this.scene, this.camera);
    this.dirty = false;
  }
}
