// One screenshot of cobra studio's console: node tools/screenshots/studio.mjs URL OUT.png [T]
// URL: a live or replay server's studio line (`cobra run APP --studio`, `cobra studio RUN_DIR`)
// or a run folder's file://.../studio/index.html. A replay is shown at T s (default: the middle of
// the run), a live run as it is when its first frame came. The view is fitted to what is drawn.
// Uses studio/web's Chromium driver (studio/web/test/browser.mjs: npm ci in studio/web first).
import { launch } from '../../studio/web/test/browser.mjs';
import { waitForStudio } from '../../studio/web/tools/shots.mjs';

const [url, out, at] = process.argv.slice(2);
if (!url || !out) {
  console.error('usage: node tools/screenshots/studio.mjs URL OUT.png [T (s, a replay\'s moment)]');
  process.exit(2);
}
const browser = await launch();
try {
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  const errors = [];
  page.on('pageerror', (err) => errors.push(err.message));
  await page.goto(url);
  const replay = await waitForStudio(page);
  if (replay) {
    const t = await page.evaluate((time) => {
      const end = window.cobraStudio.end?.t ?? 0;
      return window.cobraStudio.seek(time ?? end / 2);
    }, at === undefined ? null : Number(at));
    console.log(`replay at t = ${t} s`);
  } else {
    await page.waitForTimeout(1000);
  }
  await page.locator('#fit').click();
  await page.waitForTimeout(300);
  await page.screenshot({ path: out });
  if (errors.length) console.error(`page errors: ${errors.join('; ')}`);
  console.log(`saved ${out}`);
} finally {
  await browser.close();
}
