// The editor's document edits (src/editor_model.js), without a browser, on the palette recorded
// from cobra (test/fixtures/editor/palette.json).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  BASE_TAB, addComponent, addConfiguration, createHistory, addConnection, addDeployment, connectionsOf, emptyProject, findPort, generatedType, generatorTypes,
  inTab, instanceNameError, kindOf, LAYOUT, layersOf, normalizeProject, overlappingBlocks, orderEnds, paletteGroups, parseActivity, parsePolicy, peersOf,
  removeComponent, removeConnection, setConfigurationValue, setInDeployment, setPeers, setProperty, suggestName, typeOf,
} from '../src/editor_model.js';
import { loadPalette } from './editor_fixture_server.mjs';

const palette = loadPalette();
const type = (name) => typeOf(palette, name);

function fig34() {
  const p = emptyProject();
  addComponent(p, BASE_TAB, type('CartesianTrajectoryGenerator'), 'Traj', 10.4, 20.6);
  addComponent(p, BASE_TAB, type('VariableAdmittance'), 'Adm', 300, 20);
  addComponent(p, BASE_TAB, type('SimulatedUR5Robot'), 'Robot', 600, 20);
  addConnection(p, BASE_TAB, { output: 'Traj.desCartPose_1', input: 'Adm.refPose' });
  addConnection(p, BASE_TAB, { output: 'Adm.admPose', input: 'Robot.desCartPose' });
  return p;
}

test('an instance is placed at whole px, its package listed once, its name an unused identifier', () => {
  const p = fig34();
  assert.deepEqual(p.packages, ['cobra_motion', 'cobra_control', 'cobra_sim']);
  assert.deepEqual([p.components[0].x, p.components[0].y], [10, 21]);
  assert.equal(instanceNameError(p, ''), 'a component needs a name');
  assert.equal(instanceNameError(p, 'Adm'), "a component named 'Adm' exists already");
  assert.equal(instanceNameError(p, '1st'), "'1st' is not an identifier (letters, digits, _; not starting with a digit)");
  assert.equal(instanceNameError(p, 'Adm_2'), null);
  assert.throws(() => addComponent(p, BASE_TAB, type('Gain'), 'Adm', 0, 0), /exists already/);
  assert.equal(suggestName(p, 'VariableAdmittance'), 'VA1');
  addComponent(p, BASE_TAB, type('VariableAdmittance'), 'VA1', 0, 0);
  assert.equal(suggestName(p, 'VariableAdmittance'), 'VA2');
});

test('a connection is ordered output first whichever end was clicked first; like ends are refused', () => {
  const out = { name: 'Traj.desCartPose_1', direction: 'out' };
  const inp = { name: 'Adm.refPose', direction: 'in' };
  assert.deepEqual(orderEnds(out, inp), { output: 'Traj.desCartPose_1', input: 'Adm.refPose' });
  assert.deepEqual(orderEnds(inp, out), { output: 'Traj.desCartPose_1', input: 'Adm.refPose' });
  assert.equal(orderEnds(inp, { name: 'Robot.desCartPose', direction: 'in' }).error,
    'Adm.refPose and Robot.desCartPose are both inputs: a connection goes from an output to an input');
  assert.equal(orderEnds(out, out).error, 'Traj.desCartPose_1: a port cannot be connected to itself');
  const p = fig34();
  assert.throws(() => addConnection(p, BASE_TAB, { output: 'Traj.desCartPose_1', input: 'Adm.refPose' }), /connected already/);
  assert.deepEqual(p.connections[0].conn_policy, { type: 'data' });
  assert.equal(findPort(palette, p, 'Adm.refPose').port.type, 'KDL.Frame');
  assert.equal(findPort(palette, p, 'Adm.nope'), null);
  removeConnection(p, BASE_TAB, 'Traj.desCartPose_1', 'Adm.refPose');
  assert.equal(p.connections.length, 1);
});

test('a deployment runs the instances placed on its tab and owns its connections', () => {
  const p = fig34();
  addDeployment(p, 'follow', 'arm');
  assert.throws(() => addDeployment(p, 'follow'), /exists already/);
  assert.throws(() => addDeployment(p, 'a b'), /identifier/);
  addComponent(p, 'follow', type('WaypointPath'), 'Path', 0, 300);
  addConnection(p, 'follow', { output: 'Robot.measCartPose', input: 'Path.measPose', conn_policy: { type: 'buffer', size: 4 } });
  assert.deepEqual(p.deployments[0].components, ['Path']);
  assert.equal(connectionsOf(p, 'follow').length, 1);
  assert.equal(connectionsOf(p, BASE_TAB).length, 2);
  assert.ok(inTab(p, 'follow', 'Path') && !inTab(p, 'follow', 'Adm') && inTab(p, BASE_TAB, 'Adm'));
  setInDeployment(p, 'follow', 'Adm', true);
  setInDeployment(p, 'follow', 'Path', false);
  assert.deepEqual(p.deployments[0].components, ['Adm']);
  assert.deepEqual(p.deployments[0].connections[0].conn_policy, { type: 'buffer', size: 4 });
});

