// The live page against the fixture server: the WebGL view draws, and every link's world matrix
// in three's scene graph equals the streamed frame's link pose (cobra's forward kinematics).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { loadFixtures } from './fixture_server.mjs';
import { openStudio, readLinks, linkError, countDrawnPixels } from './browser.mjs';
import { liveFixture } from './live_fixture.mjs';

const BACKGROUND = [0x1d, 0x21, 0x26];
const live = liveFixture();

test('the WebGL canvas shows the robots and the scene (non-background pixels)', async (t) => {
  const { page, errors } = await openStudio(live.browser, live.server.pageUrl, t);
  const { drawn, total } = await countDrawnPixels(page, BACKGROUND);
  assert.ok(drawn > total * 0.02, `only ${drawn} of ${total} pixels differ from the background`);
  assert.deepEqual(errors, []);
  assert.equal(await page.locator('#error').isHidden(), true);
});

test('each link world matrix equals the frame link pose within 1e-6 m', async (t) => {
  const { recording } = loadFixtures();
  const { page } = await openStudio(live.browser, live.server.pageUrl, t);
  const seen = new Set();
  for (let sample = 0; sample < 10; sample += 1) {
    const { t, links } = await readLinks(page);
    const frame = recording.frames.find((f) => f.t === t);
    assert.ok(frame, `the page shows t = ${t}, which is no fixture frame`);
    const worst = linkError(links, frame);
    assert.ok(worst < 1e-6, `t = ${t}: a link matrix element is off by ${worst}`);
    seen.add(t);
    await page.waitForTimeout(70);
  }
  assert.ok(seen.size >= 2, `the page showed only ${seen.size} distinct frame in 10 samples 70 ms apart`);
});

test('the console shows chart states, deployments, configurations and clearance of the frame', async (t) => {
  const { page } = await openStudio(live.browser, live.server.pageUrl, t);
  await page.waitForFunction(() => window.cobraStudio.frameTime() >= 1.6 && window.cobraStudio.frameTime() < 2.4);
  const text = await page.locator('#console').innerText();
  assert.match(text, /deployment task\s+execution/);
  assert.match(text, /configuration arm\s+admittance/);
  assert.match(await page.locator('#charts tr[data-key="task"]').innerText(), /task\s+Insert\.Advance/);
  assert.match(await page.locator('#clearance').innerText(), /^clearance -?\d+\.\d mm \(min 5\.0 mm\) (valid|INVALID)$/);
  assert.ok(await page.locator('#plots .uplot').count() >= 1, 'no plot is drawn for the first signal');
});

test('mesh objects (STL and OBJ, in mm) are fetched, parsed and scaled to m', async (t) => {
  const { page } = await openStudio(live.browser, live.server.pageUrl, t);
  for (const name of ['marker_stl', 'marker_obj']) {
    await page.waitForFunction((n) => window.cobraStudio.scene.getObjectByName(n).children.length > 0, name, { timeout: 10000 });
    const box = await page.evaluate((n) => {
      const holder = window.cobraStudio.scene.getObjectByName(n);
      let triangles = 0;
      holder.traverse((o) => { if (o.isMesh) triangles += o.geometry.attributes.position.count / 3; });
      const b = new holder.position.constructor(); // a three.js Vector3
      const bounds = { min: [Infinity, Infinity, Infinity], max: [-Infinity, -Infinity, -Infinity] };
      holder.updateMatrixWorld(true);
      holder.traverse((o) => {
        if (!o.isMesh) return;
        const p = o.geometry.attributes.position;
        for (let i = 0; i < p.count; i += 1) {
          const v = b.fromBufferAttribute(p, i).applyMatrix4(o.matrixWorld);
          ['x', 'y', 'z'].forEach((k, j) => {
            bounds.min[j] = Math.min(bounds.min[j], v[k]);
            bounds.max[j] = Math.max(bounds.max[j], v[k]);
          });
        }
      });
      return { triangles, bounds };
    }, name);
    assert.equal(box.triangles, 6, `${name}: triangles`);
    const want = { min: [-0.32, name === 'marker_stl' ? 0.28 : -0.32, 0.04], max: [-0.28, name === 'marker_stl' ? 0.32 : -0.28, 0.07] };
    for (const k of ['min', 'max']) {
      box.bounds[k].forEach((v, j) => assert.ok(Math.abs(v - want[k][j]) < 1e-9, `${name}: ${k}[${j}] = ${v}, expected ${want[k][j]}`));
    }
  }
});

test('ticking a signal adds its plot, unticking removes it', async (t) => {
  const { page } = await openStudio(live.browser, live.server.pageUrl, t);
  const titles = () => page.locator('#plots .u-title').allInnerTexts();
  assert.deepEqual(await titles(), ['arm.q1.deg [deg]']);
  await page.getByLabel('clearance.mm [mm]').check();
  assert.deepEqual(await titles(), ['arm.q1.deg [deg]', 'clearance.mm [mm]']);
  await page.getByLabel('arm.q1.deg [deg]').uncheck();
  assert.deepEqual(await titles(), ['clearance.mm [mm]']);
});
