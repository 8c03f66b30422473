// The surgeon's console against cobra itself: after a fault the charts' reactions are
// offered as choices and pressing one moves the chart; a studio table naming a port the
// application lacks is the same one line in the page and on stderr; a live page and a replay end
// with how the run ended. Needs COBRA_BIN and COBRA_SOURCE_DIR (CTest sets both).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { launch, openStudio } from './browser.mjs';
import { runCobra, startCobra, stopCobras } from './cobra_process.mjs';

const { COBRA_BIN, COBRA_SOURCE_DIR } = process.env;
const skip = !COBRA_BIN || !COBRA_SOURCE_DIR ? 'COBRA_BIN and COBRA_SOURCE_DIR not set (CTest sets them)' : false;
const SOURCE = COBRA_SOURCE_DIR ?? '';
const APP = join(SOURCE, 'apps', 'puncturing');
const FAULTS = join(SOURCE, 'apps', 'puncturing', 'test', 'faults');
let browser;

before(async () => { if (!skip) browser = await launch(); });
after(async () => {
  stopCobras();
  await browser?.close();
});

const cell = (page, table, key) => page.locator(`#${table} tr[data-key="${key}"] td:last-child`);
const waitForCell = (page, table, key, text, timeout = 60000) => page.waitForFunction(
  ([tb, k, want]) => document.querySelector(`#${tb} tr[data-key="${k}"] td:last-child`)?.textContent === want,
  [table, key, text], { timeout });
const enabled = (page) => page.locator('#inputs button:not([disabled])').allInnerTexts();

test('after a fault the console offers the charts\' reactions as choices and a takeover moves the needle chart', { skip, timeout: 240000 }, async (t) => {
  // planner_fails_once.lua: the needle planner fails its first plan (MakeRoomForProbe): the needle
  // chart waits in WaitReaction for the surgeon.
  const { url } = await startCobra(['run', APP, '--studio', '--interactive', '--quiet', '--pace', '4',
    '--faults', join(FAULTS, 'planner_fails_once.lua')]);
  const { page, errors } = await openStudio(browser, url, t);

  await waitForCell(page, 'charts', 'needle', 'root.WaitIceballConfig');
  assert.deepEqual(await enabled(page), ['Iceball configured'], 'only the input the needle chart waits for');
  const first = page.locator('#choices .choice-row[data-chart="needle"]');
  assert.equal(await first.locator('.choice-what').innerText(), 'needle waits in root.WaitIceballConfig');
  assert.deepEqual(await page.locator('#states details[data-chart="needle"] li.active').evaluateAll((l) => l.map((e) => e.dataset.path)),
    ['root', 'root.WaitIceballConfig']);
  await first.getByRole('button', { name: 'Iceball configured' }).click();

  await waitForCell(page, 'charts', 'needle', 'root.WaitReaction');
  const choices = page.locator('#choices .choice-row[data-chart="needle"]');
  await choices.getByRole('button', { name: 'Take over (teleoperation)' }).waitFor();
  assert.deepEqual(await choices.locator('button').allInnerTexts(), ['Recover (after a fault)', 'Take over (teleoperation)']);
  assert.match(await choices.locator('.choice-what').innerText(),
    /^needle waits in root\.WaitReaction after NeedlePlanner: e_plan_failed at \d+\.\d\d s$/);
  assert.deepEqual(await enabled(page), ['Recover (after a fault)', 'Take over (teleoperation)']);
  assert.equal(await page.locator('#choices-section').isVisible(), true);
  assert.equal(await cell(page, 'deployments', 'deployment needle').innerText(), 'needle_autonomous_planning');

  await choices.getByRole('button', { name: 'Take over (teleoperation)' }).click();
  await waitForCell(page, 'charts', 'needle', 'root.NeedleTeleoperation.TeleoperationActive', 30000);
  await waitForCell(page, 'deployments', 'deployment needle', 'needle_teleoperated', 30000);
  assert.deepEqual(await enabled(page), ['Teleoperation done']);
  assert.deepEqual(await page.locator('#states details[data-chart="needle"] li.active').evaluateAll((l) => l.map((e) => e.dataset.path)),
    ['root', 'root.NeedleTeleoperation', 'root.NeedleTeleoperation.TeleoperationActive']);
  // The probe's scope keeps its own deployment and configuration.
  assert.match(await cell(page, 'deployments', 'deployment probe').innerText(), /^probe_autonomous_/);
  assert.match(await cell(page, 'deployments', 'configuration probe').innerText(), /^probe_/);
  assert.equal(await page.locator('#error').isHidden(), true, await page.locator('#error').innerText());
  assert.deepEqual(errors, []);
});