test('removing an instance removes every connection, peer, membership, value and list entry naming it', () => {
  const p = fig34();
  addDeployment(p, 'd', '');
  setInDeployment(p, 'd', 'Adm', true);
  addConnection(p, 'd', { output: 'Adm.admPose', input: 'Robot.desCartPose' });
  setPeers(p, 'Robot', ['Adm', 'Traj']);
  setPeers(p, 'Adm', ['Robot']);
  const c = addConfiguration(p, 'stiff');
  setConfigurationValue(palette, p, c, 'Adm.stiffness', '{ 1000, 1000, 1000, 50, 50, 50 }');
  setConfigurationValue(palette, p, c, 'Traj.max_vel', '0.1');
  p.configure.push('Adm', 'Traj');
  p.start.push('Adm');
  removeComponent(p, 'Adm');
  assert.deepEqual(p.components.map((k) => k.name), ['Traj', 'Robot']);
  assert.deepEqual(p.connections, []);
  assert.deepEqual(p.deployments[0], { name: 'd', components: [], connections: [] });
  assert.deepEqual(p.peers, [{ component: 'Robot', peers: ['Traj'] }]);
  assert.deepEqual(c.values, { 'Traj.max_vel': '0.1' });
  assert.deepEqual([p.configure, p.start], [['Traj'], []]);
});

test('policies, activities, properties, peers and configuration values from text fields', () => {
  assert.deepEqual(parsePolicy({ type: 'data', size: '' }), { type: 'data' });
  assert.deepEqual(parsePolicy({ type: 'circular', size: '8', transport: 'dds', topic: 'arm/pose', qos: '' }), { type: 'circular', size: 8, transport: 'dds', topic: 'arm/pose' });
  assert.deepEqual(parsePolicy({ type: 'data', transport: 'dds', topic: 't', qos: '{ "reliability": "reliable", "depth": "4" }' }),
    { type: 'data', transport: 'dds', topic: 't', qos: { reliability: 'reliable', depth: '4' } });
  assert.throws(() => parsePolicy({ type: 'data', qos: 'reliable' }), /policy qos 'reliable': expected a JSON object of texts/);
  assert.throws(() => parsePolicy({ type: 'data', qos: '{ "depth": 4 }' }), /expected a JSON object of texts/);
  assert.throws(() => parsePolicy({ type: 'queue' }), /policy type 'queue': expected one of data, buffer, circular/);
  assert.throws(() => parsePolicy({ type: 'buffer', size: '2.5' }), /policy size '2.5': expected a whole number of samples >= 1 for a buffer/);
  assert.deepEqual(parseActivity({ period: '0.001', priority: '', scheduler: '' }), { period: 0.001, priority: 0, scheduler: 'other' });
  assert.equal(parseActivity({ period: '' }), null);
  assert.throws(() => parseActivity({ period: '-1' }), /activity period '-1': expected seconds >= 0/);
  assert.throws(() => parseActivity({ period: '1', priority: 'high' }), /activity priority 'high': expected an integer/);
  assert.throws(() => parseActivity({ period: '1', scheduler: 'edf' }), /activity scheduler 'edf': expected one of other, fifo, rr/);
  const p = fig34();
  const adm = p.components[1];
  setProperty(adm, 'tank_max', ' 30 ');
  assert.deepEqual(adm.properties, { tank_max: '30' });
  setProperty(adm, 'tank_max', '');
  assert.deepEqual(adm.properties, {});
  setPeers(p, 'Traj', ['Adm']);
  assert.deepEqual(peersOf(p, 'Traj'), ['Adm']);
  setPeers(p, 'Traj', []);
  assert.deepEqual(p.peers, []);
  const c = addConfiguration(p, 'soft');
  assert.throws(() => setConfigurationValue(palette, p, c, 'Adm.stifness', '1'), /configuration 'soft': VariableAdmittance 'Adm' has no property 'stifness'/);
  assert.throws(() => setConfigurationValue(palette, p, c, 'Nobody.k', '1'), /configuration 'soft': no component 'Nobody'/);
});

