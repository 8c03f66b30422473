// Saves PNG screenshots of the studio page (headless Chromium, 1280x800).
//   node tools/screenshots.mjs --url URL --out DIR [--at AT1,AT2,...] [--names N1,N2,...]
//   node tools/screenshots.mjs --url URL --out DIR --phases puncturing   (A.png ... H.png, its camera)
//   --camera X,Y,Z,TX,TY,TZ: the camera at X,Y,Z looking at TX,TY,TZ (m, world), else the fitted view
//   node tools/screenshots.mjs --fixture live|replay --out DIR [...]     (the test fixture server)
// URL: the line `cobra run ... --studio` / `cobra studio RUN_DIR` prints, or file://.../index.html
// of a run folder's studio/. AT: a time T [s] or SOURCE:EVENT[+DT] (DT s after the recording's
// first event EVENT of SOURCE, e.g. needle:root.InsertingNeedles.PenetratingSkin+2). Replay: the
// timeline is moved to each; live: one shot T s of wall clock after the first frame.
// Files: DIR/<name>.png, name from --names (else the moment, e.g. t_12.50).
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import { launch } from '../test/browser.mjs';
import { startFixtureServer } from '../test/fixture_server.mjs';
import { PUNCTURING_CAMERA, PUNCTURING_PHASES, parseAt, shoot, waitForStudio } from './shots.mjs';

const fail = (message) => {
  console.error(`screenshots: ${message}`);
  process.exit(2);
};
const { values } = parseArgs({
  options: {
    url: { type: 'string' }, fixture: { type: 'string' }, out: { type: 'string' },
    at: { type: 'string', default: '0' }, names: { type: 'string', default: '' }, phases: { type: 'string' },
    camera: { type: 'string' },
  },
});
if (!values.out || !(values.url || values.fixture)) fail('expected --out DIR and --url URL or --fixture live|replay');
if (values.phases !== undefined && values.phases !== 'puncturing') fail(`--phases '${values.phases}': expected puncturing`);
let moments;
let names;
try {
  const entries = values.phases ? Object.values(PUNCTURING_PHASES) : values.at.split(',');
  moments = entries.map(parseAt);
  names = values.phases ? Object.keys(PUNCTURING_PHASES) : (values.names ? values.names.split(',') : moments.map((m) => m.label));
} catch (err) {
  fail(err.message);
}
if (names.length !== moments.length) fail(`${names.length} --names for ${moments.length} --at moments`);
let camera = values.phases ? PUNCTURING_CAMERA : undefined;
if (values.camera !== undefined) {
  const v = values.camera.split(',').map(Number);
  if (v.length !== 6 || !v.every(Number.isFinite)) fail(`--camera '${values.camera}': expected 6 numbers X,Y,Z,TX,TY,TZ (m)`);
  camera = { position: v.slice(0, 3), target: v.slice(3) };
}
mkdirSync(values.out, { recursive: true });
const server = values.fixture ? await startFixtureServer(values.fixture) : null;
const browser = await launch();
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(server ? server.pageUrl : values.url);
  await waitForStudio(page);
  for (const { file, t } of await shoot(page, moments, (i) => join(values.out, `${names[i]}.png`), camera)) {
    console.log(`${file}: t = ${t ?? 'no frame'}`);
  }
} catch (err) {
  console.error(`screenshots: ${err.message}`);
  process.exitCode = 1;
} finally {
  await browser.close();
  await server?.close();
}
