// The deployment editor against cobra itself (the editor's acceptance): the page served by
// `cobra edit`. Needs COBRA_BIN (the cobra tool) and COBRA_SOURCE_DIR (the repo); CTest passes
// both where the tree has the studio server. The Fig. 3.4 test saves the page as fig34.png in
// COBRA_EDITOR_SHOTS (CTest: build/<preset>/editor-shots), else in its temporary folder.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, statSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { launch } from './browser.mjs';
import { runCobra, startCobra, stopCobras } from './cobra_process.mjs';
import { recordedPalette, servedPalette } from './make_editor_fixtures.mjs';
import { FIG_3_4_CLICKS, buildFig34, connect, openEditor, place, project, settled } from './editor_page.mjs';

const { COBRA_BIN, COBRA_SOURCE_DIR, COBRA_EDITOR_SHOTS } = process.env;
const skip = !COBRA_BIN || !COBRA_SOURCE_DIR ? 'COBRA_BIN and COBRA_SOURCE_DIR not set (CTest sets them)' : false;
let browser;

before(async () => { if (!skip) browser = await launch(); });
after(async () => {
  stopCobras();
  await browser?.close();
});

async function editor(t, args) {
  const { url } = await startCobra(['edit', ...args], 'editor');
  const opened = await openEditor(browser, url, t);
  t.after(() => assert.deepEqual(opened.errors, []));
  return opened.page;
}

test("the browser tests' palette fixture is the palette cobra edit serves", { skip, timeout: 120000 }, async () => {
  const served = await servedPalette();
  const recorded = recordedPalette();
  const again = 'record it again: COBRA_BIN=... node test/make_editor_fixtures.mjs';
  assert.deepEqual(recorded.types.map((t) => t.type), served.types.map((t) => t.type), `the types differ; ${again}`);
  for (const type of served.types) {
    assert.deepEqual(recorded.types.find((t) => t.type === type.type), type, `${type.type} changed; ${again}`);
  }
  assert.deepEqual(recorded.packages, served.packages, `the packages differ; ${again}`);
  // The data types: what the generator form offers (those flagged generate) and the fixture serves.
  assert.deepEqual(recorded.data_types, served.data_types, `the data types differ; ${again}`);
});

test('Fig. 3.4 built by clicks in cobra edit, saved, and the saved file deploys', { skip, timeout: 240000 }, async (t) => {
  const page = await editor(t, []);
  await buildFig34(page);
  assert.equal(await page.locator('#canvas g.connection').count(), FIG_3_4_CLICKS.length);
  assert.equal(await page.locator('#canvas .lint-badge').count(), 0, await page.locator('#problem-list').textContent());
  assert.match(await page.locator('#problem-list').textContent(), /no problems/);
  const folder = mkdtempSync(join(tmpdir(), 'cobra-editor-'));
  const file = join(folder, 'fig34.lua');
  await page.locator('#save-path').fill(file);
  await page.locator('#save').click();
  await page.locator('#file-view h2', { hasText: 'fig34.lua (written)' }).waitFor({ timeout: 30000 });
  const text = readFileSync(file, 'utf8');
  const shown = await page.locator('#file-text').evaluate((e) => e.textContent.split('\n').map((l) => l.replace(/^ *\d+ /, '')).join('\n'));
  assert.equal(shown.trimEnd(), text.trimEnd(), 'the page shows the text written');
  assert.ok(existsSync(`${file}.layout.json`), 'the layout sidecar is written beside the file');
  const shots = COBRA_EDITOR_SHOTS ?? folder;
  mkdirSync(shots, { recursive: true });
  await page.screenshot({ path: join(shots, 'fig34.png') });

  const run = await runCobra(['deploy', file, '--sim', '--run-for', '0.5']);
  assert.equal(run.status, 0, `cobra deploy ${file}:\n${run.stdout}${run.stderr}\nthe file:\n${text}`);
  // The file is the Configurator tables `cobra describe` writes: describing it gives it back.
  const described = await runCobra(['describe', file]);
  assert.equal(described.status, 0, described.stderr);
  for (const c of ['Traj', 'Adm', 'Robot', 'EqW']) assert.match(described.stdout, new RegExp(`peer_name = "${c}"`));
  for (const [a, b] of [['Traj.desCartPose_1', 'Adm.refPose'], ['EqW.outWrench', 'Adm.measWrench']]) {
    assert.match(described.stdout, new RegExp(`output = "${a}", input = "${b}"`));
  }
  // Opened again, the blocks are where they were left (the layout sidecar).
  const before = await project(page);
  await page.locator('#path').fill(file);
  await page.locator('#open').click();
  await page.waitForFunction((f) => window.cobraEditor.state.path === f, file);
  await settled(page);
  const reopened = await project(page);
  for (const c of before.components) {
    const again = reopened.components.find((k) => k.name === c.name);
    assert.deepEqual([again.type, again.x, again.y], [c.type, c.x, c.y], c.name);
  }
  assert.equal(await page.locator('#canvas g.connection').count(), FIG_3_4_CLICKS.length);
});

