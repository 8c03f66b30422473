// Writes the browser tests' fixtures (test/fixtures/) from a small synthetic robot: a 4-joint arm
// and a 2-joint probe whose forward kinematics is computed here with plain quaternion algebra
// (independent of three.js, which the page uses), sampled at 30 frames per simulated s as the
// studio protocol (studio/PROTOCOL.md) prescribes. Units: m, rad, s.
// Run: node test/make_fixtures.mjs (the files are committed; rerun after changing this script).
import { writeFileSync, mkdirSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const OUT = join(dirname(fileURLToPath(import.meta.url)), 'fixtures');
const RATE = 30; // frames per simulated s
const DURATION = 4; // s

// A rigid transform: p [m] and unit quaternion q = [x, y, z, w].
const ident = () => ({ p: [0, 0, 0], q: [0, 0, 0, 1] });
function qmul(a, b) {
  const [ax, ay, az, aw] = a;
  const [bx, by, bz, bw] = b;
  return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
    aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz];
}
function rotate(q, v) {
  const r = qmul(qmul(q, [v[0], v[1], v[2], 0]), [-q[0], -q[1], -q[2], q[3]]);
  return [r[0], r[1], r[2]];
}
function compose(a, b) {
  const rp = rotate(a.q, b.p);
  return { p: [a.p[0] + rp[0], a.p[1] + rp[1], a.p[2] + rp[2]], q: qmul(a.q, b.q) };
}
const axisAngle = (axis, angle) => {
  const s = Math.sin(angle / 2);
  return [axis[0] * s, axis[1] * s, axis[2] * s, Math.cos(angle / 2)];
};
const rot = (axis, angle) => ({ p: [0, 0, 0], q: axisAngle(axis, angle) });
const trans = (x, y, z) => ({ p: [x, y, z], q: [0, 0, 0, 1] });
const chain = (...ts) => ts.reduce(compose, ident());
const pose7 = (t) => [...t.p, ...t.q];
const X = [1, 0, 0];
const Y = [0, 1, 0];
const Z = [0, 0, 1];

const ARM_BASE = chain(trans(0, 0, 0.04), rot(Z, 0.3));
const UPPER = 0.25; // m, upper arm along +x of link 2
const FORE = 0.2; // m, forearm along +x of link 3
function armLinks(q) {
  const l0 = ARM_BASE;
  const l1 = chain(l0, rot(Z, q[0]), trans(0, 0, 0.1));
  const l2 = chain(l1, trans(0, 0, 0.1), rot(Y, q[1]));
  const l3 = chain(l2, trans(UPPER, 0, 0), rot(Y, q[2]));
  const l4 = chain(l3, trans(FORE, 0, 0), rot(X, q[3]));
  return [l0, l1, l2, l3, l4];
}
const PROBE_BASE = chain(trans(0.45, -0.35, 0.04), rot(Z, Math.PI / 2));
function probeLinks(q) {
  const l0 = PROBE_BASE;
  const l1 = chain(l0, trans(0, 0, 0.15), rot(X, q[0]), trans(0, 0, q[1]));
  return [l0, l1];
}

const PHANTOM = { center: [0.35, 0.1, 0.1], radius: 0.08 };
const THRESHOLD = 0.005; // m
const alongX = axisAngle(Y, Math.PI / 2); // turns a z-axis shape onto +x

// A square pyramid, 40 mm base and 30 mm high, in mm (a CAD export's units): the mesh objects'
// file, written as ASCII STL and as OBJ, drawn at scale 0.001.
const PYRAMID = { vertices: [[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0], [0, 0, 30]],
  triangles: [[0, 2, 1], [0, 3, 2], [0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]] };
function stl({ vertices, triangles }) {
  const facets = triangles.map((t) => `facet normal 0 0 0\n outer loop\n${t.map((i) => `  vertex ${vertices[i].join(' ')}\n`).join('')} endloop\nendfacet\n`);
  return `solid pyramid\n${facets.join('')}endsolid pyramid\n`;
}
function obj({ vertices, triangles }) {
  return `# pyramid, mm\n${vertices.map((v) => `v ${v.join(' ')}`).join('\n')}\n${triangles.map((t) => `f ${t.map((i) => i + 1).join(' ')}`).join('\n')}\n`;
}

