// The editor page against test/editor_fixture_server.mjs (Debian's chromium, headless): the
// thesis' Fig. 3.4 built by clicks and saved, a type mismatch refused with its reason, a role
// violation's linter message, a malformed file shown read-only at its line, the inspector's edits
// checked by the server, tabs, a generated type, attaching to a run.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { launch } from './browser.mjs';
import { BAD_ERROR, BAD_FILE, BAD_LINE, FORCE_SAMPLE, loadPalette, startEditorFixture } from './editor_fixture_server.mjs';
import { recordedPalette } from './make_editor_fixtures.mjs';
import { FIG_3_4_CLICKS, buildFig34, connect, openEditor, place, project, setProperty, settled } from './editor_page.mjs';

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

/** Resolves once `condition()` holds (checked every 20 ms; fails after 10 s naming `what`). */
async function waitUntil(condition, what) {
  for (let waited = 0; !condition(); waited += 20) {
    if (waited > 10000) throw new Error(`waited 10 s: ${what}`);
    await new Promise((resolve) => { setTimeout(resolve, 20); });
  }
}

/** Fills the new-component form's name, role, package, folder and doc. */
async function fillTypeForm(page, { name, role, package: pkg, folder, doc }) {
  await page.locator('#type-name').fill(name);
  await page.locator('#type-role').selectOption(role);
  await page.locator('#type-package').fill(pkg);
  await page.locator('#type-folder').fill(folder);
  await page.locator('#type-doc').fill(doc);
}

/** Adds a row to the new-component form's list `list` (inputs, event_inputs, outputs, properties). */
async function addMember(page, list, name, type, unit) {
  await page.locator(`fieldset[data-list="${list}"] .member-add`).click();
  const row = page.locator(`fieldset[data-list="${list}"] .member`).last();
  await row.locator('.member-name').fill(name);
  await row.locator('.member-type').fill(type);
  await row.locator('.member-unit').fill(unit);
}

async function fixture(t, mode = 'new') {
  const server = await startEditorFixture(mode);
  t.after(() => server.close());
  const { page, errors } = await openEditor(browser, server.pageUrl, t);
  t.after(() => assert.deepEqual(errors, []));
  return { server, page };
}

test('the palette lists the recorded types by package, with ports, properties and operations, and searches', async (t) => {
  const { page } = await fixture(t);
  // The whole palette cobra serves (the fixture is its recording: make_editor_fixtures.mjs).
  const recorded = recordedPalette();
  assert.ok(recorded.types.length >= 44, `the recorded palette has ${recorded.types.length} types`);
  const packages = await page.locator('#palette-list section.package h3').allTextContents();
  assert.deepEqual(packages.filter((p) => p !== 'fixture_types'), [...new Set(recorded.types.map((t) => t.package))].sort());
  assert.equal(await page.locator('#palette-list summary[data-type]').count(), recorded.types.length + 1);
  const traj = page.locator('details:has(summary[data-type="CartesianTrajectoryGenerator"])');
  await traj.locator('summary').click();
  const text = await traj.textContent();
  assert.match(text, /Calculation/);
  assert.match(text, /out desCartPose_1 : KDL\.Frame \[m\]/);
  assert.match(text, /property arms_num : int \[1\] in \[1, 16\]/);
  assert.match(text, /operation void askStartMove\(\)/);
  assert.match(await page.locator('details:has(summary[data-type="EquivalentWrench"])').textContent(), /in \(event\) inWrench : KDL\.Wrench \[N, N·m\]/);
  await page.locator('#palette-search').fill('admittance');
  assert.deepEqual(await page.locator('#palette-list summary').evaluateAll((s) => s.map((e) => e.dataset.type)), ['VariableAdmittance']);
  await page.locator('#palette-search').fill('nothing like this');
  assert.match(await page.locator('#palette-list').textContent(), /no type matches 'nothing like this'/);
});

