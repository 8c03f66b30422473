// The deployment editor page (thesis §3.2.1, OroEdit) of cobra studio: a palette of the
// loaded component types, a canvas where blocks are placed and connected (each connection asked of
// the server first: made only when its types match, with the role linter's verdict), an inspector,
// tabs for named deployments and configurations, and files opened and saved as the Configurator's
// Lua tables by the server (studio/PROTOCOL.md "The editor (v1)").
import './editor.css';
import { api } from './editor_api.js';
import { BLOCK_WIDTH, blockHeight, createCanvas } from './editor_canvas.js';
import { setUpTypeDialog, showFile } from './editor_files.js';
import {
  BASE_TAB, addComponent, createHistory, addConfiguration, addConnection, addDeployment, connectionsOf, emptyProject, instanceNameError,
  moveComponent, normalizeProject, orderEnds, parseActivity, parsePolicy, removeComponent, removeConnection,
  setConfigurationValue, setInDeployment, setPeers, setProperty, suggestName, typeOf,
} from './editor_model.js';
import { drawConfiguration, drawInspector, drawPalette, drawProblems, drawTabs, refreshFieldProblems } from './editor_panels.js';
import { connectLive } from './source.js';

const $ = (id) => document.getElementById(id);
const VALIDATE_DELAY_MS = 250;
/** "A.x (Role) -> B.y (Role): ..." : the connection a lint message is about (deploy/lint.hpp's form). */
const LINT_HEAD = /(?:^|: )([\w]+\.[\w]+) \(\w+\) -> ([\w]+\.[\w]+) \(\w+\): /;

const state = {
  palette: { packages: [], types: [] },
  project: emptyProject(),
  tab: BASE_TAB,
  tabKind: 'deployment',
  selection: null,
  pending: null, // the first port clicked of a connection being drawn
  refusal: null, // { at: "Comp.port", text }: the server's reason next to the port
  lint: new Map(), // "out->in" -> [{ rule, message }]
  problems: [],
  path: '',
  savable: true, // false while the opened file did not load: the page never saves over it
  busy: 0,
};

const history = createHistory();
/** Keeps the project as it is before an edit, for Undo. */
const remember = () => history.remember(state.project);

function status(text, kind = 'info') {
  const bar = $('status');
  bar.textContent = text;
  bar.className = kind;
}

function showError(text) {
  $('error').hidden = !text;
  $('error').textContent = text ?? '';
}

const canvas = createCanvas($('canvas'), () => state, {
  select: (selection) => {
    state.selection = selection;
    if (!selection) state.pending = null;
    redraw();
  },
  move: (name, x, y) => {
    remember();
    moveComponent(state.project, name, x, y);
    redraw();
  },
  port: (end) => connectPorts(end),
  drop: (typeName, x, y) => placeComponent(typeName, x, y),
});

function redraw() {
  const configurationTab = state.tabKind === 'configuration';
  $('canvas-wrap').hidden = configurationTab;
  $('configuration-view').hidden = !configurationTab;
  drawTabs($('tabs'), state, { tab: selectTab, addTab });
  if (configurationTab) drawConfiguration($('configuration-view'), state, handlers);
  else canvas.draw();
  drawInspector($('inspector'), state, handlers);
  drawProblems($('problem-list'), state, selectFromProblem);
  $('save').disabled = !state.savable;
  $('undo').disabled = history.size === 0;
  $('save').title = state.savable ? 'write the project as Configurator tables (and its layout sidecar)' : 'the opened file did not load: it is never saved over';
}

let validateTimer = null;
let validatePending = false;
/** Asks the server to check the whole project (debounced); its problems show by the fields. */
function edited() {
  redraw();
  clearTimeout(validateTimer);
  validatePending = true;
  validateTimer = setTimeout(validate, VALIDATE_DELAY_MS);
}

async function validate() {
  validatePending = false;
  state.busy += 1;
  try {
    const answer = await api.validate(state.project);
    state.problems = answer.problems ?? [];
    for (const l of answer.lint ?? []) {
      const m = LINT_HEAD.exec(l.message);
      if (!m) continue;
      const key = `${m[1]}->${m[2]}`;
      const known = state.lint.get(key) ?? [];
      if (!known.some((k) => k.message === l.message)) state.lint.set(key, [...known, l]);
    }
    // Not redraw(): the inspector's fields would be drawn again under the user's typing.
    if (state.tabKind === 'deployment') canvas.draw();
    refreshFieldProblems(document.body, state);
    drawProblems($('problem-list'), state, selectFromProblem);
  } catch (err) {
    status(`validate: ${err.message}`, 'error');
  } finally {
    state.busy -= 1;
  }
}

