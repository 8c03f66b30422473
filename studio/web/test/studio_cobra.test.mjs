// The studio against cobra on each task: the Puma 260 drawn from its kinematics (its links where
// the recorded frames put them, and pixels that are the arm's), the waiting banner only when a
// person is asked (never in a run its script answers, nor in a replay), a page opened mid-run
// with the events and plot history so far. Keeps a screenshot of each task (puncturing, suturing,
// Puma 260) in COBRA_STUDIO_SHOTS (CTest: build/<preset>/studio-shots), else a temporary folder.
// Needs COBRA_BIN and COBRA_SOURCE_DIR (CTest sets both).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, mkdtempSync, readFileSync, rmSync, statSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { launch, openStudio, readLinks, linkError, countDrawnPixels } from './browser.mjs';
import { runCobra, startCobra, stopCobras } from './cobra_process.mjs';

const { COBRA_BIN, COBRA_SOURCE_DIR } = process.env;
const skip = !COBRA_BIN || !COBRA_SOURCE_DIR ? 'COBRA_BIN and COBRA_SOURCE_DIR not set (CTest sets them)' : false;
const SOURCE = COBRA_SOURCE_DIR ?? '';
const BACKGROUND = [0x1d, 0x21, 0x26];
let browser;
let shots;

before(async () => {
  if (skip) return;
  browser = await launch();
  shots = process.env.COBRA_STUDIO_SHOTS ?? mkdtempSync(join(tmpdir(), 'cobra-studio-shots-'));
  mkdirSync(shots, { recursive: true });
});
after(async () => {
  stopCobras();
  await browser?.close();
});

/** Runs APP with --report into a temporary folder (removed after `t`); resolves to the folder. */
async function recordRun(t, app, extra = []) {
  const dir = mkdtempSync(join(tmpdir(), 'cobra-studio-task-'));
  t.after(() => rmSync(dir, { recursive: true, force: true }));
  const run = await runCobra(['run', join(SOURCE, 'apps', app), '--quiet', '--report', dir, ...extra]);
  assert.equal(run.status, 0, `cobra run apps/${app}: ${run.stdout}${run.stderr}`);
  return dir;
}

/** Saves the page, fitted to what is drawn, as `name`.png in the shots folder. */
async function keepShot(page, name) {
  await page.locator('#fit').click();
  const file = join(shots, `${name}.png`);
  await page.screenshot({ path: file });
  assert.ok(statSync(file).size > 10000, `${file}: no picture`);
}

test('the Puma 260 is drawn from its kinematics: links on the recorded frames, its pixels the arm\'s', { skip, timeout: 240000 }, async (t) => {
  const dir = await recordRun(t, 'puma260');
  const recording = JSON.parse(readFileSync(join(dir, 'studio', 'recording.json'), 'utf8'));
  const { url } = await startCobra(['studio', dir]);
  const { page, errors } = await openStudio(browser, url, t);
  const puma = await page.evaluate(() => ({
    robot: window.cobraStudio.model.robots.find((r) => r.name === 'puma'),
    shapes: window.cobraStudio.model.objects.filter((o) => o.robot === 'puma').length,
  }));
  assert.equal(puma.robot.links, 8, 'DH frames 0..6 and the tool');
  assert.equal(puma.shapes, 12, 'six joint housings, the legs along d1, a2, d3, d4, d6 and the tool');
  const shownT = await page.evaluate((time) => window.cobraStudio.seek(time), recording.end.t / 2);
  const shown = await readLinks(page);
  assert.ok(linkError(shown.links, recording.frames.find((f) => f.t === shownT)) < 1e-6, 'a link is off the recorded frame');
  await keepShot(page, 'puma260');
  // The arm's own pixels: the same view with its links shrunk to nothing has far fewer drawn.
  const withArm = await countDrawnPixels(page, BACKGROUND);
  await page.evaluate(() => {
    for (let i = 0; i < 8; i += 1) window.cobraStudio.linkObject('puma', i).scale.setScalar(1e-6);
  });
  await page.evaluate((time) => window.cobraStudio.seek(time), shownT);
  const without = await countDrawnPixels(page, BACKGROUND);
  assert.ok(withArm.drawn - without.drawn > withArm.total * 0.01,
    `the arm covers only ${withArm.drawn - without.drawn} of ${withArm.total} pixels`);
  assert.equal(await page.locator('#choices-section').isHidden(), true, 'a replay asks no one');
  assert.deepEqual(errors, []);
});