test("Fig. 3.4 built by clicks: every connection asked of the server, drawn, and saved", async (t) => {
  const { server, page } = await fixture(t);
  await buildFig34(page);
  if (process.env.COBRA_EDITOR_SHOTS) await page.screenshot({ path: `${process.env.COBRA_EDITOR_SHOTS}/fig34_fixture.png` });
  // Each connection was checked once, with its output first whichever end was clicked first.
  assert.deepEqual(server.checks.map((c) => [c.output, c.input]), [
    ['Traj.desCartPose_1', 'Adm.refPose'], ['Traj.desCartTwist_1', 'Adm.refTwist'], ['Adm.admPose', 'Robot.desCartPose'],
    ['Robot.measWrench', 'EqW.inWrench'], ['Robot.measCartPose', 'EqW.referenceFrame'], ['EqW.outWrench', 'Adm.measWrench'],
  ]);
  assert.equal(await page.locator('#canvas g.connection').count(), FIG_3_4_CLICKS.length);
  assert.equal(await page.locator('#canvas .lint-badge').count(), 0);
  assert.match(await page.locator('#problem-list').textContent(), /no problems/);
  await page.locator('#save-path').fill('/tmp/fig34.lua');
  await page.locator('#save').click();
  await page.locator('#file-view h2', { hasText: '/tmp/fig34.lua (written)' }).waitFor();
  assert.equal(server.saves.length, 1);
  const saved = server.saves[0].project;
  assert.deepEqual(saved.packages, ['cobra_motion', 'cobra_control', 'cobra_sim']);
  assert.deepEqual(saved.components.map((c) => [c.name, c.type]), [
    ['Traj', 'CartesianTrajectoryGenerator'], ['Adm', 'VariableAdmittance'], ['Robot', 'SimulatedUR5Robot'], ['EqW', 'EquivalentWrench'],
  ]);
  assert.deepEqual(saved.components.find((c) => c.name === 'EqW').properties, { invert_reference: 'true', change_application_point: 'false' });
  assert.deepEqual(saved.components[0].activity, { period: 0.001, priority: 0, scheduler: 'other' });
  assert.deepEqual(saved.configure, ['Traj', 'Adm', 'Robot', 'EqW']);
  assert.equal(saved.connections.length, 6);
  assert.ok(saved.components.every((c) => Number.isFinite(c.x) && Number.isFinite(c.y)));
  // The written text is shown.
  assert.match(await page.locator('#file-text').textContent(), /component_type = "VariableAdmittance"/);
});

test('a type mismatch is refused with the reason next to the port, and nothing is drawn', async (t) => {
  const { page } = await fixture(t);
  await place(page, 'SimulatedUR5Robot', 'Robot', 700, 150);
  await place(page, 'VariableAdmittance', 'Adm', 250, 150);
  await connect(page, 'Robot.measWrench', 'Adm.refPose');
  const refusal = page.locator('#canvas text.refusal');
  assert.equal(await refusal.getAttribute('data-port'), 'Adm.refPose');
  assert.equal(await refusal.textContent(), "types differ: 'Robot.measWrench' writes KDL.Wrench, 'Adm.refPose' reads KDL.Frame");
  assert.match(await page.locator('#status').textContent(), /refused: types differ/);
  assert.equal(await page.locator('#canvas g.connection').count(), 0);
  // Two outputs are refused by the page itself.
  await connect(page, 'Robot.measWrench', 'Adm.admPose');
  assert.match(await refusal.textContent(), /are both outputs: a connection goes from an output to an input/);
  assert.equal((await project(page)).connections.length, 0);
});

test("a role violation is drawn with the linter's message on its badge and in the problems list", async (t) => {
  const { page } = await fixture(t);
  await place(page, 'SimulatedUR5Robot', 'Robot', 250, 150);
  await place(page, 'ForceWatch', 'Watch', 650, 150);
  await connect(page, 'Robot.measWrench', 'Watch.wrench');
  const message = 'Robot.measWrench (Bridge) -> Watch.wrench (Supervision): a Supervision component may read only logic data, but KDL.Wrench is pure data';
  assert.equal(await page.locator('#canvas g.connection').count(), 1);
  assert.equal(await page.locator('#canvas .lint-badge title').textContent(), message);
  assert.equal(await page.locator('#problem-list li.lint').textContent(), `a Supervision component may read only logic data: ${message}`);
  assert.match(await page.locator('#inspector ul.lint').textContent(), /may read only logic data/);
  // A problem clicked selects what it is about.
  await page.locator('#canvas g.block[data-name="Robot"] .block-name').click();
  await page.locator('#problem-list li.lint').click();
  assert.equal(await page.locator('#inspector h3').textContent(), 'Robot.measWrench → Watch.wrench');
  await page.locator('#undo').click();
  assert.equal(await page.locator('#canvas g.connection').count(), 0);
  assert.equal(await page.locator('#problem-list li.lint').count(), 0, 'the lint of a connection undone is not listed');
});