test('a type mismatch is refused by cobra with its reason, shown next to the port', { skip, timeout: 120000 }, async (t) => {
  const page = await editor(t, []);
  await place(page, 'SimulatedUR5Robot', 'Robot', 450, 150);
  await place(page, 'VariableAdmittance', 'Adm', 150, 150);
  await connect(page, 'Robot.measWrench', 'Adm.refPose');
  const reason = await page.locator('#canvas text.refusal').textContent();
  assert.match(reason, /Robot\.measWrench/);
  assert.match(reason, /KDL\.Wrench/);
  assert.match(reason, /KDL\.Frame/);
  assert.equal(await page.locator('#canvas g.connection').count(), 0);
});

test("a role violation is drawn with cobra's linter message", { skip, timeout: 120000 }, async (t) => {
  // Among cobra's own types: the Puma 260's EtherCAT master (a Bridge) reads only pure data but
  // writes its task state (logic data) — the linter's writer-side rule for bridges.
  const page = await editor(t, []);
  await place(page, 'Puma260EtherCATMaster', 'Master', 150, 150);
  await place(page, 'ScriptedSurgeon', 'Surgeon', 550, 150);
  await connect(page, 'Master.currentState', 'Surgeon.needleTaskState');
  assert.equal(await page.locator('#canvas g.connection').count(), 1, 'drawn: the linter warns, it does not refuse');
  const message = await page.locator('#canvas .lint-badge title').textContent();
  assert.match(message, /^Master\.currentState \(Bridge\) -> Surgeon\.needleTaskState \(Bridge\): a Bridge component writes the same kind of data it reads, and Master reads only pure/);
  assert.match(await page.locator('#problem-list li.lint').textContent(), /a Bridge component writes the same kind of data it reads/);
});

