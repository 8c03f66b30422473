// Saves a full-page PNG of a run report (report.html of `cobra run APP --report DIR`), rendered by
// headless Chromium (Debian's, driven by playwright-core from studio/web/node_modules).
//   node tools/screenshots/report.mjs --page DIR/report.html --out FILE.png [--width PX]
// Exit status 2 with a message when an argument is missing, the page cannot be rendered, or a text
// of a figure reaches beyond its SVG as Chromium lays it out (a title or legend that does not fit).
import { createRequire } from 'node:module';
import { existsSync } from 'node:fs';
import { dirname, resolve } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { parseArgs } from 'node:util';

const here = dirname(fileURLToPath(import.meta.url));
const fail = (message) => {
  console.error(`screenshots/report: ${message}`);
  process.exit(2);
};
const { values } = parseArgs({
  options: { page: { type: 'string' }, out: { type: 'string' }, width: { type: 'string', default: '1100' } },
});
if (!values.page || !values.out) fail('expected --page DIR/report.html --out FILE.png');
if (!existsSync(values.page)) fail(`${values.page}: no such page (run cobra run APP --report DIR first)`);
const width = Number(values.width);
if (!Number.isInteger(width) || width < 320) fail(`--width '${values.width}': expected whole px, at least 320`);

// playwright-core lives in the studio's node_modules (installed by ./do setup).
const require = createRequire(resolve(here, '../../studio/web/package.json'));
const { chromium } = require('playwright-core');
const executablePath = process.env.COBRA_CHROMIUM ?? '/usr/bin/chromium';
if (!existsSync(executablePath)) fail(`${executablePath}: no Chromium (./do setup installs it, or set COBRA_CHROMIUM)`);
const browser = await chromium.launch({ executablePath });
try {
  const page = await browser.newPage({ viewport: { width, height: 900 } });
  const errors = [];
  page.on('pageerror', (err) => errors.push(err.message));
  await page.goto(pathToFileURL(resolve(values.page)).href);
  // Every text of every figure inside its SVG, as Chromium lays it out (cobra::plot measures text
  // by estimated glyph widths; this checks the estimate with the real font).
  const overflows = await page.evaluate(() => {
    const out = [];
    for (const svg of document.querySelectorAll('svg')) {
      const frame = svg.getBoundingClientRect();
      for (const text of svg.querySelectorAll('text')) {
        const box = text.getBoundingClientRect();  // on the page, rotated labels too
        if (box.left < frame.left - 0.5 || box.right > frame.right + 0.5 || box.top < frame.top - 0.5 ||
            box.bottom > frame.bottom + 0.5)
          out.push(`'${text.textContent}' (x ${(box.left - frame.left).toFixed(0)}..${(box.right - frame.left).toFixed(0)}, ` +
                   `y ${(box.top - frame.top).toFixed(0)}..${(box.bottom - frame.top).toFixed(0)} of ${frame.width.toFixed(0)} x ${frame.height.toFixed(0)} px)`);
      }
    }
    return out;
  });
  if (overflows.length) fail(`${values.page}: text beyond its figure: ${overflows.join(', ')}`);
  await page.screenshot({ path: values.out, fullPage: true });
  if (errors.length) fail(`${values.page}: ${errors.join('; ')}`);
} finally {
  await browser.close();
}
console.log(values.out);
