// The extras cobra sends beside the robots, in the page's scene graph: the recorded runs of
// `cobra run apps/puncturing` and `cobra run apps/suturing` (their run folders' file:// pages, as
// the report links them) show the tumour sphere, every forbidden capsule and every tissue layer
// where and as large as the model says, the suturing wound's two edges, thread and stitches as the
// lines of the frame shown, and the Puma 260's contact surface (`cobra run apps/puma260`). Needs COBRA_BIN and COBRA_SOURCE_DIR (CTest sets both).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFile } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { promisify } from 'node:util';
import { launch, openStudio } from './browser.mjs';

const { COBRA_BIN, COBRA_SOURCE_DIR } = process.env;
const skip = !COBRA_BIN || !COBRA_SOURCE_DIR ? 'COBRA_BIN and COBRA_SOURCE_DIR not set (CTest sets them)' : false;
const TOLERANCE = 1e-9; // m
let browser;
const folders = [];

before(async () => { if (!skip) browser = await launch(); });
after(async () => {
  await browser?.close();
  for (const dir of folders) rmSync(dir, { recursive: true, force: true });
});

/** Records `app` for its first `seconds` of simulated time; returns its recording and its page's file:// URL. */
async function record(app, seconds) {
  const dir = mkdtempSync(join(tmpdir(), `cobra-shapes-${app}-`));
  folders.push(dir);
  const args = ['run', join(COBRA_SOURCE_DIR, 'apps', app), '--quiet', '--time-limit', String(seconds), '--report', dir];
  try {
    await promisify(execFile)(COBRA_BIN, args, { maxBuffer: 1 << 24 });
  } catch (err) { // the time limit ends the run unfinished (exit status 1): the recording is written
    if (!/time limit [\d.]+ s reached/.test(err.stderr ?? '')) throw err;
  }
  const recording = JSON.parse(readFileSync(join(dir, 'studio', 'recording.json'), 'utf8'));
  return { recording, url: pathToFileURL(join(dir, 'studio', 'index.html')).href };
}

/** Vertices: three keeps them as 32-bit floats, so each must be cobra's number rounded to one. */
function sameVertices(got, want, what) {
  assert.equal(got.length, want.length, `${what}: ${got.length} numbers, expected ${want.length}`);
  got.forEach((v, i) => assert.equal(v, Math.fround(want[i]), `${what}[${i}] = ${v}, cobra sent ${want[i]}`));
}

function near(got, want, what) {
  assert.equal(got.length, want.length, `${what}: ${got.length} numbers, expected ${want.length}`);
  got.forEach((v, i) => assert.ok(Math.abs(v - want[i]) <= TOLERANCE, `${what}[${i}] = ${v}, cobra sent ${want[i]}`));
}

/** Each mesh of the extra `name`: its world position, quaternion and geometry parameters. */
function readShapes(page, name) {
  return page.evaluate((extra) => {
    const group = window.cobraStudio.scene.getObjectByName(extra);
    group.updateMatrixWorld(true);
    return group.children.map((mesh) => {
      const p = mesh.getWorldPosition(mesh.position.clone());
      const q = mesh.getWorldQuaternion(mesh.quaternion.clone());
      return { name: mesh.name, position: p.toArray(), quaternion: q.toArray(), parameters: { ...mesh.geometry.parameters } };
    });
  }, name);
}

const extraOf = (model, name) => model.extras.find((e) => e.name === name);

