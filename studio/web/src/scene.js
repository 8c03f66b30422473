// The 3D view: the planning scene's objects on the robots' link frames and in the world, the
// extras (iceball, ultrasound plane, paths, wound/thread, stitches; the fixed shapes of shapes.js:
// tumour, forbidden regions, tissue layers, contact surface), orbit camera controls.
// cobra's world is z up (m, rad); the camera's up is +z so no transform sits between the scene
// root and the link frames: a link group's world matrix is exactly the frame's pose.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { STLLoader } from 'three/examples/jsm/loaders/STLLoader.js';
import { OBJLoader } from 'three/examples/jsm/loaders/OBJLoader.js';
import { FIXED_KINDS, makeFixedExtra, makeStrands, setPoints, setStrands } from './shapes.js';

export const BACKGROUND = 0x1d2126;
const MIN_FIT_RADIUS = 0.25; // m: a view of a single point or a small path still shows its surroundings
const PALETTE = [0x4e9ad8, 0xe0a040, 0x6cc070, 0xc46fd0, 0xd86060, 0x60c8c8, 0xb0b060];
const WORLD_PALETTE = [0x8a9099, 0xe8b4a0, 0xd05050, 0x9a7fd0, 0x70b0a0, 0xc0c070];

/** Sets an Object3D's position and quaternion from [x, y, z, qx, qy, qz, qw] (m). */
export function setPose(object, pose, where) {
  if (!Array.isArray(pose) || pose.length !== 7 || !pose.every(Number.isFinite)) {
    throw new Error(`${where}: expected a pose [x,y,z,qx,qy,qz,qw] of 7 numbers, got ${JSON.stringify(pose)}`);
  }
  object.position.set(pose[0], pose[1], pose[2]);
  object.quaternion.set(pose[3], pose[4], pose[5], pose[6]);
}

function shapeGeometry(shape, where) {
  const size = shape.size ?? [];
  const need = { box: 3, cylinder: 2, capsule: 2, sphere: 1 }[shape.type];
  if (need === undefined) {
    throw new Error(`${where}: unknown shape type '${shape.type}' (expected box, cylinder, capsule, sphere or mesh)`);
  }
  if (size.length < need || !size.slice(0, need).every((v) => Number.isFinite(v) && v >= 0)) {
    throw new Error(`${where}: shape ${shape.type} needs ${need} non-negative sizes [m], got ${JSON.stringify(size)}`);
  }
  switch (shape.type) {
    case 'box': return new THREE.BoxGeometry(size[0], size[1], size[2]);
    // three builds cylinders and capsules along y; the protocol's (and planning's) are along z.
    case 'cylinder': return new THREE.CylinderGeometry(size[0], size[0], size[1], 32).rotateX(Math.PI / 2);
    case 'capsule': return new THREE.CapsuleGeometry(size[0], size[1], 8, 24).rotateX(Math.PI / 2);
    default: return new THREE.SphereGeometry(size[0], 32, 16);
  }
}

/**
 * Parses a mesh file's bytes: STL (binary or ASCII) or OBJ, told apart by content since the
 * server names meshes /api/mesh/NAME without an extension.
 */
