// Shared by the studio and editor screenshot scripts: the arguments URL OUT.png [EXTRA], a
// Chromium page (studio/web/test/browser.mjs: npm ci in studio/web first) of `viewport` at URL,
// `shoot(page, out, extra)` and the page's errors on stderr.
import { launch } from '../../studio/web/test/browser.mjs';

export async function screenshotPage(usage, viewport, shoot) {
  const [url, out, extra] = process.argv.slice(2);
  if (!url || !out) {
    console.error(`usage: ${usage}`);
    process.exit(2);
  }
  const browser = await launch();
  try {
    const page = await browser.newPage({ viewport });
    const errors = [];
    page.on('pageerror', (err) => errors.push(err.message));
    await page.goto(url);
    await shoot(page, out, extra);
    if (errors.length) console.error(`page errors: ${errors.join('; ')}`);
    console.log(`saved ${out}`);
  } finally {
    await browser.close();
  }
}