function selectTab(id, kind) {
  state.tab = id;
  state.tabKind = kind;
  state.selection = null;
  state.pending = null;
  state.refusal = null;
  redraw();
}

/** Asks a name in the page's dialog; resolves to the name (checked by `check`) or null. */
function askName(title, suggestion, check, extra = null) {
  const dialog = $('name-dialog');
  $('name-title').textContent = title;
  $('name-input').value = suggestion;
  $('name-error').textContent = '';
  $('name-extra').hidden = !extra;
  $('name-extra-label').textContent = extra ?? '';
  $('name-extra-input').value = '';
  dialog.showModal();
  $('name-input').select();
  return new Promise((resolve) => {
    const done = (value) => {
      $('name-form').onsubmit = null;
      $('name-cancel').onclick = null;
      dialog.close();
      resolve(value);
    };
    $('name-form').onsubmit = (e) => {
      e.preventDefault();
      const name = $('name-input').value.trim();
      const error = check(name);
      if (error) {
        $('name-error').textContent = error;
        return;
      }
      done({ name, extra: $('name-extra-input').value.trim() });
    };
    $('name-cancel').onclick = () => done(null);
  });
}

async function placeComponent(typeName, x, y) {
  const type = typeOf(state.palette, typeName);
  if (!type || type.generated) return;
  const answer = await askName(`Name of the new ${typeName}`, suggestName(state.project, typeName), (n) => instanceNameError(state.project, n));
  if (!answer) return;
  remember();
  addComponent(state.project, state.tabKind === 'deployment' ? state.tab : BASE_TAB, type, answer.name, x, y);
  state.selection = { kind: 'component', name: answer.name };
  status(`placed ${typeName} '${answer.name}'`);
  edited();
}

async function addTab(kind) {
  const deployment = kind === 'deployment';
  const taken = (n) => (deployment ? state.project.deployments : state.project.configurations).some((d) => d.name === n);
  const answer = await askName(`Name of the new ${kind}`, '', (n) => (taken(n) ? `a ${kind} named '${n}' exists already` : (/^[A-Za-z_]\w*$/.test(n) ? null : `'${n}' is not an identifier`)),
    deployment ? 'scope (deployments of one scope replace each other; empty: none)' : null);
  if (!answer) return;
  remember();
  if (deployment) addDeployment(state.project, answer.name, answer.extra);
  else addConfiguration(state.project, answer.name);
  selectTab(answer.name, kind);
  edited();
}

/** A port clicked: the first end, or the second (the connection is asked of the server). */
async function connectPorts(end) {
  state.refusal = null;
  if (!state.pending) {
    state.pending = end;
    status(`${end.name}: now click the ${end.direction === 'out' ? 'input' : 'output'} to connect it to`);
    return redraw();
  }
  const first = state.pending;
  state.pending = null;
  const ends = orderEnds(first, end);
  if (ends.error) {
    state.refusal = { at: end.name, text: ends.error };
    status(ends.error, 'error');
    return redraw();
  }
  const connection = { output: ends.output, input: ends.input, conn_policy: { type: 'data' } };
  state.busy += 1;
  try {
    const answer = await api.check(state.project, connection);
    if (!answer.ok) {
      state.refusal = { at: ends.input, text: answer.reason };
      status(`refused: ${answer.reason}`, 'error');
      return redraw();
    }
    remember();
    addConnection(state.project, state.tab, connection);
    state.lint.set(`${ends.output}->${ends.input}`, answer.lint ?? []);
    state.selection = { kind: 'connection', key: `${ends.output}->${ends.input}`, output: ends.output, input: ends.input };
    status(answer.lint?.length ? `connected, but: ${answer.lint.map((l) => l.message).join('; ')}` : `connected ${ends.output} -> ${ends.input}`,
      answer.lint?.length ? 'warning' : 'info');
    return edited();
  } catch (err) {
    state.refusal = { at: ends.input, text: err.message };
    status(err.message, 'error');
    return redraw();
  } finally {
    state.busy -= 1;
  }
}