const objects = [
  { name: 'table', group: 'environment', robot: '', link: -1, shape: { type: 'box', size: [1.2, 1.0, 0.04] }, pose: [0, 0, 0.02, 0, 0, 0, 1] },
  { name: 'phantom', group: 'environment', robot: '', link: -1, shape: { type: 'sphere', size: [PHANTOM.radius] }, pose: [...PHANTOM.center, 0, 0, 0, 1] },
  { name: 'marker_stl', group: 'environment', robot: '', link: -1, shape: { type: 'mesh', file: '/api/mesh/marker_stl', scale: 0.001 }, pose: [-0.3, 0.3, 0.04, 0, 0, 0, 1] },
  { name: 'marker_obj', group: 'environment', robot: '', link: -1, shape: { type: 'mesh', file: '/api/mesh/marker_obj', scale: 0.001 }, pose: [-0.3, -0.3, 0.04, 0, 0, 0, 1] },
  { name: 'arm_base', group: 'arm', robot: 'arm', link: 0, shape: { type: 'cylinder', size: [0.08, 0.1] }, pose: [0, 0, 0.05, 0, 0, 0, 1] },
  { name: 'arm_shoulder', group: 'arm', robot: 'arm', link: 1, shape: { type: 'box', size: [0.09, 0.09, 0.1] }, pose: [0, 0, 0.05, 0, 0, 0, 1] },
  { name: 'arm_upper', group: 'arm', robot: 'arm', link: 2, shape: { type: 'capsule', size: [0.03, UPPER] }, pose: [UPPER / 2, 0, 0, ...alongX] },
  { name: 'arm_fore', group: 'arm', robot: 'arm', link: 3, shape: { type: 'capsule', size: [0.025, FORE] }, pose: [FORE / 2, 0, 0, ...alongX] },
  { name: 'arm_tool', group: 'arm', robot: 'arm', link: 4, shape: { type: 'cylinder', size: [0.004, 0.08] }, pose: [0, 0, -0.04, 0, 0, 0, 1] },
  { name: 'probe_base', group: 'probe', robot: 'probe', link: 0, shape: { type: 'box', size: [0.08, 0.08, 0.15] }, pose: [0, 0, 0.075, 0, 0, 0, 1] },
  { name: 'probe_body', group: 'probe', robot: 'probe', link: 1, shape: { type: 'cylinder', size: [0.02, 0.12] }, pose: [0, 0, 0.06, 0, 0, 0, 1] },
];

const TASK_STATES = [[0, 'Idle'], [0.5, 'Approach'], [1.5, 'Insert.Advance'], [2.5, 'Insert.Hold'], [3.5, 'Done']];
const stateAt = (t) => TASK_STATES.filter(([start]) => t >= start - 1e-9).at(-1)[1];

function model(mode) {
  return {
    protocol: 1, mode, app: 'fixture', scenario: 'synthetic_arm',
    ...(mode === 'replay' ? { duration: DURATION } : {}),
    robots: [
      { name: 'arm', joints: ['q1', 'q2', 'q3', 'q4'], links: 5, tools: 1 },
      { name: 'probe', joints: ['p1', 'p2'], links: 2, tools: 1 },
    ],
    objects,
    charts: [
      { name: 'task', states: TASK_STATES.map(([, s]) => s) },
      { name: 'needle', states: ['WaitMounted', 'Mounted'] },
    ],
    signals: [
      { name: 'arm.q1.deg', unit: 'deg' },
      { name: 'arm.tip.z.mm', unit: 'mm' },
      { name: 'clearance.mm', unit: 'mm' },
    ],
    inputs: [
      { name: 'needle_mounted', label: 'Needle mounted', target: 'Surgeon.say' },
      { name: 'cryo_done', label: 'Cryo cycle done', target: 'Surgeon.say' },
    ],
    extras: [
      { name: 'iceball', kind: 'sphere', frame: 'world' },
      { name: 'us_plane', kind: 'plane', frame: 'world', size: [0.12, 0.1] },
      { name: 'nominal_path', kind: 'path', frame: 'world' },
      { name: 'wound', kind: 'polyline', frame: 'world' },
      { name: 'stitches', kind: 'points', frame: 'world' },
      { name: 'tool', kind: 'points', frame: 'world' },
    ],
  };
}