test('puncturing and suturing: the replays drawn mid-task, no one asked', { skip, timeout: 480000 }, async (t) => {
  for (const app of ['puncturing', 'suturing']) {
    const dir = await recordRun(t, app);
    const { url } = await startCobra(['studio', dir]);
    const { page, errors } = await openStudio(browser, url, t);
    const end = await page.evaluate(() => window.cobraStudio.end.t);
    // Every moment of the run: a chart waiting for an input is no reason to ask anyone in a replay.
    for (const at of [0.25, 0.5, 0.75]) {
      await page.evaluate((time) => window.cobraStudio.seek(time), end * at);
      assert.equal(await page.locator('#choices-section').isHidden(), true, `${app} at ${end * at} s`);
    }
    await page.evaluate((time) => window.cobraStudio.seek(time), end * 0.4);
    const { drawn, total } = await countDrawnPixels(page, BACKGROUND);
    assert.ok(drawn > total * 0.02, `${app}: only ${drawn} of ${total} pixels drawn`);
    await keepShot(page, app);
    assert.deepEqual(errors, []);
  }
});

test('a run its surgeon script answers: the buttons follow the charts, the waiting banner never shows', { skip, timeout: 240000 }, async (t) => {
  const { url } = await startCobra(['run', join(SOURCE, 'apps', 'puncturing'), '--studio', '--quiet', '--pace', '4']);
  const { page, errors } = await openStudio(browser, url, t);
  assert.equal(await page.evaluate(() => window.cobraStudio.model.interactive), false);
  // Until an input is accepted (a chart waits for the surgeon's script), the banner stays hidden.
  let offered = 0;
  for (let sample = 0; sample < 300 && offered < 3; sample += 1) {
    const enabled = await page.locator('#inputs button:not([disabled])').count();
    if (enabled > 0) offered += 1;
    assert.equal(await page.locator('#choices-section').isHidden(), true, `at ${await page.evaluate(() => window.cobraStudio.frameTime())} s`);
    await page.waitForTimeout(100);
  }
  assert.ok(offered >= 3, 'no chart waited for an input while the test watched');
  assert.deepEqual(errors, []);
});

test('a page opened mid-run shows the events and the plots from the run\'s start, each event once', { skip, timeout: 240000 }, async (t) => {
  const { url } = await startCobra(['run', join(SOURCE, 'apps', 'puncturing'), '--studio', '--quiet', '--pace', '4']);
  const origin = new URL(url).origin;
  const token = new URL(url).searchParams.get('token');
  // Wait until the run is 8 s on: the history holds what a page opened then has missed.
  let history = { frames: [], events: [] };
  for (let i = 0; i < 200 && (history.frames.at(-1)?.t ?? 0) < 8; i += 1) {
    await new Promise((resolve) => setTimeout(resolve, 100));
    history = await (await fetch(`${origin}/api/recording?token=${token}`)).json();
  }
  assert.ok(history.frames.at(-1).t >= 8, 'the run did not get to 8 s');
  assert.ok(history.frames[0].t < 0.1, `the history starts at ${history.frames[0].t} s`);
  const { page, errors } = await openStudio(browser, url, t);
  const times = await page.evaluate(() => window.cobraStudio.plotTimes());
  assert.ok(times[0] < 0.1 && times.at(-1) >= 8, `the plots hold ${times[0]} .. ${times.at(-1)} s`);
  assert.deepEqual(times, [...times].sort((a, b) => a - b), 'the plots\' frames in the order of the run');
  const log = await page.locator('#events li').evaluateAll((items) => items.map((li) => ({ t: Number(li.dataset.t), text: li.textContent })));
  for (const e of history.events.slice(0, 5)) {
    assert.ok(log.some((line) => line.text.includes(`${e.source}: ${e.name}`)), `the log lacks ${e.source}: ${e.name} at ${e.t} s`);
  }
  // Up to the history's last event the log is the history: none lost, none shown twice (the
  // socket's copies of those are dropped).
  const last = history.events.at(-1).t;
  assert.equal(log.filter((line) => line.t <= last).length, history.events.length, 'the log before the page came');
  await keepShot(page, 'puncturing-late-page');
  assert.deepEqual(errors, []);
});