/** Component names and connections (output, input) in a `cobra describe` text. */
function describedParts(text) {
  const components = [...text.matchAll(/peer_name = "(\w+)", component_type/g)].map((m) => m[1]);
  const connections = [...text.matchAll(/output = "([\w.]+)", input = "([\w.]+)"/g)].map((m) => [m[1], m[2]]);
  const deployments = [...text.matchAll(/defineDeployment\(\s*"(\w+)"|\{ name = "(\w+)", (?:scope|components)/g)].map((m) => m[1] ?? m[2]);
  return { components: [...new Set(components)], connections, deployments: [...new Set(deployments)] };
}

test('apps/puncturing opens with every component and connection cobra describe lists, deployments as tabs', { skip, timeout: 240000 }, async (t) => {
  const app = join(COBRA_SOURCE_DIR, 'apps', 'puncturing');
  const described = await runCobra(['describe', join(app, 'puncturing.lua')]);
  assert.equal(described.status, 0, described.stderr);
  const want = describedParts(described.stdout);
  assert.ok(want.components.length > 20 && want.connections.length > 20, described.stdout);
  const page = await editor(t, [app]);
  await page.waitForFunction(() => window.cobraEditor.state.project.components.length > 0);
  const blocks = await page.locator('#canvas g.block').evaluateAll((gs) => gs.map((g) => g.dataset.name));
  for (const name of want.components) assert.ok(blocks.includes(name), `component ${name} is not drawn`);
  const tabs = await page.locator('#tabs .tab.deployment').evaluateAll((bs) => bs.map((b) => b.dataset.tab));
  for (const name of want.deployments) assert.ok(tabs.includes(name), `deployment ${name} has no tab`);
  // Every connection described is drawn on the base tab or on a deployment's tab.
  const drawn = new Set();
  for (const tab of tabs) {
    await page.locator(`#tabs .tab.deployment[data-tab="${tab}"]`).click();
    const own = await page.locator('#canvas g.connection:not(.base)').evaluateAll((gs) => gs.map((g) => `${g.dataset.output}->${g.dataset.input}`));
    for (const c of own) drawn.add(c);
    // A deployment's own components are drawn as members of it.
    const p = await project(page);
    const members = tab === '' ? [] : p.deployments.find((d) => d.name === tab).components;
    for (const name of members) {
      assert.doesNotMatch(await page.locator(`#canvas g.block[data-name="${name}"]`).getAttribute('class'), /outside/, `${name} in ${tab}`);
    }
  }
  for (const [output, input] of want.connections) assert.ok(drawn.has(`${output}->${input}`), `connection ${output} -> ${input} is not drawn`);
});

test('apps/puncturing without a layout: no two blocks overlap on any tab, the file view without stray text', { skip, timeout: 240000 }, async (t) => {
  const app = join(COBRA_SOURCE_DIR, 'apps', 'puncturing');
  assert.ok(!existsSync(join(app, 'puncturing.lua.layout.json')), 'the test needs the application without a layout sidecar');
  const page = await editor(t, [app]);
  await page.waitForFunction(() => window.cobraEditor.state.project.components.length > 0);
  await settled(page);
  const tabs = await page.locator('#tabs .tab.deployment').evaluateAll((bs) => bs.map((b) => b.dataset.tab));
  for (const tab of tabs) {
    await page.locator(`#tabs .tab.deployment[data-tab="${tab}"]`).click();
    // Each block's rectangle as drawn (its body's box in the canvas), then every pair compared.
    const boxes = await page.locator('#canvas g.block').evaluateAll((gs) => gs.map((g) => {
      const box = g.querySelector('rect.body').getBBox();
      const m = g.getCTM();
      return { name: g.dataset.name, x: m.e + box.x, y: m.f + box.y, w: box.width, h: box.height };
    }));
    assert.ok(boxes.length > 20, `${boxes.length} blocks on tab '${tab}'`);
    for (const [i, a] of boxes.entries()) {
      for (const b of boxes.slice(i + 1)) {
        const apart = a.x + a.w <= b.x || b.x + b.w <= a.x || a.y + a.h <= b.y || b.y + b.h <= a.y;
        assert.ok(apart, `tab '${tab}': ${a.name} ${JSON.stringify(a)} overlaps ${b.name} ${JSON.stringify(b)}`);
      }
    }
  }
  await page.locator('#tabs .tab.deployment[data-tab=""]').click();
  // Within each block no input's name runs into an output's (a planner's allowedContactDistance).
  const crossing = await page.locator('#canvas g.block').evaluateAll((gs) => gs.flatMap((g) => {
    const labels = (side) => [...g.querySelectorAll(`.port.${side} .port-label`)].map((l) => ({ name: l.textContent, box: l.getBoundingClientRect() }));
    const ins = labels('in');
    return labels('out').flatMap((o) => ins.filter((i) => i.box.right > o.box.left && o.box.right > i.box.left
      && i.box.bottom > o.box.top && o.box.bottom > i.box.top).map((i) => `${g.dataset.name}: ${i.name} / ${o.name}`));
  }));
  assert.deepEqual(crossing, []);
  // And every text of a block stays inside it (a long type name in the header).
  const outside = await page.locator('#canvas g.block').evaluateAll((gs) => gs.flatMap((g) => {
    const body = g.querySelector('rect.body').getBoundingClientRect();
    return [...g.querySelectorAll('.block-name, .block-type')].filter((l) => l.getBoundingClientRect().right > body.right + 0.5)
      .map((l) => `${g.dataset.name}: ${l.textContent}`);
  }));
  assert.deepEqual(outside, []);
  // The file view: its title, then the text; no text of its own besides (a stray "null" before).
  const view = await page.locator('#file-view').evaluate((section) => ({
    title: section.querySelector('h2').textContent,
    loose: [...section.childNodes].filter((n) => n.nodeType === Node.TEXT_NODE).map((n) => n.textContent),
    children: [...section.children].map((c) => c.tagName),
  }));
  assert.equal(view.title, `${join(app, 'puncturing.lua')} (as opened)`);
  assert.deepEqual(view.loose, []);
  assert.deepEqual(view.children, ['H2', 'PRE']);
  const shots = COBRA_EDITOR_SHOTS ?? mkdtempSync(join(tmpdir(), 'cobra-editor-shots-'));
  mkdirSync(shots, { recursive: true });
  // The whole canvas in one picture: a viewport as large as the drawn blocks.
  const extent = await page.locator('#canvas').evaluate((svg) => [Number(svg.getAttribute('width')), Number(svg.getAttribute('height'))]);
  await page.setViewportSize({ width: Math.min(extent[0] + 700, 4000), height: Math.min(extent[1] + 300, 3000) });
  await page.screenshot({ path: join(shots, 'puncturing.png'), fullPage: true });
  assert.ok(statSync(join(shots, 'puncturing.png')).size > 10000);
});

test('a file that does not parse opens read-only at its line and is never saved over', { skip, timeout: 120000 }, async (t) => {
  const folder = mkdtempSync(join(tmpdir(), 'cobra-editor-'));
  const file = join(folder, 'broken.lua');
  const text = 'initConfigurator({ "cobra_signal" }, {\n  { peer_name = "Sine", component_type = "SineGenerator" },\n  { peer_name = "Amp" component_type = "Gain" },\n})\n';
  writeFileSync(file, text);
  const mtime = statSync(file).mtimeMs;
  const page = await editor(t, [file]);
  await page.locator('#file-view .file-error').waitFor();
  assert.match(await page.locator('#file-view .file-error').textContent(), /broken\.lua:3:/);
  assert.equal(await page.locator('#file-text .error-line').getAttribute('data-line'), '3');
  assert.ok(await page.locator('#save').isDisabled());
  assert.equal(readFileSync(file, 'utf8'), text);
  assert.equal(statSync(file).mtimeMs, mtime);
});

test('a new component type is generated by cobra into a folder from the form', { skip, timeout: 120000 }, async (t) => {
  const page = await editor(t, []);
  const folder = join(mkdtempSync(join(tmpdir(), 'cobra-editor-')), 'my_tools');
  await page.locator('#new-type').click();
  await page.locator('#type-name').fill('ForceLimiter');
  await page.locator('#type-role').selectOption('Calculation');
  await page.locator('#type-package').fill('my_tools');
  await page.locator('#type-folder').fill(folder);
  await page.locator('#type-doc').fill('clamps a wrench to a maximum force');
  for (const [list, name, type, unit] of [['inputs', 'wrench', 'KDL.Wrench', 'N, N·m'], ['outputs', 'limited', 'KDL.Wrench', 'N, N·m'], ['properties', 'max_force', 'double', 'N']]) {
    await page.locator(`fieldset[data-list="${list}"] .member-add`).click();
    const row = page.locator(`fieldset[data-list="${list}"] .member`).last();
    await row.locator('.member-name').fill(name);
    await row.locator('.member-type').fill(type);
    await row.locator('.member-unit').fill(unit);
  }
  await page.locator('#type-generate').click();
  await page.locator('#type-files li').first().waitFor({ timeout: 30000 });
  const files = await page.locator('#type-files li').allTextContents();
  assert.ok(files.length >= 2, files.join('\n'));
  for (const f of files) assert.ok(existsSync(f.startsWith('/') ? f : join(folder, f)), `${f} was not written`);
  assert.ok(files.some((f) => /force_limiter|ForceLimiter/.test(f)), files.join('\n'));
  await page.locator('#type-close').click();
  assert.match(await page.locator('summary[data-type="ForceLimiter"]').textContent(), /generated \(build the package to use it\)/);
});

test("attached to cobra run --studio, the page follows the run's deployment switches to its end", { skip, timeout: 180000 }, async (t) => {
  // studio/test/apps/editor_switch.lua: deployment "first" at once, "second" at 20 ms, done at 40 ms;
  // paced at 0.002 simulated s per wall s: "second" comes 10 s after the start.
  const app = join(COBRA_SOURCE_DIR, 'studio/test/apps/editor_switch.lua');
  const { url } = await startCobra(['run', app, '--studio', '--studio-port', '0', '--pace', '0.002', '--quiet']);
  const opened = await openEditor(browser, url.replace('/?token=', '/editor.html?token='), t);
  t.after(() => assert.deepEqual(opened.errors, []));
  const { page } = opened;
  await page.locator('#attach').waitFor({ state: 'visible', timeout: 30000 });
  await page.locator('#attach').click();
  await page.waitForFunction(() => window.cobraEditor.running !== null);
  const first = await page.evaluate(() => window.cobraEditor.running);
  assert.deepEqual(first.project.apply, ['first'], 'attached before the switch');
  assert.ok(first.now.running.includes('GainA') && !first.now.running.includes('GainB'), JSON.stringify(first.now.running));
  // The switch comes over the console's WebSocket: the page reads the running deployment again.
  await page.waitForFunction(() => window.cobraEditor.running.project.apply[0] === 'second', null, { timeout: 60000 });
  const second = await page.evaluate(() => window.cobraEditor.running);
  assert.deepEqual(second.now.deployments, [{ scope: '', deployment: 'second' }]);
  assert.ok(second.now.connections.some((c) => c.output === 'GainB.out' && c.input === 'Recorder.in'), JSON.stringify(second.now.connections));
  assert.ok(await page.locator('#canvas g.block[data-name="GainB"]').count() === 1);
  // The run's end is read once more: no longer live, the last deployment in force.
  await page.waitForFunction(() => window.cobraEditor.running.live === false, null, { timeout: 60000 });
  assert.deepEqual(await page.evaluate(() => window.cobraEditor.running.project.apply), ['second']);
});
