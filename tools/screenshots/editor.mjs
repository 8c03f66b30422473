// One screenshot of cobra's deployment editor: node tools/screenshots/editor.mjs URL OUT.png [TAB]
// URL: the line `cobra edit APP` prints (`editor: http://...`). The page is shown once its project
// is drawn, on the base deployment or on the deployment tab TAB, the whole canvas in view.
import { screenshotPage } from './page.mjs';

await screenshotPage('node tools/screenshots/editor.mjs URL OUT.png [deployment tab]', { width: 1600, height: 1000 },
  async (page, out, tab) => {
    await page.waitForFunction(() => window.cobraEditor?.ready && window.cobraEditor.idle(), null, { timeout: 120000 });
    if (tab) await page.locator(`#tabs .tab.deployment[data-tab="${tab}"]`).click();
    // The whole canvas in one picture: a viewport as large as the drawn blocks.
    const extent = await page.locator('#canvas').evaluate((svg) => [Number(svg.getAttribute('width')), Number(svg.getAttribute('height'))]);
    await page.setViewportSize({ width: Math.min(extent[0] + 700, 4000), height: Math.min(extent[1] + 300, 3000) });
    await page.waitForTimeout(300);
    await page.screenshot({ path: out, fullPage: true });
  });
