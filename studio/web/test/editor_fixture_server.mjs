// A stand-in for cobra's editor routes (studio/PROTOCOL.md "The editor (v1)") for the editor's
// browser tests: serves dist/ and answers /api/editor/* with the palette recorded from cobra
// (fixtures/editor/palette.json, test/make_editor_fixtures.mjs) and the rules the server applies:
// a connection goes from an existing output to an existing input of the same type; the role
// linter's rules of deploy/lint.hpp (kinds: Event and TaskState are logic data, the rest pure);
// property texts of double, int and bool parsed and held to their range; a generated component's
// port and property types among the palette's data types flagged generate (the fixture adds a
// package's, FORCE_SAMPLE). It keeps what the page posted (saves, generates) for the tests to look at.
//   mode 'new':       /api/editor/project is an empty project.
//   mode 'malformed': /api/editor/project answers 422 for BAD_FILE (line BAD_LINE).
//   mode 'running':   like 'new', and /api/editor/running answers RUNNING_PROJECT as of the
//                     deployment in force; /ws sends frames naming it (the server's switchTo(name)
//                     switches and sends three frames, as a run's frames repeat it).
import { createServer } from 'node:http';
import { existsSync, readFileSync } from 'node:fs';
import { extname, join, normalize } from 'node:path';
import { fileURLToPath } from 'node:url';
import { WebSocketServer } from 'ws';
import { DIST, FIXTURES, TOKEN, closeServer, json, tokenOf } from './fixture_server.mjs';

/**
 * The fixture's own type beside the recorded ones: a Supervision component reading a wrench (as
 * deploy/test/lint_test.cpp's Watch does). cobra's shipped types keep the role rules with every
 * pair of matching port types, so a role violation needs a type like this one.
 */
export const FORCE_WATCH = {
  type: 'ForceWatch', package: 'fixture_types', role: 'Supervision', doc: 'fixture: a supervisor that reads a wrench (breaks a role rule)',
  ports: [
    { name: 'events', direction: 'out', type: 'Event', event: false, unit: '', doc: 'what happened to this component' },
    { name: 'wrench', direction: 'in', type: 'KDL.Wrench', event: false, unit: 'N, N·m', doc: 'a measured wrench' },
  ],
  properties: [], operations: [],
};
/**
 * The fixture's package data type beside the recorded ones (fixtures/editor/package_data_type.json):
 * example.ForceSample, registered by examples/06_package's package example_filters, as `cobra edit`
 * lists it in its palette's data_types when that package is loaded (cobra's build does not build
 * the example, so the recording has only cobra's types; studio/test/editor_test.cpp checks that
 * the server lists the example's type as this file says).
 */
export const FORCE_SAMPLE = JSON.parse(readFileSync(join(FIXTURES, 'editor/package_data_type.json'), 'utf8'));
export const BAD_FILE = '/fixture/apps/broken/broken.lua';
export const BAD_LINE = 4;
export const BAD_TEXT = [
  '-- a hand-edited deployment that does not load',
  'initConfigurator({ "cobra_signal" }, {',
  '  { peer_name = "Sine", component_type = "SineGenerator" },',
  '  { peer_name = "Gain" component_type = "Gain" },',
  '})',
  '',
].join('\n');
export const BAD_ERROR = `${BAD_FILE}:${BAD_LINE}: '}' expected (to close '{' at line 2) near 'component_type'`;
export const RUNNING_PROJECT = {
  packages: ['cobra_signal'],
  components: [
    { name: 'Sine', type: 'SineGenerator', properties: { frequency: '2' }, activity: { period: 0.01, priority: 0, scheduler: 'other' } },
    { name: 'Amp', type: 'Gain', properties: { k: '3' } },
    { name: 'Gate', type: 'ThresholdDetector', properties: {} },
  ],
  peers: [],
  connections: [{ output: 'Sine.out', input: 'Amp.in', conn_policy: { type: 'data', transport: 'dds', topic: 'sine', qos: { reliability: 'reliable' } } }],
  // A port the palette's fresh ThresholdDetector lacks (as ports made at configure are missing there).
  deployments: [{ name: 'gated', scope: '', components: ['Gate'], connections: [{ output: 'Amp.out', input: 'Gate.limit', conn_policy: { type: 'data' } }] }],
  configurations: [], configure: ['Sine', 'Amp'], start: ['Sine', 'Amp'], apply: [],
};
/** GET /api/editor/running's answer while `deployment` ("" none) is in force since `t` s. */
function runningAnswer(deployment, t) {
  const applied = RUNNING_PROJECT.deployments.find((d) => d.name === deployment);
  return {
    live: true, taken: 'at setup; deployments of now',
    now: {
      t, switches: deployment ? 1 : 0, deployments: [{ scope: '', deployment }], configuration: '',
      running: [...RUNNING_PROJECT.start, ...(applied?.components ?? [])],
      connections: [...RUNNING_PROJECT.connections, ...(applied?.connections ?? [])],
    },
    project: { ...RUNNING_PROJECT, apply: applied ? [deployment] : [] },
  };
}
const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.txt': 'text/plain' };
const LOGIC = new Set(['Event', 'TaskState']);