const probeLost = (t) => t >= 3 - 1e-9 && t < 3.2 - 1e-9;

function frame(t, path) {
  const qa = [0.6 * Math.sin(0.5 * t), 0.5 + 0.3 * Math.sin(t), -0.9 + 0.5 * Math.sin(0.7 * t), 2 * t];
  const qp = [0.3 * Math.sin(t), 0.05 * (1 + Math.sin(t))];
  const arm = armLinks(qa);
  const tip = arm[4].p;
  const gap = Math.hypot(tip[0] - PHANTOM.center[0], tip[1] - PHANTOM.center[1], tip[2] - PHANTOM.center[2]) - PHANTOM.radius;
  const r = (v) => Math.round(v * 1e9) / 1e9; // signals rounded to 1e-9 only to keep the file short
  return {
    type: 'frame', t: r(t),
    // The probe's state is lost for 0.2 s: the server sends nulls for what it cannot read.
    robots: { arm: { q: qa, links: arm.map(pose7) }, probe: probeLost(t) ? { q: [null, null], links: [Array(7).fill(null), Array(7).fill(null)] } : { q: qp, links: probeLinks(qp).map(pose7) } },
    extras: {
      iceball: { center: PHANTOM.center, radius: t < 2.5 ? 0 : 0.02 * Math.min(1, (t - 2.5) / 1.5) },
      us_plane: { pose: [0.35, 0.1, 0.2, ...axisAngle(X, Math.PI / 2)] },
      nominal_path: { points: path },
      wound: { points: [[0.3, 0.05, 0.18], [0.4, 0.15, 0.18]] },
      tool: { points: [tip] },
      stitches: { points: [[0.32, 0.07, 0.18], [0.35, 0.1, 0.18], [0.38, 0.13, 0.18]].slice(0, Math.floor(t)) },
    },
    charts: { task: stateAt(t), needle: 'WaitMounted' },
    deployments: { task: t < 1.5 ? 'planning' : 'execution' },
    configurations: { arm: t < 1.5 ? 'position' : 'admittance' },
    signals: { 'arm.q1.deg': r(qa[0] * 180 / Math.PI), 'arm.tip.z.mm': r(tip[2] * 1000), 'clearance.mm': r(gap * 1000) },
    clearance: { min: gap, threshold: THRESHOLD, valid: gap > THRESHOLD },
  };
}

const count = DURATION * RATE + 1;
const times = Array.from({ length: count }, (_, i) => i / RATE);
const path = times.filter((_, i) => i % 10 === 0).map((t) => frame(t, []).robots.arm.links[4].slice(0, 3));
const frames = times.map((t) => frame(t, path));
const events = TASK_STATES.map(([t, s]) => ({ type: 'event', t, source: 'task', name: `entered ${s}` }));
events.push({ type: 'end', t: DURATION, outcome: 'Completed', message: 'synthetic run finished' });

mkdirSync(OUT, { recursive: true });
mkdirSync(join(OUT, 'meshes'), { recursive: true });
writeFileSync(join(OUT, 'meshes', 'marker_stl'), stl(PYRAMID));
writeFileSync(join(OUT, 'meshes', 'marker_obj'), obj(PYRAMID));
writeFileSync(join(OUT, 'model.json'), JSON.stringify(model('live')) + '\n');
const recording = { model: model('replay'), frames, events };
writeFileSync(join(OUT, 'recording.json'), JSON.stringify(recording) + '\n');
console.log(`fixtures: ${frames.length} frames, ${objects.length} objects -> ${OUT}`);