test('undo puts back what an edit changed: a deleted block with its connection, the connection, the blocks', async (t) => {
  const { page } = await fixture(t);
  assert.ok(await page.locator('#undo').isDisabled());
  await place(page, 'SineGenerator', 'Sine', 150, 150);
  await place(page, 'Gain', 'Amp', 500, 150);
  await connect(page, 'Sine.out', 'Amp.in');
  await page.locator('#canvas g.block[data-name="Amp"] .block-name').click();
  await page.locator('#delete-selected').click();
  assert.equal(await page.locator('#canvas g.block').count(), 1);
  assert.equal(await page.locator('#canvas g.connection').count(), 0);
  await page.locator('#undo').click();
  assert.deepEqual(await page.locator('#canvas g.block').evaluateAll((gs) => gs.map((g) => g.dataset.name)), ['Sine', 'Amp']);
  assert.equal(await page.locator('#canvas g.connection').count(), 1);
  await page.locator('#undo').click();
  assert.equal(await page.locator('#canvas g.connection').count(), 0);
  await page.keyboard.press('Control+z');
  await page.keyboard.press('Control+z');
  assert.equal(await page.locator('#canvas g.block').count(), 0);
  assert.ok(await page.locator('#undo').isDisabled());
  assert.deepEqual((await project(page)).packages, []);
});

test('a malformed file shows its error and its line in a read-only view, and cannot be saved', async (t) => {
  const { server, page } = await fixture(t, 'malformed');
  assert.match(await page.locator('#file-view .file-error').textContent(), new RegExp(BAD_ERROR.replace(/[.*+?^${}()|[\]\\]/g, '\\$&')));
  assert.equal(await page.locator('#file-text .error-line').getAttribute('data-line'), String(BAD_LINE));
  assert.match(await page.locator('#file-text .error-line').textContent(), /peer_name = "Gain" component_type/);
  assert.equal(await page.locator('#file-text').evaluate((e) => e.isContentEditable), false);
  assert.ok(await page.locator('#save').isDisabled());
  assert.equal(await page.locator('#path').inputValue(), BAD_FILE);
  assert.equal(server.saves.length, 0);
});

test('properties are checked by the server and problems show by the field; a policy is edited', async (t) => {
  const { page } = await fixture(t);
  await place(page, 'CartesianTrajectoryGenerator', 'Traj', 200, 120);
  await place(page, 'VariableAdmittance', 'Adm', 550, 120);
  await setProperty(page, 'Traj', 'arms_num', '40');
  const row = page.locator('#inspector tr[data-property="arms_num"]');
  await row.locator('.field-problem', { hasText: 'out of its range' }).waitFor();
  await page.locator('#canvas').click({ position: { x: 600, y: 700 } });
  assert.equal(await page.locator('#problem-list li.problem').textContent(), "component 'Traj' property 'arms_num': 40 is out of its range [1, 16]");
  await page.locator('#problem-list li.problem').click();
  assert.equal(await page.locator('#inspector h3').textContent(), 'Traj');
  assert.equal(await row.locator('.field-problem').textContent(), '40 is out of its range [1, 16]');
  assert.match(await row.locator('.prop-type').textContent(), /int \[1\] in \[1, 16\]/);
  await setProperty(page, 'Traj', 'arms_num', '2');
  assert.equal(await row.locator('.field-problem').textContent(), '');
  await connect(page, 'Adm.refPose', 'Traj.desCartPose_1');
  await page.locator('#policy-type').selectOption('buffer');
  await page.locator('#policy-size').fill('0');
  await page.locator('#policy-apply').click();
  assert.match(await page.locator('#status').textContent(), /policy size '0': expected a whole number of samples >= 1 for a buffer/);
  await page.locator('#policy-size').fill('16');
  await page.locator('#policy-apply').click();
  assert.deepEqual((await project(page)).connections[0].conn_policy, { type: 'buffer', size: 16 });
  assert.equal(await page.locator('#canvas .policy-label').textContent(), 'buffer(16)');
  await page.locator('#delete-selected').click();
  assert.equal(await page.locator('#canvas g.connection').count(), 0);
  // A block is moved by dragging its body.
  const block = page.locator('#canvas g.block[data-name="Adm"] .body');
  // The canvas is drawn anew after the deletion: the block's element may be replaced between
  // two reads (a null box was seen on a loaded machine), so read until it is there.
  let box = null;
  for (let tries = 0; tries < 100 && box === null; ++tries) {
    await block.waitFor({ state: 'visible' });
    box = await block.boundingBox();
  }
  assert.ok(box, 'the Adm block is drawn after the deletion');
  await page.mouse.move(box.x + 100, box.y + 60);
  await page.mouse.down();
  await page.mouse.move(box.x + 40, box.y + 260, { steps: 5 });
  await page.mouse.up();
  const adm = (await project(page)).components.find((c) => c.name === 'Adm');
  // Dropped centred at (550, 120): its corner at (550 - 105, 120 - 19); dragged by (-60, 200)
  // (within 1 px: the page rounds the drop and the drag to whole px).
  assert.ok(Math.abs(adm.x - 385) <= 1 && Math.abs(adm.y - 301) <= 1, `Adm at (${adm.x}, ${adm.y}), expected (385, 301)`);
});

