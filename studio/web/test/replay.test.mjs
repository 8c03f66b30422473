// Replay: the timeline scrubs the recording's frames and the 3D view, the chart states and the
// event log follow; served by the (fixture) server and from the file system via recording.js.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { cpSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { startFixtureServer, loadFixtures, DIST } from './fixture_server.mjs';
import { launch, openStudio, readLinks, linkError } from './browser.mjs';

const { recording } = loadFixtures();
let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

async function scrubTo(page, index) {
  await page.locator('#scrub').fill(String(index));
  await page.waitForFunction((t) => window.cobraStudio.frameTime() === t, recording.frames[index].t);
}

/**
 * Scrubs to four frames (one with too little clearance, one where the probe's pose is null) and
 * checks the links, the tool's trail, the clearance's colour, the task chart and the greyed-out
 * events.
 */
async function checkScrubbing(page) {
  assert.equal(await page.locator('#scrub').getAttribute('max'), String(recording.frames.length - 1));
  const start = await readLinks(page);
  assert.equal(start.t, 0);
  assert.ok(linkError(start.links, recording.frames[0]) < 1e-6);
  const invalid = recording.frames.findIndex((f) => !f.clearance.valid);
  assert.ok(invalid > 0, 'the fixture has no frame with too little clearance');
  for (const index of [45, invalid, 90, recording.frames.length - 1]) {
    await scrubTo(page, index);
    const frame = recording.frames[index];
    const now = await readLinks(page);
    assert.ok(linkError(now.links, frame) < 1e-6, `frame ${index}: a link is off the recorded pose`);
    assert.ok(linkError(now.links, recording.frames[0]) > 0.01, `frame ${index}: the arm did not move from t = 0`);
    const trail = await page.evaluate(() => Array.from(window.cobraStudio.scene.getObjectByName('tool.trail').geometry.attributes.position.array));
    const want = recording.frames.slice(0, index + 1).flatMap((f) => f.extras.tool.points[0]);
    assert.equal(trail.length, want.length, `frame ${index}: the tool's trail has ${trail.length / 3} points, expected ${index + 1}`);
    assert.ok(trail.every((v, k) => Math.abs(v - want[k]) < 1e-6), `frame ${index}: the tool's trail is not the recorded tool points`);
    assert.equal(await page.locator('#clearance').getAttribute('class'), `clearance ${frame.clearance.valid ? 'valid' : 'invalid'}`);
    const lost = frame.robots.probe.links[1].includes(null);
    assert.equal(await page.evaluate(() => window.cobraStudio.linkObject('probe', 1).visible), !lost,
      `frame ${index}: the probe's link should be ${lost ? 'hidden (null pose)' : 'shown'}`);
    assert.match(await page.locator('#charts tr[data-key="task"]').innerText(), new RegExp(`task\\s+${frame.charts.task.replace('.', '\\.')}$`));
    const future = await page.locator('#events li.future').count();
    assert.equal(future, recording.events.filter((e) => e.t > frame.t + 1e-9).length);
  }
  assert.match(await page.locator('#outcome').innerText(), /^outcome: Completed — synthetic run finished$/);
  await scrubTo(page, 10);
  assert.equal(await page.locator('#outcome').innerText(), '');
}

test('replay from the server: scrubbing the timeline moves the robot and the states follow', async (t) => {
  const server = await startFixtureServer('replay');
  try {
    const { page, errors } = await openStudio(browser, server.pageUrl, t);
    assert.equal(await page.locator('#inputs button').first().isDisabled(), true);
    await checkScrubbing(page);
    assert.deepEqual(errors, []);
  } finally {
    await server.close();
  }
});

test('replay from the file system: index.html with recording.js needs no server', async (t) => {
  const dir = mkdtempSync(join(tmpdir(), 'cobra-studio-replay-'));
  try {
    cpSync(DIST, dir, { recursive: true });
    writeFileSync(join(dir, 'recording.js'), `window.COBRA_RECORDING = ${JSON.stringify(recording)};\n`);
    const { page, errors } = await openStudio(browser, pathToFileURL(join(dir, 'index.html')).href, t);
    await checkScrubbing(page);
    assert.deepEqual(errors, []);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

test('a file:// page without recording.js says what is missing', async () => {
  const dir = mkdtempSync(join(tmpdir(), 'cobra-studio-empty-'));
  try {
    cpSync(DIST, dir, { recursive: true });
    const page = await browser.newPage();
    await page.goto(pathToFileURL(join(dir, 'index.html')).href);
    await page.locator('#error').waitFor({ state: 'visible' });
    assert.match(await page.locator('#error').innerText(), /^recording\.js: not found beside index\.html/);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

test('Play runs through the recording and Pause stops it where it is', async (t) => {
  const server = await startFixtureServer('replay');
  try {
    const { page } = await openStudio(browser, server.pageUrl, t);
    // The replay plays on a clock the test moves: on the wall clock a loaded machine could let the
    // 4 s recording run to its end (and stop by itself) between two of the test's steps. An
    // installed clock still flows with the wall clock until it is paused: pause it (a minute
    // ahead, surely later than the clock's time however slow the machine) before Play.
    await page.clock.install();
    await page.clock.pauseAt(Date.now() + 60_000);
    const play = page.locator('#play');
    await play.click();
    assert.equal(await play.innerText(), 'Pause');
    await page.clock.runFor(700);
    const played = await page.evaluate(() => window.cobraStudio.frameTime());
    assert.ok(played >= 0.5 && played < 1, `after 0.7 s of play the replay is at ${played} s`);
    await play.click();
    assert.equal(await play.innerText(), 'Play');
    const paused = await page.evaluate(() => window.cobraStudio.frameTime());
    await page.clock.runFor(300);
    assert.equal(await page.evaluate(() => window.cobraStudio.frameTime()), paused);
    assert.equal(await page.locator('#scrub').inputValue(), String(recording.frames.findIndex((f) => f.t === paused)));
  } finally {
    await server.close();
  }
});