test('a project from the server is completed: lists, deployment members as names, positions', () => {
  const p = normalizeProject({
    components: [{ name: 'A', type: 'Gain', x: 5, y: 6 }, { name: 'B', type: 'Gain' }],
    deployments: [{ name: 'd', components: [{ name: 'A' }, 'B'] }],
    configurations: [{ name: 'c' }],
  });
  assert.deepEqual(p.deployments[0], { name: 'd', components: ['A', 'B'], connections: [] });
  assert.deepEqual(p.configurations[0].values, {});
  // B goes below A (placed, 160 px tall by default) with a 30 px gap.
  assert.deepEqual([p.components[0].x, p.components[0].y, p.components[1].x, p.components[1].y], [5, 6, 40, 196]);
  assert.deepEqual(p.peers, []);
  assert.deepEqual(normalizeProject(null), emptyProject());
});

test('blocks without a position are laid out in layers along the connections, none over another', () => {
  // S -> G -> D, S -> D, D -> G (a cycle, cut where met), Q apart; E only in a deployment's connection.
  const project = normalizeProject({
    components: ['S', 'G', 'D', 'Q', 'E'].map((name) => ({ name, type: 'Gain' })),
    connections: [{ output: 'S.out', input: 'G.in' }, { output: 'G.out', input: 'D.in' }, { output: 'S.out', input: 'D.in' },
      { output: 'D.out', input: 'G.in' }],
    deployments: [{ name: 'd', components: ['E'], connections: [{ output: 'D.out', input: 'E.in' }] }],
  }, (c) => (c.name === 'S' ? 300 : 100), 200);
  assert.deepEqual(Object.fromEntries(layersOf(project)), { S: 0, G: 1, D: 2, Q: 0, E: 3 });
  // Columns 200 + 90 px apart; S (300 px tall) and Q share column 0, Q below S with a 30 px gap.
  assert.deepEqual(project.components.map((c) => [c.name, c.x, c.y]),
    [['S', 40, 40], ['G', 330, 40], ['D', 620, 40], ['Q', 40, 370], ['E', 910, 40]]);
  assert.deepEqual(overlappingBlocks(project, (c) => (c.name === 'S' ? 300 : 100), 200), []);
  // Layers deeper than LAYOUT.columns wrap into a band below the tallest column of the first.
  const chain = Array.from({ length: LAYOUT.columns + 2 }, (_, i) => `C${i}`);
  const wrapped = normalizeProject({
    components: chain.map((name) => ({ name, type: 'Gain' })),
    connections: chain.slice(1).map((name, i) => ({ output: `${chain[i]}.out`, input: `${name}.in` })),
  }, (c) => (c.name === 'C1' ? 300 : 100), 200);
  assert.deepEqual(wrapped.components.map((c) => [c.x, c.y]),
    [...chain.slice(0, LAYOUT.columns).map((_, i) => [40 + i * 290, 40]), [40, 40 + 300 + 30 + 30], [330, 400]]);
  assert.deepEqual(overlappingBlocks(wrapped, (c) => (c.name === 'C1' ? 300 : 100), 200), []);
  // Blocks placed over each other are found (and new ones go below every placed one).
  const placed = normalizeProject({ components: [{ name: 'A', x: 0, y: 0 }, { name: 'B', x: 100, y: 50 }, { name: 'C' }] }, () => 100, 200);
  assert.deepEqual(overlappingBlocks(placed, () => 100, 200), [['A', 'B']]);
  assert.deepEqual([placed.components[2].x, placed.components[2].y], [40, 180]);
});