export function loadPalette() {
  const palette = JSON.parse(readFileSync(join(FIXTURES, 'editor/palette.json'), 'utf8'));
  const dataTypes = [...palette.data_types, FORCE_SAMPLE].sort((a, b) => (a.name < b.name ? -1 : 1)); // by name, as cobra's
  return { packages: [...palette.packages, FORCE_WATCH.package], types: [...palette.types, FORCE_WATCH], data_types: dataTypes };
}

const kind = (type) => (LOGIC.has(type) ? 'logic' : 'pure');

/** Port `full` ("Comp.port") of the project, or { error } with a did-you-mean. */
function port(palette, project, full) {
  const [name, portName] = full.split('.');
  const component = project.components.find((c) => c.name === name);
  if (!component) return { error: `no component '${name}' (in '${full}')` };
  const type = palette.types.find((t) => t.type === component.type);
  const found = type.ports.find((p) => p.name === portName);
  if (found) return { component, type, port: found };
  const near = type.ports.find((p) => p.name.toLowerCase().startsWith(portName.slice(0, 3).toLowerCase()));
  return { error: `${type.type} '${name}' has no port '${portName}'${near ? `; did you mean '${near.name}'?` : ''}` };
}

/** deploy/lint.hpp's rules, in its message form (without a file:line). */
function lint(from, to) {
  const out = [];
  const head = `${from.component.name}.${from.port.name} (${from.type.role}) -> ${to.component.name}.${to.port.name} (${to.type.role}): `;
  const k = kind(from.port.type);
  const report = (rule) => out.push({ rule, message: `${head}${rule}, but ${from.port.type} is ${k} data` });
  if (from.port.name !== 'events') {
    if (from.type.role === 'Calculation' && k !== 'pure') report('a Calculation component may write only pure data');
    if (from.type.role === 'Supervision' && k !== 'logic') report('a Supervision component may write only logic data');
    if (from.type.role === 'Decision' && k !== 'logic') report('a Decision component may write only logic data');
  }
  if (to.type.role === 'Calculation' && k !== 'pure') report('a Calculation component may read only pure data');
  if (to.type.role === 'Decision' && k !== 'pure') report('a Decision component may read only pure data');
  if (to.type.role === 'Supervision' && k !== 'logic') report('a Supervision component may read only logic data');
  return out;
}

/** The check route's answer for one connection. */
export function check(palette, project, connection) {
  const from = port(palette, project, connection.output);
  if (from.error) return { ok: false, reason: from.error, lint: [] };
  const to = port(palette, project, connection.input);
  if (to.error) return { ok: false, reason: to.error, lint: [] };
  if (from.port.direction !== 'out') return { ok: false, reason: `'${connection.output}' is an input port; a connection starts at an output port`, lint: [] };
  if (to.port.direction !== 'in') return { ok: false, reason: `'${connection.input}' is an output port; a connection ends at an input port`, lint: [] };
  if (from.port.type !== to.port.type) {
    return { ok: false, reason: `types differ: '${connection.output}' writes ${from.port.type}, '${connection.input}' reads ${to.port.type}`, lint: [] };
  }
  return { ok: true, reason: '', lint: lint(from, to) };
}

