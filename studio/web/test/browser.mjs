// Shared by the browser tests and the screenshot script: Debian's Chromium driven headless by
// playwright-core (WebGL through SwiftShader, as there is no GPU), and checks on the page.
import { chromium } from 'playwright-core';
import { existsSync } from 'node:fs';

export const CHROMIUM = process.env.COBRA_CHROMIUM ?? '/usr/bin/chromium';

export async function launch() {
  if (!existsSync(CHROMIUM)) {
    throw new Error(`${CHROMIUM}: no Chromium (install Debian's chromium with ./do setup, or set COBRA_CHROMIUM)`);
  }
  return chromium.launch({
    executablePath: CHROMIUM,
    args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-gpu-sandbox'],
  });
}

/**
 * Opens `url` in a 1280x800 page, closed after the node:test test `t`; resolves once the page
 * shows its first frame.
 */
export async function openStudio(browser, url, t) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  t.after(() => page.close());
  const errors = [];
  page.on('pageerror', (err) => errors.push(err.message));
  await page.goto(url);
  await page.waitForFunction(() => window.cobraStudio?.frameTime() != null, null, { timeout: 15000 });
  return { page, errors };
}

/** Every link's world matrix (column-major, as three stores it) with the frame time, read at once. */
export function readLinks(page) {
  return page.evaluate(() => {
    const studio = window.cobraStudio;
    const links = {};
    for (const robot of studio.model.robots) {
      links[robot.name] = Array.from({ length: robot.links }, (_, i) => Array.from(studio.linkObject(robot.name, i).matrixWorld.elements));
    }
    return { t: studio.frameTime(), links };
  });
}

/** The column-major 4x4 matrix of a pose [x,y,z,qx,qy,qz,qw] (unit quaternion), computed here. */
export function poseMatrix([x, y, z, qx, qy, qz, qw]) {
  return [
    1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qz * qw), 2 * (qx * qz - qy * qw), 0,
    2 * (qx * qy - qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qx * qw), 0,
    2 * (qx * qz + qy * qw), 2 * (qy * qz - qx * qw), 1 - 2 * (qx * qx + qy * qy), 0,
    x, y, z, 1,
  ];
}

/**
 * Largest element difference between the page's link matrices and a frame's link poses (links
 * the frame sent as nulls are skipped: the page hides them and keeps their last pose).
 */
export function linkError(pageLinks, frame) {
  let worst = 0;
  for (const [robot, state] of Object.entries(frame.robots)) {
    state.links.forEach((pose, i) => {
      if (pose.includes(null)) return;
      const want = poseMatrix(pose);
      pageLinks[robot][i].forEach((v, k) => { worst = Math.max(worst, Math.abs(v - want[k])); });
    });
  }
  return worst;
}

/**
 * Screenshots the 3D view and counts its pixels that differ from the background colour `rgb`
 * by more than 8 in a channel (the PNG is decoded by the page's own image decoder).
 */
export async function countDrawnPixels(page, rgb) {
  const png = await page.locator('#view canvas').screenshot();
  return page.evaluate(async ({ data, bg }) => {
    const image = new Image();
    image.src = `data:image/png;base64,${data}`;
    await image.decode();
    const canvas = document.createElement('canvas');
    canvas.width = image.width;
    canvas.height = image.height;
    const ctx = canvas.getContext('2d');
    ctx.drawImage(image, 0, 0);
    const px = ctx.getImageData(0, 0, image.width, image.height).data;
    let drawn = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (Math.abs(px[i] - bg[0]) > 8 || Math.abs(px[i + 1] - bg[1]) > 8 || Math.abs(px[i + 2] - bg[2]) > 8) drawn += 1;
    }
    return { drawn, total: px.length / 4 };
  }, { data: png.toString('base64'), bg: rgb });
}