function parseMesh(buffer, material) {
  const bytes = new Uint8Array(buffer);
  const head = new TextDecoder().decode(bytes.subarray(0, 512)).trimStart();
  const view = new DataView(buffer);
  const binaryStl = bytes.length >= 84 && 84 + 50 * view.getUint32(80, true) === bytes.length;
  if (binaryStl || (head.startsWith('solid') && /facet/.test(new TextDecoder().decode(bytes.subarray(0, 4096))))) {
    return new THREE.Mesh(new STLLoader().parse(buffer), material);
  }
  if (/^(#|v|vn|vt|f|o|g|s|mtllib|usemtl)\s/m.test(head)) {
    const group = new OBJLoader().parse(new TextDecoder().decode(bytes));
    group.traverse((child) => { if (child.isMesh) child.material = material; });
    return group;
  }
  throw new Error('expected an STL (binary or ASCII) or OBJ file');
}

/** Fetches a mesh shape (STL or OBJ, from shape.file) into `parent`, scaled by shape.scale. */
async function loadMesh(shape, material, parent, where) {
  const file = String(shape.file ?? '');
  const url = new URL(file, window.location.href);
  const token = new URLSearchParams(window.location.search).get('token');
  if (token) url.searchParams.set('token', token);
  try {
    const response = await fetch(url, { headers: token ? { 'X-Cobra-Token': token } : {} });
    if (!response.ok) throw new Error(`HTTP ${response.status}`);
    const object = parseMesh(await response.arrayBuffer(), material);
    object.scale.setScalar(shape.scale ?? 1);
    parent.add(object);
    object.updateMatrixWorld(true);
  } catch (err) {
    throw new Error(`${where}: mesh '${file}' cannot be loaded: ${err.message}`, { cause: err });
  }
}

const EXTRA_COLORS = [0xffb347, 0x7fff7f, 0xff6f91, 0x9ad0ff, 0xf0f060];
// Fixed shapes by what they usually are (a tumour, forbidden regions, a surface); others cycle.
const FIXED_COLORS = { spheres: 0xb060e0, capsules: 0xff4040, cylinders: 0xd89878, boxes: 0xe8c0a8 };

/** The three.js object of one model extra; its colour in userData.color (for the legend). */
function makeExtra(extra, index) {
  const color = FIXED_COLORS[extra.kind] ?? EXTRA_COLORS[index % EXTRA_COLORS.length];
  const object = (() => {
    if (FIXED_KINDS[extra.kind]) return makeFixedExtra(extra, color);
    switch (extra.kind) {
      case 'sphere': return new THREE.Mesh(new THREE.SphereGeometry(1, 32, 16),
        new THREE.MeshStandardMaterial({ color: 0xaee6ff, transparent: true, opacity: 0.6 }));
      case 'plane': return new THREE.Mesh(new THREE.PlaneGeometry(1, 1),
        new THREE.MeshBasicMaterial({ color: 0x9ad0ff, transparent: true, opacity: 0.35, side: THREE.DoubleSide }));
      case 'polyline': return makeStrands(extra, color);
      case 'segments': return new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color }));
      case 'path': return new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color }));
      case 'points': return new THREE.Points(new THREE.BufferGeometry(),
        new THREE.PointsMaterial({ color, size: 7, sizeAttenuation: false }));
      default: throw new Error(`model extras '${extra.name}': unknown kind '${extra.kind}' (expected sphere, plane, points, `
        + 'polyline, segments, path, spheres, capsules, cylinders or boxes)');
    }
  })();
  object.userData.color = object.material?.color ?? new THREE.Color(color);
  return object;
}

const finite = (values, n) => Array.isArray(values) && values.length === n && values.every(Number.isFinite);

/**
 * Applies one extra's frame data (the payload of each kind: studio/web/README.md). The server
 * sends null for a value it could not read (a port not written yet): that extra is hidden.
 */
function updateExtra(extra, object, data) {
  if (!data) return;
  switch (extra.kind) {
    case 'sphere':
      object.visible = finite(data.center, 3) && Number.isFinite(data.radius) && data.radius > 0;
      if (object.visible) {
        object.position.fromArray(data.center);
        object.scale.setScalar(data.radius);
      }
      break;
    case 'plane': {
      const size = data.size ?? extra.size ?? [0.1, 0.1];
      object.visible = finite(data.pose, 7) && finite(size, 2);
      if (object.visible) {
        setPose(object, data.pose, `frame extras '${extra.name}'.pose`);
        object.scale.set(size[0], size[1], 1);
      }
      break;
    }
    case 'polyline': setStrands(object, (data.points ?? []).filter((p) => finite(p, 3))); break;
    default: setPoints(object, (data.points ?? []).filter((p) => finite(p, 3)));
  }
}