test('an instance name is an identifier and unique', async (t) => {
  const { page } = await fixture(t);
  await place(page, 'Gain', 'Amp', 300, 200);
  await page.locator('summary[data-type="Gain"]').dragTo(page.locator('#canvas'), { targetPosition: { x: 600, y: 200 } });
  await page.locator('#name-input').fill('Amp');
  await page.locator('#name-ok').click();
  assert.equal(await page.locator('#name-error').textContent(), "a component named 'Amp' exists already");
  await page.locator('#name-input').fill('2nd');
  await page.locator('#name-ok').click();
  assert.match(await page.locator('#name-error').textContent(), /'2nd' is not an identifier/);
  await page.locator('#name-cancel').click();
  assert.equal(await page.locator('#canvas g.block').count(), 1);
});

test('deployment and configuration tabs: a deployment runs its components and owns its connections', async (t) => {
  const { server, page } = await fixture(t);
  await place(page, 'SineGenerator', 'Sine', 150, 150);
  await page.locator('#add-deployment').click();
  await page.locator('#name-input').fill('scaled');
  await page.locator('#name-extra-input').fill('signal');
  await page.locator('#name-ok').click();
  assert.equal(await page.locator('#tabs .tab.active').textContent(), 'scaled (signal)');
  assert.deepEqual(await page.locator('#tabs .tab').allTextContents(), ['base deployment', 'scaled (signal)']);
  assert.match(await page.locator('#canvas g.block[data-name="Sine"]').getAttribute('class'), /outside/);
  await place(page, 'Gain', 'Amp', 500, 150);
  await connect(page, 'Sine.out', 'Amp.in');
  let p = await project(page);
  assert.deepEqual(p.deployments, [{ name: 'scaled', scope: 'signal', components: ['Amp'], connections: [{ output: 'Sine.out', input: 'Amp.in', conn_policy: { type: 'data' } }] }]);
  assert.equal(p.connections.length, 0);
  await page.locator('#tabs .tab', { hasText: 'base deployment' }).click();
  assert.equal(await page.locator('#canvas g.connection').count(), 0);
  await page.locator('#add-configuration').click();
  await page.locator('#name-input').fill('loud');
  await page.locator('#name-ok').click();
  await page.locator('#value-key').selectOption('Amp.k');
  await page.locator('#value-text').fill('10');
  await page.locator('#value-add').click();
  await settled(page);
  p = await project(page);
  assert.deepEqual(p.configurations, [{ name: 'loud', values: { 'Amp.k': '10' } }]);
  assert.equal(server.saves.length, 0);
});

