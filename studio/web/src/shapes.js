// The extras cobra sends once, in the model (PROTOCOL.md, "Extras"): fixed shapes in the world
// frame read from the components' properties (the phantom's tumour and layers, the forbidden
// regions, the Puma 260's surface), and the lines the frames refill (polyline strands, segments).
// Units m; cobra's world is z up, so the shapes are placed in the scene root as they come.
import * as THREE from 'three';

/** Numbers per shape of each fixed kind, as the model sends them in `shapes`. */
export const FIXED_KINDS = { spheres: 4, capsules: 7, cylinders: 7, boxes: 10 };

const UP = new THREE.Vector3(0, 1, 0); // three builds capsules and cylinders along y
// Layers (boxes) stacked in one extra get a tint each, so that neighbouring slabs tell apart.
const BOX_TINTS = [0xe8c0a8, 0xf0e0a0, 0xc87870, 0xa05860, 0x9ab0c8, 0xb8d0a0];

function translucent(color, opacity) {
  return new THREE.MeshStandardMaterial({
    color, transparent: true, opacity, roughness: 0.7, metalness: 0, depthWrite: false, side: THREE.DoubleSide,
  });
}

/** A mesh of `geometry` (built along y) whose axis runs from a to b, centred between them. */
function alongSegment(geometry, a, b, material) {
  const mesh = new THREE.Mesh(geometry, material);
  const from = new THREE.Vector3(...a);
  const to = new THREE.Vector3(...b);
  mesh.position.copy(from).add(to).multiplyScalar(0.5);
  const axis = to.clone().sub(from);
  if (axis.lengthSq() > 0) mesh.quaternion.setFromUnitVectors(UP, axis.normalize());
  return mesh;
}

function fixedShape(kind, s, material, index) {
  switch (kind) {
    case 'spheres': {
      const mesh = new THREE.Mesh(new THREE.SphereGeometry(s[3], 32, 16), material);
      mesh.position.set(s[0], s[1], s[2]);
      return mesh;
    }
    case 'capsules': {
      const length = Math.hypot(s[3] - s[0], s[4] - s[1], s[5] - s[2]);
      return alongSegment(new THREE.CapsuleGeometry(s[6], length, 8, 24), s.slice(0, 3), s.slice(3, 6), material);
    }
    case 'cylinders': {
      const length = Math.hypot(s[3] - s[0], s[4] - s[1], s[5] - s[2]);
      return alongSegment(new THREE.CylinderGeometry(s[6], s[6], length, 48), s.slice(0, 3), s.slice(3, 6), material);
    }
    default: { // boxes: pose (7), full lengths (3)
      const mesh = new THREE.Mesh(new THREE.BoxGeometry(s[7], s[8], s[9]),
        translucent(BOX_TINTS[index % BOX_TINTS.length], material.opacity));
      mesh.position.set(s[0], s[1], s[2]);
      mesh.quaternion.set(s[3], s[4], s[5], s[6]);
      return mesh;
    }
  }
}

/**
 * The group of a fixed extra (kind spheres, capsules, cylinders or boxes): one mesh per shape,
 * named NAME[i]. @throws Error naming the extra and the shape when its numbers are not what the
 * kind needs.
 */
export function makeFixedExtra(extra, color) {
  const per = FIXED_KINDS[extra.kind];
  const group = new THREE.Group();
  // What lies inside the layers (a tumour, forbidden regions) is drawn after them and more opaque,
  // so that it shows through them.
  const material = translucent(color, extra.kind === 'boxes' ? 0.2 : 0.7);
  (extra.shapes ?? []).forEach((s, i) => {
    const where = `model extras '${extra.name}' shapes[${i}]`;
    if (!Array.isArray(s) || s.length !== per || !s.every(Number.isFinite)) {
      throw new Error(`${where}: expected ${per} finite numbers for ${extra.kind}, got ${JSON.stringify(s)}`);
    }
    const mesh = fixedShape(extra.kind, s, material, i);
    mesh.name = `${extra.name}[${i}]`;
    mesh.renderOrder = extra.kind === 'boxes' ? 0 : 1;
    group.add(mesh);
  });
  return group;
}

/** The lines of a 'polyline' extra: `strands` lines (at least one) the frame's points are dealt to. */
export function makeStrands(extra, color) {
  const strands = Number.isInteger(extra.strands) && extra.strands > 0 ? extra.strands : 1;
  const group = new THREE.Group();
  for (let i = 0; i < strands; i += 1) {
    const line = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color }));
    line.name = `${extra.name}[${i}]`;
    group.add(line);
  }
  return group;
}

/** Fills `object` (a Line, LineSegments or Points) with the points [[x,y,z], ...] (m). */
export function setPoints(object, points) {
  // A new geometry each time: three's setFromPoints only refills an existing attribute's size.
  object.geometry.dispose();
  object.geometry = new THREE.BufferGeometry().setFromPoints(points.map((p) => new THREE.Vector3(p[0], p[1], p[2])));
}

/** Deals a frame's points to the strands of a 'polyline' group: point k to strand k mod strands. */
export function setStrands(group, points) {
  const n = group.children.length;
  group.children.forEach((line, i) => setPoints(line, points.filter((_, k) => k % n === i)));
}
