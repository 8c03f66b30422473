// One screenshot of cobra studio's console: node tools/screenshots/studio.mjs URL OUT.png [T]
// URL: a live or replay server's studio line (`cobra run APP --studio`, `cobra studio RUN_DIR`)
// or a run folder's file://.../studio/index.html. A replay is shown at T s (default: the middle of
// the run), a live run a second after its first frame came. The view is fitted to what is drawn.
import { waitForStudio } from '../../studio/web/tools/shots.mjs';
import { screenshotPage } from './page.mjs';

await screenshotPage('node tools/screenshots/studio.mjs URL OUT.png [T (s, a replay\'s moment)]', { width: 1440, height: 900 },
  async (page, out, at) => {
    if (await waitForStudio(page)) {
      const t = await page.evaluate((time) => window.cobraStudio.seek(time ?? (window.cobraStudio.end?.t ?? 0) / 2),
        at === undefined ? null : Number(at));
      console.log(`replay at t = ${t} s`);
    } else {
      await page.waitForTimeout(1000);
    }
    await page.locator('#fit').click();
    await page.waitForTimeout(300);
    await page.screenshot({ path: out });
  });