function propertyProblem(property, text) {
  const number = Number(text);
  if (property.type === 'bool') return text === 'true' || text === 'false' ? null : `'${text}' is not a bool (true or false)`;
  if (property.type === 'int' && !/^-?\d+$/.test(text)) return `'${text}' is not an int`;
  if (property.type === 'double' && (text.trim() === '' || !Number.isFinite(number))) return `'${text}' is not a double`;
  if (property.range && (property.type === 'int' || property.type === 'double') && (number < property.range[0] || number > property.range[1])) {
    return `${text} is out of its range [${property.range[0]}, ${property.range[1]}]`;
  }
  return null;
}

/** The validate route's answer: properties, activities, peers and every connection of the project. */
export function validate(palette, project) {
  const problems = [];
  const lints = [];
  for (const c of project.components) {
    const type = palette.types.find((t) => t.type === c.type);
    if (!type) {
      problems.push({ where: `component '${c.name}'`, message: `no component type '${c.type}' in the loaded packages` });
      continue;
    }
    for (const [name, text] of Object.entries(c.properties ?? {})) {
      const property = type.properties.find((p) => p.name === name);
      const message = property ? propertyProblem(property, text) : `${c.type} has no property '${name}'`;
      if (message) problems.push({ where: `component '${c.name}' property '${name}'`, message });
    }
    if (c.activity && !(c.activity.period >= 0)) problems.push({ where: `activity of '${c.name}'`, message: 'period must be >= 0 s' });
  }
  for (const p of project.peers) {
    for (const q of p.peers) {
      if (!project.components.some((c) => c.name === q)) problems.push({ where: `peers of '${p.component}'`, message: `no component '${q}'` });
    }
  }
  for (const c of [...project.connections, ...project.deployments.flatMap((d) => d.connections)]) {
    const answer = check(palette, project, c);
    if (!answer.ok) problems.push({ where: `connection '${c.output}' -> '${c.input}'`, message: answer.reason });
    lints.push(...answer.lint);
  }
  return { problems, lint: lints };
}

/** A Lua text of the saved project (the fixture's stand-in for the server's writer). */
function luaText(project) {
  const rows = project.components.map((c) => `  { peer_name = "${c.name}", component_type = "${c.type}" },`);
  const connections = project.connections.map((c) => `  { output = "${c.output}", input = "${c.input}" },`);
  return `initConfigurator({ ${project.packages.map((p) => `"${p}"`).join(', ')} }, {\n${rows.join('\n')}\n})\nconnectPorts({\n${connections.join('\n')}\n})\n`;
}

const EMPTY = { packages: [], components: [], peers: [], connections: [], deployments: [], configurations: [], configure: [], start: [], apply: [] };

