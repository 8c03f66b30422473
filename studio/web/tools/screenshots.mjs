// Saves PNG screenshots of the studio page (headless Chromium, 1280x800).
//   node tools/screenshots.mjs --url URL --out DIR [--at T1,T2,...] [--names N1,N2,...]
//   node tools/screenshots.mjs --fixture live|replay --out DIR [...]   (the test fixture server)
// URL: the line `cobra run ... --studio` / `cobra studio RUN_DIR` prints, or file://.../index.html
// of a run folder's studio/. Replay: one shot per time T [s] of --at (the timeline is moved
// there); live: one shot per --at entry, T s of wall clock after the page showed its first frame.
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
const times = values.at.split(',').map(Number);
if (times.some((t) => !Number.isFinite(t) || t < 0)) {
  console.error(`screenshots: --at '${values.at}': expected times [s] >= 0 separated by commas`);
  process.exit(2);
}
const names = values.names ? values.names.split(',') : times.map((t) => `t_${t.toFixed(2)}`);
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
  for (const [i, t] of times.entries()) {
    if (replay) await page.evaluate((at) => window.cobraStudio.seek(at), t);
    else await page.waitForTimeout(Math.max(0, start + t * 1000 - Date.now()));
    await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
    const file = join(values.out, `${names[i]}.png`);
    await page.screenshot({ path: file });
    const shown = await page.evaluate(() => window.cobraStudio?.frameTime() ?? null);
    console.log(`${file}: t = ${shown ?? 'no frame'}`);
  }
} finally {
  await browser.close();
  await server?.close();
}
