// End to end against cobra itself (the studio's acceptance): the page served by
// `cobra run apps/puncturing --studio --interactive` and by `cobra studio RUN_DIR`.
// Needs COBRA_BIN (the cobra tool) and COBRA_SOURCE_DIR (the repo); CTest passes both, and
// registers this file only in a tree that has the studio server (studio/CMakeLists.txt). The
// replay test saves the puncturing phases A-H (thesis Fig. 4.22) as A.png ... H.png in
// COBRA_STUDIO_SHOTS (CTest: build/<preset>/studio-phases), else in a temporary folder.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, mkdtempSync, readFileSync, rmSync, statSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import WebSocket from 'ws';
import { launch, openStudio, readLinks, linkError, countDrawnPixels } from './browser.mjs';
import { runCobra, startCobra, stopCobras } from './cobra_process.mjs';
import { PUNCTURING_CAMERA, PUNCTURING_PHASES, parseAt, shoot } from '../tools/shots.mjs';

const { COBRA_BIN, COBRA_SOURCE_DIR } = process.env;
const skip = !COBRA_BIN || !COBRA_SOURCE_DIR ? 'COBRA_BIN and COBRA_SOURCE_DIR not set (CTest sets them)' : false;
const APP = COBRA_SOURCE_DIR ? join(COBRA_SOURCE_DIR, 'apps', 'puncturing') : '';
const BACKGROUND = [0x1d, 0x21, 0x26];
let browser;

/** Runs cobra to its end; rejects with its output when it fails. */
async function runCobraOk(args) {
  const { status, stdout, stderr } = await runCobra(args);
  if (status !== 0) throw new Error(`cobra ${args.join(' ')}: exit ${status}\n${stdout}${stderr}`);
}

before(async () => { if (!skip) browser = await launch(); });
after(async () => {
  stopCobras();
  await browser?.close();
});

test('live: the page renders, links equal the streamed FK, the token is required, buttons drive the needle chart', { skip, timeout: 240000 }, async (t) => {
  const { url } = await startCobra(['run', APP, '--studio', '--interactive', '--quiet', '--pace', '4']);
  const token = new URL(url).searchParams.get('token');
  const origin = new URL(url).origin;

  assert.equal((await fetch(`${origin}/api/model`)).status, 403);
  assert.equal((await fetch(`${origin}/api/model?token=${'0'.repeat(32)}`)).status, 403);
  const refused = await new Promise((resolve) => {
    const ws = new WebSocket(`${origin.replace('http', 'ws')}/ws`);
    ws.on('unexpected-response', (_req, res) => resolve(res.statusCode));
    ws.on('open', () => resolve('open'));
    ws.on('error', () => {});
  });
  assert.equal(refused, 403, 'a WebSocket upgrade without the token');

  // A client of its own collects the frames the server streams, to compare the page's links with.
  const frames = new Map();
  const socket = new WebSocket(`${origin.replace('http', 'ws')}/ws?token=${token}`);
  socket.on('message', (data) => {
    const msg = JSON.parse(String(data));
    if (msg.type === 'frame') frames.set(msg.t, msg);
  });
  t.after(() => socket.close());

  const { page, errors } = await openStudio(browser, url, t);
  const { drawn, total } = await countDrawnPixels(page, BACKGROUND);
  assert.ok(drawn > total * 0.02, `only ${drawn} of ${total} pixels differ from the background`);

  let matched = 0;
  for (let sample = 0; sample < 60 && matched < 5; sample += 1) {
    const shown = await readLinks(page);
    const frame = frames.get(shown.t);
    if (frame) {
      const worst = linkError(shown.links, frame);
      assert.ok(worst < 1e-6, `t = ${shown.t}: a link matrix element is off cobra's FK by ${worst}`);
      matched += 1;
    }
    await page.waitForTimeout(50);
  }
  assert.ok(matched >= 5, `only ${matched} of the page's frames were among the ${frames.size} the test's client received`);

  const needle = page.locator('#charts tr[data-key="needle"] td:last-child');
  assert.equal(await needle.innerText(), 'root.WaitIceballConfig');
  await page.waitForTimeout(1000);
  assert.equal(await needle.innerText(), 'root.WaitIceballConfig', 'the needle chart went on without the surgeon');
  await page.locator('#inputs').getByRole('button', { name: 'Iceball configured' }).click();
  await page.waitForFunction(() => document.querySelector('#charts tr[data-key="needle"] td:last-child').textContent === 'root.InsertingNeedles.WaitNeedleMounted', null, { timeout: 120000 });
  await page.locator('#inputs').getByRole('button', { name: 'Needle mounted' }).click();
  await page.waitForFunction(() => document.querySelector('#charts tr[data-key="needle"] td:last-child').textContent.startsWith('root.InsertingNeedles.MoveToSkin'), null, { timeout: 30000 });
  assert.equal(await page.locator('#error').isHidden(), true, await page.locator('#error').innerText());
  assert.deepEqual(errors, []);
});

test('replay: cobra studio RUN_DIR and the run folder\'s file:// page scrub the recorded run', { skip, timeout: 240000 }, async (t) => {
  const dir = mkdtempSync(join(tmpdir(), 'cobra-studio-e2e-'));
  t.after(() => rmSync(dir, { recursive: true, force: true }));
  await runCobraOk(['run', APP, '--quiet', '--report', dir]);
  const recording = JSON.parse(readFileSync(join(dir, 'studio', 'recording.json'), 'utf8'));
  const { url } = await startCobra(['studio', dir]);
  for (const address of [url, pathToFileURL(join(dir, 'studio', 'index.html')).href]) {
    const { page, errors } = await openStudio(browser, address, t);
    const start = await readLinks(page);
    for (const at of [20, 60, 100]) {
      const shownT = await page.evaluate((time) => window.cobraStudio.seek(time), at);
      const frame = recording.frames.find((f) => f.t === shownT);
      const now = await readLinks(page);
      assert.equal(now.t, shownT);
      assert.ok(linkError(now.links, frame) < 1e-6, `${address} t = ${shownT}: a link is off the recorded FK`);
      assert.ok(linkError(start.links, frame) > 1e-3, `${address} t = ${shownT}: no link moved since t = ${start.t}`);
    }
    assert.deepEqual(errors, []);
  }
  const shots = process.env.COBRA_STUDIO_SHOTS ?? join(dir, 'phases');
  mkdirSync(shots, { recursive: true });
  const { page } = await openStudio(browser, url, t);
  const names = Object.keys(PUNCTURING_PHASES);
  const saved = await shoot(page, Object.values(PUNCTURING_PHASES).map(parseAt), (i) => join(shots, `${names[i]}.png`), PUNCTURING_CAMERA);
  const times = saved.map((s) => s.t);
  assert.deepEqual(times, [...times].sort((a, b) => a - b), 'phases A-H are not in the order of the run');
  assert.equal(new Set(times).size, names.length, `phases A-H at ${times.join(', ')} s: two share a frame`);
  for (const { file } of saved) assert.ok(statSync(file).size > 10000, `${file}: no picture`);
});