test('a new component type is generated from the form and listed as generated', async (t) => {
  const { server, page } = await fixture(t);
  await page.locator('#new-type').click();
  await fillTypeForm(page, { name: 'ForceLimiter', role: 'Calculation', package: 'my_tools', folder: '/tmp/my_tools', doc: 'clamps a wrench' });
  await addMember(page, 'inputs', 'wrench', 'KDL.Wrench', 'N, N·m');
  await addMember(page, 'outputs', 'limited', 'KDL.Wrench', 'N, N·m');
  await addMember(page, 'properties', 'max_force', 'double', 'N');
  await page.locator('#type-generate').click();
  await page.locator('#type-files li').first().waitFor();
  assert.deepEqual(await page.locator('#type-files li').allTextContents(), [
    '/tmp/my_tools/include/my_tools/force_limiter.hpp', '/tmp/my_tools/src/force_limiter.cpp', '/tmp/my_tools/test/force_limiter_test.cpp',
  ]);
  assert.deepEqual(server.generated[0].component, {
    name: 'ForceLimiter', role: 'calculation', package: 'my_tools', doc: 'clamps a wrench',
    // Sent by the palette's names, which the generator takes.
    inputs: [{ name: 'wrench', type: 'KDL.Wrench', unit: 'N, N·m' }], event_inputs: [],
    outputs: [{ name: 'limited', type: 'KDL.Wrench', unit: 'N, N·m' }], properties: [{ name: 'max_force', type: 'double', unit: 'N' }],
  });
  await page.locator('#type-close').click();
  assert.match(await page.locator('summary[data-type="ForceLimiter"]').textContent(), /generated \(build the package to use it\)/);
  // A name the palette has is refused before asking.
  await page.locator('#new-type').click();
  await page.locator('#type-name').fill('Gain');
  await page.locator('#type-generate').click();
  assert.equal(await page.locator('#type-error').textContent(), "a component type named 'Gain' exists already (package cobra_signal)");
  // A type the generator does not know is refused before asking.
  await page.locator('#type-name').fill('Planner2');
  await page.locator('#type-package').fill('my_tools');
  await page.locator('fieldset[data-list="inputs"] .member-add').click();
  await page.locator('fieldset[data-list="inputs"] .member .member-name').last().fill('path');
  await page.locator('fieldset[data-list="inputs"] .member .member-type').last().fill('TGL.MultiAxisPath');
  await page.locator('#type-generate').click();
  assert.match(await page.locator('#type-error').textContent(), /^inputs: 'path' has type 'TGL\.MultiAxisPath', which the generator does not know; it knows Event, Geometry\.PointList, Imaging\.GrayImage, KDL\.Frame, /);
  assert.deepEqual(await page.locator('#palette-data-types option').evaluateAll((os) => os.map((o) => o.value)).then((v) => v.includes('KDL.Wrench') && !v.includes('TGL.MultiAxisPath')), true);
  assert.equal(server.generated.length, 1);
});

test("a package's data type is offered by the generator form and a component reading it is generated", async (t) => {
  const { server, page } = await fixture(t);
  await page.locator('#new-type').click();
  // Offered: the palette's data types the generator writes, cobra's and the package's, by name.
  const known = loadPalette().data_types.filter((d) => d.generate).map((d) => d.name);
  assert.ok(known.includes(FORCE_SAMPLE.name) && known.includes('KDL.Frame') && !known.includes('TGL.MultiAxisPath'), known.join(', '));
  assert.deepEqual(await page.locator('#palette-data-types option').evaluateAll((os) => os.map((o) => o.value)), known);
  assert.equal(await page.locator('#type-known').textContent(), `port and property types: ${known.join(', ')}`);
  assert.deepEqual(await page.locator('.member-add').allTextContents(), ['+ input', '+ event input', '+ output', '+ property']);
  await fillTypeForm(page, { name: 'ForceSampleWatch', role: 'Calculation', package: 'my_filters', folder: '/tmp/my_filters', doc: '' });
  await addMember(page, 'event_inputs', 'sample', 'example.ForceSample', 'N');
  await addMember(page, 'outputs', 'force', 'double', 'N');
  // A misspelt type is refused before asking, naming the types the generator knows.
  await addMember(page, 'properties', 'hold', 'example.ForceSampel', 'N');
  await page.locator('#type-generate').click();
  assert.equal(await page.locator('#type-error').textContent(),
    `properties: 'hold' has type 'example.ForceSampel', which the generator does not know; it knows ${known.join(', ')}`);
  assert.equal(server.generated.length, 0);
  await page.locator('fieldset[data-list="properties"] .member .member-type').fill('example.ForceSample');
  await page.locator('#type-generate').click();
  await page.locator('#type-files li').first().waitFor();
  assert.equal(await page.locator('#type-error').textContent(), '');
  assert.deepEqual(await page.locator('#type-files li').allTextContents(), [
    '/tmp/my_filters/include/my_filters/force_sample_watch.hpp', '/tmp/my_filters/src/force_sample_watch.cpp', '/tmp/my_filters/test/force_sample_watch_test.cpp',
  ]);
  assert.deepEqual(server.generated.map((g) => g.component), [{
    name: 'ForceSampleWatch', role: 'calculation', package: 'my_filters', doc: '', inputs: [],
    event_inputs: [{ name: 'sample', type: 'example.ForceSample', unit: 'N' }], outputs: [{ name: 'force', type: 'double', unit: 'N' }],
    properties: [{ name: 'hold', type: 'example.ForceSample', unit: 'N' }],
  }]);
  if (process.env.COBRA_EDITOR_SHOTS) await page.locator('#type-dialog').screenshot({ path: `${process.env.COBRA_EDITOR_SHOTS}/editor_package_type.png` });
  await page.locator('#type-close').click();
  // The generated type joins the palette with its port of the package's type.
  const entry = page.locator('details:has(summary[data-type="ForceSampleWatch"])');
  assert.match(await entry.locator('summary').textContent(), /generated \(build the package to use it\)/);
  await entry.locator('summary').click();
  assert.match(await entry.textContent(), /in \(event\) sample : example\.ForceSample/);
});