test('the palette grouped by package and searched by every word; its data types; a generated entry', () => {
  const all = paletteGroups(palette);
  assert.deepEqual(all.map((g) => g.package), [...palette.packages]);
  assert.equal(all.reduce((n, g) => n + g.types.length, 0), palette.types.length);
  // "wrench" in a name, doc or port name, and the role Calculation (groups in the packages' order).
  assert.deepEqual(paletteGroups(palette, 'WRENCH calculation').flatMap((g) => g.types.map((t) => t.type)), ['LinkImpairment', 'VariableAdmittance', 'EquivalentWrench']);
  assert.deepEqual(paletteGroups(palette, 'supervision').map((g) => g.package), ['cobra_coordination', 'fixture_types']);
  // The generator's types: the data types flagged generate, a package's too, in the palette's order.
  const known = generatorTypes(palette);
  assert.ok(['KDL.Frame', 'vector<double>', 'example.ForceSample'].every((t) => known.includes(t)), known.join(', '));
  assert.ok(!known.includes('TGL.MultiAxisPath'));
  assert.deepEqual(known, [...known].sort());
  assert.deepEqual(generatorTypes({ packages: [], types: [] }), []);
  const g = generatedType({ name: 'Lim', role: 'calculation', package: 'mine', inputs: [{ name: 'u', type: 'double', unit: 'N' }],
    event_inputs: [{ name: 'trigger', type: 'Event' }], outputs: [{ name: 'y', type: 'double', unit: 'N' }], properties: [{ name: 'k', type: 'double', unit: '1' }] });
  assert.equal(g.generated, true);
  assert.equal(g.role, 'Calculation');
  assert.deepEqual(g.ports.map((q) => [q.name, q.direction, q.event]), [['u', 'in', false], ['trigger', 'in', true], ['y', 'out', false]]);
  assert.equal(kindOf('Event'), 'logic');
  assert.equal(kindOf('KDL.Wrench'), 'pure');
});

test('the undo history gives back the projects before each edit, newest first, up to its limit', () => {
  const history = createHistory(2);
  const p = emptyProject();
  assert.equal(history.undo(), null);
  for (const name of ['A', 'B', 'C']) {
    history.remember(p);
    addComponent(p, BASE_TAB, type('Gain'), name, 0, 0);
  }
  assert.equal(history.size, 2);
  assert.deepEqual(history.undo().components.map((c) => c.name), ['A', 'B']);
  assert.deepEqual(history.undo().components.map((c) => c.name), ['A']);
  assert.equal(history.undo(), null);
  history.remember(p);
  p.components[0].properties.k = '2';
  assert.deepEqual(history.undo().components[0].properties, {}, 'a copy, not the edited project');
});

/** Park-Miller: the same sequence of edits on every run. */
function random(seed) {
  let s = seed;
  return () => {
    s = (s * 48271) % 2147483647;
    return s / 2147483647;
  };
}

test('random edits never leave a reference to a removed instance (seeded, 300 sequences of 40 edits)', () => {
  const next = random(20260520);
  const pick = (list) => list[Math.floor(next() * list.length)];
  const wired = palette.types.filter((t) => t.ports.length > 1);
  for (let run = 0; run < 300; run += 1) {
    const p = emptyProject();
    addDeployment(p, 'd', 's');
    const c = addConfiguration(p, 'c');
    for (let step = 0; step < 40; step += 1) {
      const r = next();
      const names = p.components.map((k) => k.name);
      if (r < 0.35 || names.length < 2) {
        addComponent(p, next() < 0.5 ? BASE_TAB : 'd', pick(wired), suggestName(p, 'X'), next() * 900, next() * 600);
      } else if (r < 0.65) {
        const from = p.components.filter((k) => typeOf(palette, k.type).ports.some((q) => q.direction === 'out'));
        const to = p.components.filter((k) => typeOf(palette, k.type).ports.some((q) => q.direction === 'in'));
        if (!from.length || !to.length) continue;
        const a = pick(from);
        const b = pick(to);
        const output = `${a.name}.${pick(typeOf(palette, a.type).ports.filter((q) => q.direction === 'out')).name}`;
        const input = `${b.name}.${pick(typeOf(palette, b.type).ports.filter((q) => q.direction === 'in')).name}`;
        try { addConnection(p, next() < 0.5 ? BASE_TAB : 'd', { output, input }); } catch { /* already connected */ }
      } else if (r < 0.75) {
        setPeers(p, pick(names), names.filter(() => next() < 0.3));
      } else if (r < 0.85) {
        const k = pick(p.components);
        const prop = typeOf(palette, k.type).properties[0];
        if (prop) setConfigurationValue(palette, p, c, `${k.name}.${prop.name}`, '1');
        p.configure.push(k.name);
      } else {
        removeComponent(p, pick(names));
      }
      const alive = new Set(p.components.map((k) => k.name));
      const named = [
        ...[...p.connections, ...p.deployments[0].connections].flatMap((k) => [k.output, k.input]).map((f) => f.split('.')[0]),
        ...p.peers.flatMap((q) => [q.component, ...q.peers]), ...p.deployments[0].components,
        ...Object.keys(c.values).map((f) => f.split('.')[0]), ...p.configure,
      ];
      for (const n of named) assert.ok(alive.has(n), `run ${run} step ${step}: '${n}' was removed but is still named`);
    }
  }
});