/** Starts the server on 127.0.0.1; resolves to { url, pageUrl, saves, generated, checks, close() }. */
export async function startEditorFixture(mode = 'new') {
  const palette = loadPalette();
  const saves = [];
  const generated = [];
  const checks = [];
  const running = { deployment: '', t: 0, reads: 0 };
  const malformed = { error: BAD_ERROR, path: BAD_FILE, line: BAD_LINE, text: BAD_TEXT };
  const routes = {
    'GET /api/editor/palette': () => [200, palette],
    'GET /api/editor/project': () => (mode === 'malformed' ? [422, malformed] : [200, { path: '', text: '', project: EMPTY }]),
    'POST /api/editor/open': ({ path }) => (path === BAD_FILE ? [422, malformed] : [404, { error: `${path}: no such file or application folder` }]),
    'POST /api/editor/check': ({ project, connection }) => {
      checks.push(connection);
      return [200, check(palette, project, connection)];
    },
    'POST /api/editor/validate': ({ project }) => [200, validate(palette, project)],
    'POST /api/editor/save': ({ path, project }) => {
      if (path === BAD_FILE) return [409, { error: `${path}: opened with an error; not overwritten` }];
      saves.push({ path, project });
      return [200, { path, text: luaText(project) }];
    },
    'POST /api/editor/generate': ({ folder, component }) => {
      if (!folder) return [400, { error: 'generate: no package folder given' }];
      if (!['calculation', 'supervision', 'decision', 'bridge'].includes(component.role)) {
        return [400, { error: `role '${component.role}' must be calculation, supervision, decision or bridge` }];
      }
      // The generator's types: the palette's data types flagged generate (by name; cobra's also
      // takes short names, KDL.Frame as Frame, which the page does not send).
      const known = palette.data_types.filter((d) => d.generate).map((d) => d.name);
      for (const list of ['inputs', 'event_inputs', 'outputs', 'properties']) {
        for (const m of component[list]) {
          const item = `${m.name}:${m.type}${m.unit ? `:${m.unit}` : ''}`;
          if (!known.includes(m.type)) return [400, { error: `component.${list} '${item}': unknown type '${m.type}'; the types are: ${known.join(', ')}` }];
        }
      }
      generated.push({ folder, component });
      const file = component.name.replace(/([a-z])([A-Z])/g, '$1_$2').toLowerCase();
      return [200, { files: [`${folder}/include/${component.package}/${file}.hpp`, `${folder}/src/${file}.cpp`, `${folder}/test/${file}_test.cpp`] }];
    },
    'GET /api/editor/running': () => {
      if (mode !== 'running') return [404, { error: 'no run here: GET /api/editor/running is served by `cobra run APP --studio`' }];
      running.reads += 1;
      return [200, runningAnswer(running.deployment, running.t)];
    },
  };
  const server = createServer((req, res) => {
    const url = new URL(req.url, 'http://127.0.0.1');
    if (tokenOf(req, url) !== TOKEN) return json(res, 403, { error: 'missing or wrong token' });
    const route = routes[`${req.method} ${url.pathname}`];
    if (route) {
      let body = '';
      req.on('data', (chunk) => { body += chunk; });
      req.on('end', () => {
        const [status, answer] = route(body ? JSON.parse(body) : {});
        json(res, status, answer);
      });
      return undefined;
    }
    const file = normalize(join(DIST, url.pathname === '/' ? 'editor.html' : url.pathname));
    if (!file.startsWith(DIST) || !existsSync(file)) return json(res, 404, { error: `no file ${url.pathname}` });
    const headers = { 'Content-Type': TYPES[extname(file)] ?? 'application/octet-stream' };
    // As the real server: a page asked with the token sets the cookie its assets are then asked with.
    if (extname(file) === '.html') headers['Set-Cookie'] = `cobra_token=${TOKEN}; HttpOnly; SameSite=Strict`;
    res.writeHead(200, headers);
    return res.end(readFileSync(file));
  });
  // The console's WebSocket: frames carry each scope's deployment in force (PROTOCOL.md).
  const sockets = new Set();
  const wss = new WebSocketServer({ noServer: true });
  const frame = () => JSON.stringify({ type: 'frame', t: running.t, deployments: { '': running.deployment }, configurations: { '': '' } });
  server.on('upgrade', (req, socket, head) => {
    const url = new URL(req.url, 'http://127.0.0.1');
    if (mode !== 'running' || url.pathname !== '/ws' || tokenOf(req, url) !== TOKEN) {
      socket.end('HTTP/1.1 403 Forbidden\r\n\r\n');
      return;
    }
    wss.handleUpgrade(req, socket, head, (ws) => {
      sockets.add(ws);
      ws.on('close', () => sockets.delete(ws));
      ws.send(frame());
    });
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  const url = `http://127.0.0.1:${server.address().port}/`;
  return {
    url, pageUrl: `${url}editor.html?token=${TOKEN}`, saves, generated, checks, running,
    sockets: () => sockets.size,
    /** The run switches to deployment `name` at `t` s: three frames name it. */
    switchTo(name, t) {
      running.deployment = name;
      running.t = t;
      for (let i = 0; i < 3; i += 1) for (const ws of sockets) ws.send(frame());
    },
    close: () => closeServer(server, wss, sockets),
  };
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const server = await startEditorFixture(process.argv[2] ?? 'new');
  console.log(`fixture editor: ${server.pageUrl}`);
}