test('attach: shown when the server has a running deployment, which it loads', async (t) => {
  const { page } = await fixture(t, 'running');
  await page.locator('#attach').click();
  await page.locator('#canvas g.block[data-name="Amp"]').waitFor();
  // The attached project's checks redraw the canvas as they answer: click a wire that stays.
  await settled(page);
  assert.equal(await page.locator('#canvas g.connection').count(), 1);
  // A dds connection's transport fields are shown and edited with its policy.
  await page.locator('#canvas g.connection .wire-hit').click({ force: true });
  assert.equal(await page.locator('#policy-transport').inputValue(), 'dds');
  assert.equal(await page.locator('#policy-qos').inputValue(), '{"reliability":"reliable"}');
  await page.locator('#policy-topic').fill('sine2');
  await page.locator('#policy-apply').click();
  assert.deepEqual((await project(page)).connections[0].conn_policy, { type: 'data', transport: 'dds', topic: 'sine2', qos: { reliability: 'reliable' } });
  // A connection to a port the palette does not list draws that port, marked as made at configure.
  await page.locator('#tabs .tab[data-tab="gated"]').click();
  assert.equal(await page.locator('#canvas g.connection:not(.base)').count(), 1);
  assert.match(await page.locator('#canvas g.port[data-port="Gate.limit"]').getAttribute('class'), /\bin\b.*\bconfigured\b/);
  const other = await fixture(t, 'new');
  assert.ok(await other.page.locator('#attach').isHidden());
});

test('attached, the page follows the run: a switch pushed over /ws re-reads the running deployment, once', async (t) => {
  const { server, page } = await fixture(t, 'running');
  await page.locator('#attach').click();
  await page.locator('#canvas g.block[data-name="Amp"]').waitFor();
  await page.waitForFunction(() => window.cobraEditor.running !== null);
  await waitUntil(() => server.sockets() === 1, 'the page opens the WebSocket');
  const reads = server.running.reads; // the page's probe at start and the attach
  assert.deepEqual((await project(page)).apply, []);
  // Frames that name the same deployments ask nothing (no polling).
  await new Promise((resolve) => { setTimeout(resolve, 300); });
  assert.equal(server.running.reads, reads);
  server.switchTo('gated', 0.25);
  await page.waitForFunction(() => window.cobraEditor.running?.now?.deployments?.[0]?.deployment === 'gated');
  await new Promise((resolve) => { setTimeout(resolve, 300); });
  assert.equal(server.running.reads, reads + 1, 'three frames naming the new deployment: one read');
  assert.deepEqual((await project(page)).apply, ['gated']);
  assert.match(await page.locator('#status').textContent(), /the run switched to default: gated: re-read the running deployment \(t = 0\.25 s; default: gated\)/);
  // Edits made since are kept when the run switches again.
  await setProperty(page, 'Amp', 'k', '4');
  server.switchTo('', 0.5);
  await page.waitForFunction(() => /your edits are kept/.test(document.getElementById('status').textContent));
  assert.deepEqual((await project(page)).apply, ['gated']);
});
