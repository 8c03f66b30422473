// The editor page driven by clicks, shared by the fixture's browser tests and the end-to-end test
// against `cobra edit`: open the page, drop a type from the palette, draw a connection, set a
// property, and the thesis' Fig. 3.4 example (a trajectory generator feeding a variable admittance
// that commands a simulated robot, whose measured wrench, moved to the base frame by an equivalent
// wrench, and pose feed back).

/** Opens `url` in a 1280x800 page closed after test `t`; resolves once the editor has its project. */
export async function openEditor(browser, url, t) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  t.after(() => page.close());
  const errors = [];
  page.on('pageerror', (err) => errors.push(err.message));
  await page.goto(url);
  await page.waitForFunction(() => window.cobraEditor?.ready === true, null, { timeout: 30000 });
  return { page, errors };
}

/** Waits until the page has no request out and no validation due. */
export function settled(page) {
  return page.waitForFunction(() => window.cobraEditor.idle(), null, { timeout: 30000 });
}

/** Drags palette type `type` onto the canvas at (x, y) px and names the instance `name`. */
export async function place(page, type, name, x, y) {
  await page.locator('#palette-search').fill('');
  await page.locator(`summary[data-type="${type}"]`).dragTo(page.locator('#canvas'), { targetPosition: { x, y } });
  await page.locator('#name-input').fill(name);
  await page.locator('#name-ok').click();
  await page.locator(`#canvas g.block[data-name="${name}"]`).waitFor();
}

/** Clicks port `first` then port `second` ("Comp.port" each) and waits for the server's answer. */
export async function connect(page, first, second) {
  await page.locator(`#canvas g.port[data-port="${first}"] .handle`).click();
  await page.locator(`#canvas g.port[data-port="${second}"] .handle`).click();
  await settled(page);
}

/** Selects block `name` and types `text` into its property `property`. */
export async function setProperty(page, name, property, text) {
  await page.locator(`#canvas g.block[data-name="${name}"] .block-name`).click();
  const input = page.locator(`#inspector tr[data-property="${property}"] input`);
  await input.fill(text);
  await input.press('Tab'); // leaving the field commits it (change)
  await settled(page);
}

/** Selects block `name`, sets its period (s) and ticks configure and start. */
export async function setActivity(page, name, period) {
  await page.locator(`#canvas g.block[data-name="${name}"] .block-name`).click();
  await page.locator('#activity-period').fill(String(period));
  await page.locator('#activity-apply').click();
  for (const list of ['configure', 'start']) {
    const box = page.locator(`#inspector input[data-list="${list}"]`);
    if (!(await box.isChecked())) await box.check();
  }
  await settled(page);
}

/** The connections of Fig. 3.4 as drawn: [first clicked, second clicked] (one from its input end). */
export const FIG_3_4_CLICKS = [
  ['Traj.desCartPose_1', 'Adm.refPose'],
  ['Traj.desCartTwist_1', 'Adm.refTwist'],
  ['Adm.admPose', 'Robot.desCartPose'],
  ['EqW.inWrench', 'Robot.measWrench'],
  ['Robot.measCartPose', 'EqW.referenceFrame'],
  ['EqW.outWrench', 'Adm.measWrench'],
];

/** Builds Fig. 3.4 on an empty canvas by clicks: four blocks, six connections, properties, activities. */
export async function buildFig34(page) {
  // Drop points (block centres) that keep the drawing inside the canvas' view at 1280x800.
  await place(page, 'CartesianTrajectoryGenerator', 'Traj', 115, 60);
  await place(page, 'VariableAdmittance', 'Adm', 365, 250);
  await place(page, 'SimulatedUR5Robot', 'Robot', 575, 60);
  await place(page, 'EquivalentWrench', 'EqW', 115, 440);
  for (const [a, b] of FIG_3_4_CLICKS) await connect(page, a, b);
  // The sensor's wrench is in the tool frame; the measured tool pose turns it into base axes at the tool point.
  await setProperty(page, 'EqW', 'invert_reference', 'true');
  await setProperty(page, 'EqW', 'change_application_point', 'false');
  for (const name of ['Traj', 'Adm', 'Robot', 'EqW']) await setActivity(page, name, 0.001);
}

/** The page's project (a copy). */
export function project(page) {
  return page.evaluate(() => structuredClone(window.cobraEditor.state.project));
}