test('puncturing: the tumour sphere, the forbidden capsules and the tissue layers are where cobra sent them', { skip, timeout: 180000 }, async (t) => {
  const { recording, url } = await record('puncturing', 1);
  const { page, errors } = await openStudio(browser, url, t);

  const tumour = extraOf(recording.model, 'tumour');
  assert.equal(tumour.kind, 'spheres');
  assert.equal(tumour.shapes.length, 1);
  const [sphere] = await readShapes(page, 'tumour');
  near([...sphere.position, sphere.parameters.radius], tumour.shapes[0], 'tumour centre, radius');

  const forbidden = extraOf(recording.model, 'forbidden');
  assert.equal(forbidden.kind, 'capsules');
  assert.ok(forbidden.shapes.length >= 2, 'the rib and the vessel');
  const capsules = await readShapes(page, 'forbidden');
  assert.equal(capsules.length, forbidden.shapes.length);
  capsules.forEach((c, i) => { // three: `height` is the capsule's middle section
    near([...axisEnds(c, c.parameters.height), c.parameters.radius], forbidden.shapes[i], `forbidden[${i}] a, b, radius`);
  });

  const layers = extraOf(recording.model, 'layers');
  assert.equal(layers.kind, 'boxes');
  assert.equal(layers.shapes.length, 4, 'skin, fat, muscle, kidney');
  const boxes = await readShapes(page, 'layers');
  boxes.forEach((box, i) => {
    const { width, height, depth } = box.parameters;
    near([...box.position, ...box.quaternion, width, height, depth], layers.shapes[i], `layers[${i}] pose, size`);
  });
  assert.deepEqual(errors, []);
});

/** The axis' end points [a, b] of a mesh built along its local y (three's capsules and cylinders). */
function axisEnds(mesh, length) {
  const [x, y, z, w] = mesh.quaternion;
  const axis = [2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)];
  return [-1, 1].flatMap((sign) => mesh.position.map((v, k) => v + sign * axis[k] * length / 2));
}

test('puma260: the contact surface is the cylinder cobra sent', { skip, timeout: 180000 }, async (t) => {
  const { recording, url } = await record('puma260', 1);
  const { page, errors } = await openStudio(browser, url, t);
  const surface = extraOf(recording.model, 'surface');
  assert.equal(surface.kind, 'cylinders');
  const [cylinder] = await readShapes(page, 'surface');
  near([...axisEnds(cylinder, cylinder.parameters.height), cylinder.parameters.radiusTop], surface.shapes[0], 'surface a, b, radius');
  assert.equal(cylinder.parameters.radiusBottom, cylinder.parameters.radiusTop);
  assert.deepEqual(errors, []);
});

test('suturing: the wound edges are two lines, the thread and the stitches are the frame\'s points', { skip, timeout: 180000 }, async (t) => {
  const { recording, url } = await record('suturing', 20);
  const { page, errors } = await openStudio(browser, url, t);
  const shownT = await page.evaluate(() => window.cobraStudio.seek(19));
  const frame = recording.frames.find((f) => f.t === shownT);
  const lines = await page.evaluate(() => {
    const points = (name) => {
      const object = window.cobraStudio.scene.getObjectByName(name);
      return { type: object.type, xyz: Array.from(object.geometry.attributes.position?.array ?? []) };
    };
    return { right: points('wound_edges[0]'), left: points('wound_edges[1]'), thread: points('thread[0]'), stitches: points('stitches') };
  });
  const edges = frame.extras.wound_edges.points;
  assert.ok(edges.length >= 4, 'both edges');
  assert.equal(lines.right.type, 'Line');
  sameVertices(lines.right.xyz, edges.filter((_, k) => k % 2 === 0).flat(), 'right edge');
  sameVertices(lines.left.xyz, edges.filter((_, k) => k % 2 === 1).flat(), 'left edge');
  assert.ok(frame.extras.thread.points.length >= 3, 'a stitch made by 19 s: skin points and the tip');
  sameVertices(lines.thread.xyz, frame.extras.thread.points.flat(), 'thread');
  assert.equal(lines.stitches.type, 'LineSegments');
  assert.equal(frame.extras.stitches.points.length, 6, 'one complete stitch: two halves and the crossing');
  sameVertices(lines.stitches.xyz, frame.extras.stitches.points.flat(), 'stitches');
  assert.deepEqual(errors, []);
});
