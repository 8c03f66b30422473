// Screenshots of the studio page at chosen moments, shared by tools/screenshots.mjs and the
// end-to-end test that saves the puncturing phases A-H (thesis §4.9, Fig. 4.22).

/**
 * Moments of the puncturing run's phases A-H (§4.9), as SOURCE:EVENT[+DT] of the needle chart
 * ('needle') and the ultrasound probe chart ('us') of apps/puncturing: A the initial poses,
 * B the UR5 moving to its planned pose, C the UR5 on the skin and the I-SUR moving to the
 * insertion point, D the insertion motion started, E the needle at the skin (penetration
 * configuration), F the insertion going on (insertion configuration), G the needle extracted and
 * the I-SUR on its collision-free way to the needle change pose, H the UR5 to its next pose.
 */
export const PUNCTURING_PHASES = {
  A: '0.5',
  B: 'us:root.MoveToSkin.Approach+2',
  C: 'needle:root.InsertingNeedles.MoveToSkin.Approach+8',
  D: 'needle:root.InsertingNeedles.MoveToSkin.Descend+0.3',
  E: 'needle:root.InsertingNeedles.PenetratingSkin+0.05',
  F: 'needle:root.InsertingNeedles.MoveToTumor+0.8',
  G: 'needle:root.InsertingNeedles.MoveToNeedleChange+5',
  H: 'us:root.NextProbePose+2',
};

/** A camera for the phases: behind the phantom, opposite the UR5, the I-SUR's needle in view (m). */
export const PUNCTURING_CAMERA = { position: [-0.8, 1.0, 0.85], target: [0.05, -0.1, 0.3] };

const AT = /^(?:(?<t>\d+(?:\.\d*)?)|(?<source>[^:,]+):(?<event>[^+,]+)(?:\+(?<dt>\d+(?:\.\d*)?))?)$/;

/** Parses a moment: a time T [s] or SOURCE:EVENT[+DT]; throws naming the entry if neither. */
export function parseAt(entry) {
  const m = AT.exec(entry.trim());
  if (!m) throw new Error(`moment '${entry}': expected a time [s] >= 0 or SOURCE:EVENT[+DT]`);
  const g = m.groups;
  return g.t !== undefined ? { t: Number(g.t), label: `t_${Number(g.t).toFixed(2)}` }
    : { source: g.source, event: g.event, dt: Number(g.dt ?? 0), label: `${g.source}_${g.event}${g.dt ? `+${g.dt}` : ''}` };
}

/** Waits until the page shows its first frame or an error; resolves to whether it is a replay. */
export async function waitForStudio(page) {
  await Promise.race([
    page.waitForFunction(() => window.cobraStudio?.frameTime() != null, null, { timeout: 30000 }),
    page.locator('#error').waitFor({ state: 'visible', timeout: 30000 }),
  ]);
  return page.evaluate(() => window.cobraStudio?.model.mode === 'replay');
}

/**
 * Saves one PNG per moment as `${file(i)}`: in a replay the timeline is moved to the moment (an
 * event's time + DT), live the moment is T s of wall clock from now. `camera` ({ position,
 * target }, optional) replaces the fitted view. Resolves to [{ file, t }], t the frame time shown.
 */
export async function shoot(page, moments, file, camera) {
  const replay = await page.evaluate(() => window.cobraStudio?.model.mode === 'replay');
  const events = await page.evaluate(() => window.cobraStudio?.events ?? []);
  const start = Date.now();
  const saved = [];
  for (const [i, at] of moments.entries()) {
    let t = at.t;
    if (at.source !== undefined) {
      const hit = events.find((e) => e.source === at.source && e.name === at.event);
      if (!replay || !hit) {
        throw new Error(`${at.source}:${at.event}: ${replay ? 'no such event in the recording' : 'events name times in replays only'}`);
      }
      t = hit.t + at.dt;
    }
    if (replay) await page.evaluate((time) => window.cobraStudio.seek(time), t);
    else await page.waitForTimeout(Math.max(0, start + t * 1000 - Date.now()));
    if (camera) await page.evaluate((c) => window.cobraStudio.setCamera(c.position, c.target), camera);
    await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
    await page.screenshot({ path: file(i) });
    saved.push({ file: file(i), t: await page.evaluate(() => window.cobraStudio?.frameTime() ?? null) });
  }
  return saved;
}