const handlers = {
  property: (name, property, text) => {
    remember();
    setProperty(state.project.components.find((c) => c.name === name), property, text);
    edited();
  },
  activity: (name, fields) => {
    const component = state.project.components.find((c) => c.name === name);
    try {
      const activity = parseActivity(fields);
      remember();
      if (activity) component.activity = activity;
      else delete component.activity;
      status(`${name}: activity ${activity ? `every ${activity.period} s` : 'removed (triggered)'}`);
      edited();
    } catch (err) {
      status(`${name}: ${err.message}`, 'error');
    }
  },
  lifecycle: (name, list, on) => {
    remember();
    state.project[list] = state.project[list].filter((c) => c !== name);
    if (on) state.project[list].push(name);
    edited();
  },
  peers: (name, peers) => {
    remember();
    setPeers(state.project, name, peers);
    edited();
  },
  membership: (name, member) => {
    remember();
    setInDeployment(state.project, state.tab, name, member);
    edited();
  },
  deleteComponent: (name) => {
    remember();
    removeComponent(state.project, name);
    for (const key of [...state.lint.keys()]) if (key.split('->').some((end) => end.split('.')[0] === name)) state.lint.delete(key);
    state.selection = null;
    edited();
  },
  policy: (connection, fields) => {
    try {
      const policy = parsePolicy(fields);
      remember();
      connection.conn_policy = policy;
      status(`${connection.output} -> ${connection.input}: ${connection.conn_policy.type}`);
      edited();
    } catch (err) {
      status(err.message, 'error');
    }
  },
  deleteConnection: (connection) => {
    remember();
    removeConnection(state.project, state.tab, connection.output, connection.input);
    if (!connectionsOf(state.project, BASE_TAB).concat(...state.project.deployments.map((d) => d.connections))
      .some((c) => c.output === connection.output && c.input === connection.input)) state.lint.delete(`${connection.output}->${connection.input}`);
    state.selection = null;
    edited();
  },
  configurationValue: (configuration, key, text) => {
    try {
      const before = structuredClone(state.project);
      setConfigurationValue(state.palette, state.project, configuration, key, text);
      history.remember(before);
      edited();
    } catch (err) {
      status(err.message, 'error');
    }
  },
};

/** A problem clicked: its component or connection selected (on the base tab when it is not in this one). */
function selectFromProblem(selection) {
  if (selection.kind === 'connection' && !connectionsOf(state.project, state.tab).some((c) => c.output === selection.output && c.input === selection.input)) {
    const owner = state.project.deployments.find((d) => d.connections.some((c) => c.output === selection.output && c.input === selection.input));
    selectTab(owner ? owner.name : BASE_TAB, 'deployment');
  }
  state.selection = selection;
  redraw();
}

/** Puts the project back as it was before the last edit. */
function undo() {
  const previous = history.undo();
  if (!previous) return status('nothing to undo');
  state.project = previous;
  state.selection = null;
  state.pending = null;
  state.refusal = null;
  if (state.tabKind === 'deployment' ? state.tab !== BASE_TAB && !state.project.deployments.some((d) => d.name === state.tab)
    : !state.project.configurations.some((c) => c.name === state.tab)) selectTab(BASE_TAB, 'deployment');
  status('undone');
  return edited();
}

/** Shows an answer of /project, /open or /running: the project, or the file that did not load. */
function loaded(answer, source) {
  // /running may answer the Project itself rather than { path, text, project }.
  state.project = normalizeProject(answer.project ?? answer, (c, project) => blockHeight(state.palette, c, project), BLOCK_WIDTH);
  state.path = answer.path ?? '';
  state.savable = true;
  history.clear();
  state.lint = new Map();
  state.problems = [];
  state.selection = null;
  selectTab(BASE_TAB, 'deployment');
  $('path').value = state.path;
  $('save-path').value = state.path;
  showFile($('file-view'), { title: state.path ? `${state.path} (as opened)` : '', text: state.path ? answer.text : null });
  status(state.path ? `opened ${state.path}: ${state.project.components.length} components, ${state.project.deployments.length} deployments` : source);
  edited();
}

function loadFailed(err, what) {
  const body = err.body ?? {};
  if (err.status === 422 && body.text != null) {
    state.project = emptyProject();
    state.savable = false;
    state.path = body.path ?? '';
    state.lint = new Map();
    state.problems = [];
    $('path').value = state.path;
    showFile($('file-view'), { title: `${state.path} (did not load: read only)`, text: body.text, errorLine: body.line, error: err.message });
    status(`${what}: ${err.message}`, 'error');
    return selectTab(BASE_TAB, 'deployment');
  }
  return status(`${what}: ${err.message}`, 'error');
}

async function open(path) {
  try {
    loaded(await api.open(path), `opened ${path}`);
  } catch (err) {
    loadFailed(err, `open ${path}`);
  }
}

async function save() {
  const path = $('save-path').value.trim();
  if (!state.savable) return status('the opened file did not load: it is never saved over', 'error');
  if (!path) return status('save: give the path of the file to write', 'error');
  try {
    const answer = await api.save(path, state.project);
    state.path = answer.path;
    showFile($('file-view'), { title: `${answer.path} (written)`, text: answer.text });
    window.cobraEditor.saved = answer;
    return status(`saved ${answer.path}`);
  } catch (err) {
    return status(`save ${path}: ${err.message}`, 'error');
  }
}