test('a studio table naming a port the application lacks: the page shows the line cobra prints on stderr', { skip, timeout: 120000 }, async () => {
  const app = join(SOURCE, 'studio', 'test', 'apps', 'bad_port.lua');
  const { url, stderr } = await startCobra(['run', app, '--studio', '--quiet']);
  const deadline = Date.now() + 30000;
  while (!stderr().includes('\n') && Date.now() < deadline) await new Promise((r) => setTimeout(r, 50));
  const line = stderr().split('\n')[0];
  assert.equal(line, `cobra: ${app}:6: run.studio.signals: component 'Gain' has no port 'outt'; did you mean 'out'? known output ports: events, out`);
  const page = await browser.newPage();
  try {
    await page.goto(url);
    const banner = page.locator('#error');
    await banner.waitFor({ state: 'visible', timeout: 15000 });
    assert.equal(await banner.textContent(), line);
  } finally {
    await page.close();
  }
});

test('live: a page that comes after the run ended shows how it ended, as cobra run printed it', { skip, timeout: 120000 }, async (t) => {
  const app = join(SOURCE, 'studio', 'test', 'apps', 'threshold_studio.lua');
  const { url, stdout } = await startCobra(['run', app, '--studio', '--quiet']);
  const deadline = Date.now() + 30000;
  while (!/^completed in /m.test(stdout()) && Date.now() < deadline) await new Promise((r) => setTimeout(r, 50));
  const line = /^completed in \d+\.\d{3} s$/m.exec(stdout())?.[0];
  assert.ok(line, `no end line in:\n${stdout()}`);
  const { page, errors } = await openStudio(browser, url, t);
  await page.locator('#end-section').waitFor({ state: 'visible', timeout: 15000 });
  assert.equal(await cell(page, 'end', 'outcome').textContent(), 'completed');
  assert.equal(await cell(page, 'end', 'exit status').textContent(), '0');
  assert.equal(await cell(page, 'end', 'cobra run').textContent(), line);
  assert.equal(await cell(page, 'end', 'final task').textContent(), 'root.done');
  assert.equal(await page.locator('#choices-section').isHidden(), true, 'a chart in its done state waits for nothing');
  assert.deepEqual(errors, []);
});

test('a replay ends with how the run ended: outcome, exit status, the line cobra run printed and the final states', { skip, timeout: 240000 }, async (t) => {
  const dir = mkdtempSync(join(tmpdir(), 'cobra-studio-console-'));
  t.after(() => rmSync(dir, { recursive: true, force: true }));
  // planner_fails_again.lua: the same failure after the reaction: a safe stop, exit status 1.
  const run = await runCobra(['run', APP, '--quiet', '--report', dir, '--faults', join(FAULTS, 'planner_fails_again.lua')]);
  assert.equal(run.status, 1, run.stderr);
  const line = run.stderr.split('\n').find((l) => l.startsWith('cobra run: '));
  assert.match(line, /^cobra run: safe stop: needle chart stopped safely in root\.MakeRoomForProbe: NeedlePlanner: e_plan_failed at/);
  const recording = JSON.parse(readFileSync(join(dir, 'studio', 'recording.json'), 'utf8'));
  assert.equal(recording.end.line, line);

  const { page, errors } = await openStudio(browser, pathToFileURL(join(dir, 'studio', 'index.html')).href, t);
  await page.evaluate(() => window.cobraStudio.seek(1));
  assert.equal(await page.locator('#end-section').isHidden(), true, 'the outcome shows only at the end of the timeline');
  const last = await page.evaluate(() => window.cobraStudio.seek(1e9));
  assert.ok(last >= recording.end.t - 1 / 30, `the last frame at ${last} s, the run ended at ${recording.end.t} s`);
  assert.equal(await page.locator('#end-section').isVisible(), true);
  assert.equal(await cell(page, 'end', 'outcome').innerText(), 'safe stop');
  assert.equal(await cell(page, 'end', 'exit status').innerText(), '1');
  // textContent: innerText folds the runs of spaces the line has ("at   4.009 s").
  assert.equal(await cell(page, 'end', 'cobra run').textContent(), line);
  assert.equal(await cell(page, 'end', 'final needle').innerText(), 'root.SafeStop');
  assert.equal(await cell(page, 'end', 'final us').innerText(), 'root.SafeStop');
  assert.equal(await page.locator('#outcome').textContent(), `outcome: safe stop — ${recording.end.message}`);
  assert.deepEqual(errors, []);
});