export class StudioView {
  /** Builds the view for `model` (the protocol's /api/model) inside the element `container`. */
  constructor(container, model, onError) {
    this.model = model;
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(BACKGROUND);
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    container.append(this.renderer.domElement);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 50);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(1.4, -1.4, 1.1);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.set(0.2, 0, 0.2);
    this.controls.addEventListener('change', () => this.render());
    this.fitted = false;
    this.addLightsAndGrid();
    this.links = new Map();
    for (const robot of model.robots ?? []) {
      const groups = Array.from({ length: robot.links }, (_, i) => {
        const group = new THREE.Group();
        group.name = `${robot.name}.${i}`;
        this.scene.add(group);
        return group;
      });
      this.links.set(robot.name, groups);
    }
    this.meshes = []; // promises of the meshes being fetched
    this.addObjects(model.objects ?? [], onError);
    this.extras = new Map();
    for (const [index, extra] of (model.extras ?? []).entries()) {
      const object = makeExtra(extra, index);
      object.name = extra.name;
      object.visible = extra.kind !== 'sphere';
      this.scene.add(object);
      let trail = null;
      if (extra.kind === 'points') {
        trail = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: object.userData.color }));
        trail.name = `${extra.name}.trail`;
        this.scene.add(trail);
      }
      this.extras.set(extra.name, { extra, object, trail });
    }
    this.resizeObserver = new ResizeObserver(() => this.resize(container));
    this.resizeObserver.observe(container);
    this.resize(container);
  }

  addLightsAndGrid() {
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(2, -1, 3);
    this.scene.add(sun);
    const grid = new THREE.GridHelper(2, 20, 0x56606c, 0x3a414b);
    grid.rotateX(Math.PI / 2); // three's grid lies in xz; cobra's floor is the xy plane
    const axes = new THREE.AxesHelper(0.1);
    grid.userData.helper = true;
    axes.userData.helper = true;
    this.scene.add(grid, axes);
  }

  /**
   * Robot-borne objects take their collision group's colour (macro, micro, ur5 ... tell apart),
   * and so do world objects of such a group (a robot's fixed frame); other world objects get one
   * colour each (the table, the phantom and its parts). World objects are translucent.
   */
  addObjects(objects, onError) {
    const groups = [...new Set(objects.filter((o) => o.robot).map((o) => o.group))];
    let worldIndex = 0;
    for (const [index, object] of objects.entries()) {
      const where = `model objects[${index}] '${object.name}'`;
      let parent = this.scene;
      if (object.robot) {
        parent = this.links.get(object.robot)?.[object.link];
        if (!parent) {
          throw new Error(`${where}: robot '${object.robot}' link ${object.link} is not in the model's robots (expected a robot name and 0 <= link < its links)`);
        }
      }
      const world = !object.robot;
      const color = groups.includes(object.group) ? PALETTE[groups.indexOf(object.group) % PALETTE.length]
        : WORLD_PALETTE[worldIndex++ % WORLD_PALETTE.length];
      const material = new THREE.MeshStandardMaterial({
        color,
        roughness: 0.6, metalness: 0.1, transparent: world, opacity: world ? 0.55 : 1,
        depthWrite: !world, // what lies inside a world object (the phantom's tumour) shows through it
      });
      const holder = new THREE.Group();
      holder.name = object.name;
      setPose(holder, object.pose, `${where}.pose`);
      if (object.shape?.type === 'mesh') {
        this.meshes.push(loadMesh(object.shape, material, holder, where).then(() => this.render(), (err) => onError(err.message)));
      }
      else holder.add(new THREE.Mesh(shapeGeometry(object.shape ?? {}, where), material));
      parent.add(holder);
    }
  }

  /** Places the camera at `position` looking at `target` ([x,y,z] m, world) and redraws. */
  setCamera(position, target) {
    this.camera.position.fromArray(position);
    this.controls.target.fromArray(target);
    const distance = this.camera.position.distanceTo(this.controls.target);
    this.camera.near = distance / 100;
    this.camera.far = distance * 20;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.render();
  }

  /** Each extra's name, kind and CSS colour, for the view's legend. */
  legend() {
    return [...this.extras.values()].map(({ extra, object }) => ({
      name: extra.name, kind: extra.kind, color: `#${object.userData.color.getHexString()}`,
    }));
  }

  /** Draws the trail of a 'points' extra: where its first point was, oldest first ([x,y,z] m). */
  setTrail(name, points) {
    const trail = this.extras.get(name)?.trail;
    if (trail) setPoints(trail, points);
  }

  /** The group placed at link `index` of `robot` (its world matrix = the frame's link pose). */
  linkObject(robot, index) {
    return this.links.get(robot)?.[index] ?? null;
  }

  /**
   * Places every link and extra from a FRAME message and redraws. A link whose pose the server
   * sent as nulls (no joint state yet, or the kinematics failed) is hidden until it has one.
   */
  applyFrame(frame) {
    for (const [name, state] of Object.entries(frame.robots ?? {})) {
      const groups = this.links.get(name);
      if (!groups) continue;
      (state.links ?? []).forEach((pose, i) => {
        if (!groups[i]) return;
        groups[i].visible = finite(pose, 7);
        if (groups[i].visible) setPose(groups[i], pose, `frame t=${frame.t} robots '${name}' links[${i}]`);
      });
    }
    for (const [name, data] of Object.entries(frame.extras ?? {})) {
      const entry = this.extras.get(name);
      if (entry) updateExtra(entry.extra, entry.object, data);
    }
    this.scene.updateMatrixWorld(true);
    if (!this.fitted) this.fitCamera();
    this.render();
  }

  /**
   * Points the camera at everything drawn but the grid and axes (after the first frame placed the
   * robots, and on "Fit view"), at least MIN_FIT_RADIUS m around it.
   */
  fitCamera() {
    this.fitted = true;
    const box = new THREE.Box3();
    this.scene.traverse((o) => {
      if ((o.isMesh || o.isLine || o.isPoints) && !o.userData.helper && o.visible && o.geometry.attributes.position) box.expandByObject(o);
    });
    if (box.isEmpty()) return;
    const center = box.getCenter(new THREE.Vector3());
    const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, MIN_FIT_RADIUS);
    const distance = radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2));
    this.controls.target.copy(center);
    this.camera.position.copy(center).add(new THREE.Vector3(0.8, -1, 0.6).normalize().multiplyScalar(distance));
    this.camera.near = distance / 100;
    this.camera.far = distance * 10;
    this.camera.updateProjectionMatrix();
    this.controls.update();
  }

  resize(container) {
    const width = Math.max(container.clientWidth, 1);
    const height = Math.max(container.clientHeight, 1);
    this.renderer.setSize(width, height, false);
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }
}
