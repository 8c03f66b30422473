// Saves PNG screenshots of the studio page (headless Chromium, 1280x800).
//   node tools/screenshots.mjs --url URL --out DIR [--at AT1,AT2,...] [--names N1,N2,...]
//   node tools/screenshots.mjs --fixture live|replay --out DIR [...]   (the test fixture server)
// URL: the line `cobra run ... --studio` / `cobra studio RUN_DIR` prints, or file://.../index.html
// of a run folder's studio/. Replay: one shot per time T [s] of --at (the timeline is moved
// there, AT: a time T or SOURCE:EVENT[+DT], DT s after the recording's first event EVENT of SOURCE,
// e.g. needle:root.InsertingNeedles.Insert+2); live: one shot per --at entry, T s of wall clock
// after the page showed its first frame.
// Files: DIR/<name>.png, name from --names (else the time, e.g. t_12.50).
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import { launch } from '../test/browser.mjs';
import { startFixtureServer } from '../test/fixture_server.mjs';

const { values } = parseArgs({
  options: {
    url: { type: 'string' }, fixture: { type: 'string' }, out: { type: 'string' },
    at: { type: 'string', default: '0' }, names: { type: 'string', default: '' },
  },
});
if (!values.out || !(values.url || values.fixture)) {
  console.error('screenshots: expected --out DIR and --url URL or --fixture live|replay');
  process.exit(2);
}
// Each --at entry: { t } or { source, event, dt }.
const AT = /^(?:(?<t>\d+(?:\.\d*)?)|(?<source>[^:,]+):(?<event>[^+,]+)(?:\+(?<dt>\d+(?:\.\d*)?))?)$/;
const times = values.at.split(',').map((entry) => {
  const m = AT.exec(entry.trim());
  if (!m) {
    console.error(`screenshots: --at entry '${entry}': expected a time [s] >= 0 or SOURCE:EVENT[+DT]`);
    process.exit(2);
  }
  const g = m.groups;
  return g.t !== undefined ? { t: Number(g.t), label: `t_${Number(g.t).toFixed(2)}` }
    : { source: g.source, event: g.event, dt: Number(g.dt ?? 0), label: `${g.source}_${g.event}${g.dt ? `+${g.dt}` : ''}` };
});
const names = values.names ? values.names.split(',') : times.map((at) => at.label);
if (names.length !== times.length) {
  console.error(`screenshots: ${names.length} --names for ${times.length} --at times`);
  process.exit(2);
}
mkdirSync(values.out, { recursive: true });
const server = values.fixture ? await startFixtureServer(values.fixture) : null;
const browser = await launch();
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(server ? server.pageUrl : values.url);
  await Promise.race([
    page.waitForFunction(() => window.cobraStudio?.frameTime() != null, null, { timeout: 30000 }),
    page.locator('#error').waitFor({ state: 'visible', timeout: 30000 }),
  ]);
  const replay = await page.evaluate(() => window.cobraStudio?.model.mode === 'replay');
  const start = Date.now();
  const events = await page.evaluate(() => window.cobraStudio?.events ?? []);
  for (const [i, at] of times.entries()) {
    let t = at.t;
    if (at.source !== undefined) {
      const hit = events.find((e) => e.source === at.source && e.name === at.event);
      if (!replay || !hit) {
        throw new Error(`--at ${at.source}:${at.event}: ${replay ? 'no such event in the recording' : 'events name times in replays only'}`);
      }
      t = hit.t + at.dt;
    }
    if (replay) await page.evaluate((time) => window.cobraStudio.seek(time), t);
    else await page.waitForTimeout(Math.max(0, start + t * 1000 - Date.now()));
    await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
    const file = join(values.out, `${names[i]}.png`);
    await page.screenshot({ path: file });
    const shown = await page.evaluate(() => window.cobraStudio?.frameTime() ?? null);
    console.log(`${file}: t = ${shown ?? 'no frame'}`);
  }
} catch (err) {
  console.error(`screenshots: ${err.message}`);
  process.exitCode = 1;
} finally {
  await browser.close();
  await server?.close();
}