/**
 * Attached to a run (`cobra run --studio`): the run's deployments as the last GET
 * /api/editor/running gave them (its `now`), and the console's WebSocket, whose frames carry each
 * scope's deployment and configuration in force: when they change, the page reads the running
 * deployment again (no polling: it asks only when the run switched).
 */
const run = { now: null, socket: false, shown: null, reading: false, again: null };

/** "scope: deployment" of each scope in force (`now` of /running, or a frame's map). */
function inForce(deployments) {
  const entries = Array.isArray(deployments) ? deployments.map((d) => [d.scope, d.deployment]) : Object.entries(deployments ?? {});
  return entries.map(([scope, name]) => `${scope || 'default'}: ${name || '(none)'}`).join(', ');
}

/** Reads the running deployment; `byUser`: the Attach button (else a switch of the run). */
async function attach(what, byUser = false) {
  if (run.reading) {
    run.again = what; // a switch while reading: read once more after
    return;
  }
  run.reading = true;
  try {
    const answer = await api.running();
    // Edits made since the last attach are not thrown away by a switch of the run.
    if (!byUser && history.size > 0) {
      status(`the run switched (${inForce(answer.now?.deployments)}); your edits are kept: Attach to the run to see it`);
    } else {
      loaded(answer, `${what}${answer.now ? ` (t = ${answer.now.t} s; ${inForce(answer.now.deployments)})` : ''}`);
      $('save-path').value = '';
    }
    run.now = answer.now ?? null;
    window.cobraEditor.running = answer;
    follow();
  } catch (err) {
    status(`attach: ${err.message}`, 'error');
  } finally {
    run.reading = false;
  }
  if (run.again) {
    const next = run.again;
    run.again = null;
    await attach(next);
  }
}

/** The scopes whose deployment a frame and the last answer both name differ. */
function differsFromAnswer(frameDeployments) {
  return (run.now?.deployments ?? []).some((d) => d.scope in (frameDeployments ?? {}) && frameDeployments[d.scope] !== d.deployment);
}

function follow() {
  if (run.socket) return;
  run.socket = true;
  connectLive({
    frame: (msg) => {
      const shown = JSON.stringify([msg.deployments ?? {}, msg.configurations ?? {}]);
      // The first frame is compared with the answer (a switch between the two is not missed);
      // later ones with the frame before.
      const switched = run.shown === null ? differsFromAnswer(msg.deployments) : shown !== run.shown;
      run.shown = shown;
      if (switched) attach(`the run switched to ${inForce(msg.deployments)}: re-read the running deployment`);
    },
    end: () => attach('the run ended: its deployment as it ended'),
    closed: (reason) => { if (run.now) status(`${reason}; the running deployment is no longer followed`, 'error'); },
  });
}

async function start() {
  $('palette-search').addEventListener('input', (e) => drawPalette($('palette-list'), state, e.target.value));
  $('open').addEventListener('click', () => open($('path').value.trim()));
  $('path').addEventListener('keydown', (e) => { if (e.key === 'Enter') open($('path').value.trim()); });
  $('save').addEventListener('click', save);
  $('undo').addEventListener('click', undo);
  document.addEventListener('keydown', (e) => {
    if (e.target.closest('input, select, textarea')) return;
    if ((e.ctrlKey || e.metaKey) && e.key === 'z') undo();
    if (e.key === 'Escape' && state.pending) {
      state.pending = null;
      status('connection cancelled');
      redraw();
    }
  });
  $('new-type').addEventListener('click', () => $('type-dialog').showModal());
  $('attach').addEventListener('click', () => attach('attached to the running deployment', true));
  const token = new URLSearchParams(window.location.search).get('token');
  $('console-link').href = token ? `index.html?token=${encodeURIComponent(token)}` : 'index.html';
  try {
    state.palette = await api.palette();
  } catch (err) {
    showError(`palette: ${err.message}`);
  }
  drawPalette($('palette-list'), state, '');
  setUpTypeDialog($('type-dialog'), {
    palette: () => state.palette,
    generate: (folder, spec) => api.generate(folder, spec),
    added: (type) => {
      state.palette.types.push(type);
      drawPalette($('palette-list'), state, $('palette-search').value);
      status(`generated ${type.type}: build the package to use it`);
    },
  });
  try {
    loaded(await api.project(), 'a new project');
  } catch (err) {
    loadFailed(err, 'project');
  }
  api.running().then(() => { $('attach').hidden = false; }, () => {});
  window.cobraEditor.ready = true;
}

/** For tests: the page's state (project, palette, lint, problems), `saved` (the last save's answer), `running` (the last GET /api/editor/running answer). */
window.cobraEditor = { state, ready: false, saved: null, running: null, idle: () => state.busy === 0 && !validatePending };
start();
