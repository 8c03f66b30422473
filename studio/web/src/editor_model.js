// The deployment editor's document (studio/PROTOCOL.md "The editor (v1)": the Project) and its
// edits, without the DOM: the page and the unit tests (test/editor_model.test.mjs) share them.
// Every component instance lives in `project.components` (with its block position x, y in px);
// a named deployment lists the names of the instances it runs and its own connections, as the
// Configurator's defineDeployment does. A "tab" is '' for the base deployment or a deployment's name.

export const BASE_TAB = '';
export const POLICY_TYPES = ['data', 'buffer', 'circular'];
export const SCHEDULERS = ['other', 'fifo', 'rr'];
const LOGIC_TYPES = new Set(['Event', 'TaskState']);

/** A project with nothing in it. */
export function emptyProject() {
  return { packages: [], components: [], peers: [], connections: [], deployments: [], configurations: [], configure: [], start: [], apply: [] };
}

/**
 * Where blocks without a position go (px): the first column's left, the gap between columns and
 * between blocks, and the columns of a band (deeper layers wrap into the next band below).
 */
export const LAYOUT = { left: 40, top: 40, columnGap: 90, rowGap: 30, columns: 6 };

/**
 * Each component's layer: 0 for one that reads from no other, else one more than the deepest
 * component it reads from (the connections of the base deployment and of every named one), so
 * data flows left to right. A cycle is cut at the connection that closes it in a walk along the
 * data from the components that read from none (then the rest), in the project's order.
 */
export function layersOf(project) {
  const names = project.components.map((c) => c.name);
  const writesTo = new Map(names.map((n) => [n, []]));
  for (const c of [...project.connections, ...project.deployments.flatMap((d) => d.connections ?? [])]) {
    const from = String(c.output).split('.')[0];
    const to = String(c.input).split('.')[0];
    if (writesTo.has(from) && writesTo.has(to) && from !== to && !writesTo.get(from).includes(to)) writesTo.get(from).push(to);
  }
  // The walk keeps the connections that do not lead back to a component on its path.
  const readsFrom = new Map(names.map((n) => [n, []]));
  const state = new Map(); // 1: on the walk's path, 2: done
  const walk = (name) => {
    state.set(name, 1);
    for (const to of writesTo.get(name)) {
      if (state.get(to) === 1) continue;
      readsFrom.get(to).push(name);
      if (!state.has(to)) walk(to);
    }
    state.set(name, 2);
  };
  const sources = names.filter((n) => ![...writesTo.values()].some((list) => list.includes(n)));
  for (const n of [...sources, ...names]) if (!state.has(n)) walk(n);
  const layer = new Map();
  const depth = (name) => {
    if (!layer.has(name)) layer.set(name, Math.max(-1, ...readsFrom.get(name).map(depth)) + 1);
    return layer.get(name);
  };
  for (const n of names) depth(n);
  return layer;
}

/**
 * The project as the page keeps it: every list present, deployment components as names (an entry
 * given as an object is reduced to its name), every component with a position. Those without one
 * (a project opened without a layout sidecar) are laid out in layers (layersOf: a column per
 * layer, BLOCK_WIDTH + columnGap apart, at most LAYOUT.columns side by side, deeper ones in bands
 * below) below the placed ones, each column's blocks stacked `rowGap` apart by their heights, so
 * no two blocks overlap. `heightOf(component, project)`: a
 * block's height in px, `width`: its width.
 */
export function normalizeProject(input, heightOf = () => 160, width = 210) {
  const project = { ...emptyProject(), ...structuredClone(input ?? {}) };
  for (const key of Object.keys(emptyProject())) if (!Array.isArray(project[key])) project[key] = [];
  for (const d of project.deployments) {
    d.components = (d.components ?? []).map((c) => (typeof c === 'string' ? c : c.name));
    d.connections ??= [];
  }
  for (const c of project.configurations) c.values ??= {};
  const placed = (c) => Number.isFinite(c.x) && Number.isFinite(c.y);
  let top = Math.max(LAYOUT.top, ...project.components.filter(placed).map((c) => c.y + heightOf(c, project) + LAYOUT.rowGap));
  const layers = layersOf(project);
  const unplaced = project.components.filter((c) => !placed(c));
  for (const c of project.components) c.properties ??= {};
  // Layers beyond `columns` wrap into bands below, each band as tall as its tallest column.
  const deepest = Math.max(-1, ...unplaced.map((c) => layers.get(c.name)));
  for (let band = 0; band * LAYOUT.columns <= deepest; band += 1) {
    let bottom = top;
    for (let column = 0; column < LAYOUT.columns; column += 1) {
      let y = top;
      for (const c of unplaced.filter((k) => layers.get(k.name) === band * LAYOUT.columns + column)) {
        c.x = LAYOUT.left + column * (width + LAYOUT.columnGap);
        c.y = y;
        y += heightOf(c, project) + LAYOUT.rowGap;
      }
      bottom = Math.max(bottom, y);
    }
    top = bottom + LAYOUT.rowGap;
  }
  return project;
}

/** The pairs of components whose blocks (x, y, width, heightOf) intersect: [] when none overlap. */
export function overlappingBlocks(project, heightOf, width = 210) {
  const boxes = project.components.map((c) => ({ name: c.name, x: c.x, y: c.y, right: c.x + width, bottom: c.y + heightOf(c, project) }));
  const pairs = [];
  for (const [i, a] of boxes.entries()) {
    for (const b of boxes.slice(i + 1)) {
      if (a.x < b.right && b.x < a.right && a.y < b.bottom && b.y < a.bottom) pairs.push([a.name, b.name]);
    }
  }
  return pairs;
}

/** True for a Lua identifier (what a component instance is named by in a deployment file). */
export function isIdentifier(name) {
  return /^[A-Za-z_][A-Za-z0-9_]*$/.test(name);
}

/** Why `name` cannot name a new instance (empty, not an identifier, taken), or null. */
export function instanceNameError(project, name) {
  if (!name) return 'a component needs a name';
  if (!isIdentifier(name)) return `'${name}' is not an identifier (letters, digits, _; not starting with a digit)`;
  if (project.components.some((c) => c.name === name)) return `a component named '${name}' exists already`;
  return null;
}

/** The first free name TypeN (N = 1, 2, ...) built from the type's capitals, e.g. VariableAdmittance -> VA1. */
export function suggestName(project, type) {
  const stem = type.replace(/[^A-Z]/g, '') || type;
  for (let n = 1; ; n += 1) if (!project.components.some((c) => c.name === `${stem}${n}`)) return `${stem}${n}`;
}

export function deploymentOf(project, tab) {
  return tab === BASE_TAB ? null : project.deployments.find((d) => d.name === tab) ?? null;
}

/** The connections a tab edits: the base deployment's or a named deployment's own. */
export function connectionsOf(project, tab) {
  return tab === BASE_TAB ? project.connections : deploymentOf(project, tab)?.connections ?? [];
}

/** True when the tab runs the component (the base tab runs them all). */
export function inTab(project, tab, name) {
  return tab === BASE_TAB || (deploymentOf(project, tab)?.components.includes(name) ?? false);
}

/** Adds an instance of palette type `type` at (x, y); on a deployment tab the deployment runs it. */
export function addComponent(project, tab, type, name, x, y) {
  const error = instanceNameError(project, name);
  if (error) throw new Error(error);
  const component = { name, type: type.type, x: Math.round(x), y: Math.round(y), properties: {} };
  project.components.push(component);
  if (type.package && !project.packages.includes(type.package)) project.packages.push(type.package);
  deploymentOf(project, tab)?.components.push(name);
  return component;
}

const touches = (name) => (c) => c.output.split('.')[0] === name || c.input.split('.')[0] === name;

/** Removes an instance and everything naming it: connections, peers, deployments, values, lists. */
export function removeComponent(project, name) {
  project.components = project.components.filter((c) => c.name !== name);
  project.connections = project.connections.filter((c) => !touches(name)(c));
  for (const d of project.deployments) {
    d.components = d.components.filter((c) => c !== name);
    d.connections = d.connections.filter((c) => !touches(name)(c));
  }
  project.peers = project.peers
    .filter((p) => p.component !== name)
    .map((p) => ({ ...p, peers: p.peers.filter((q) => q !== name) }))
    .filter((p) => p.peers.length > 0);
  for (const c of project.configurations) {
    for (const key of Object.keys(c.values)) if (key.split('.')[0] === name) delete c.values[key];
  }
  for (const list of ['configure', 'start']) project[list] = project[list].filter((c) => c !== name);
}

export function moveComponent(project, name, x, y) {
  const c = project.components.find((k) => k.name === name);
  c.x = Math.round(x);
  c.y = Math.round(y);
}

/** The palette entry of a type name, or undefined. */
export function typeOf(palette, typeName) {
  return palette.types.find((t) => t.type === typeName);
}

/** { component, type, port } of "Comp.port" in the project, or null when any part is unknown. */
export function findPort(palette, project, full) {
  const [name, portName] = full.split('.');
  const component = project.components.find((c) => c.name === name);
  const type = component && typeOf(palette, component.type);
  const port = type?.ports.find((p) => p.name === portName);
  return port ? { component, type, port } : null;
}

/**
 * The connection two clicked port handles {name: "Comp.port", direction} make, whichever was
 * clicked first (OroEdit let one draw from either end): { output, input } or { error }. The
 * server decides the rest (types, roles).
 */
export function orderEnds(first, second) {
  if (first.name === second.name) return { error: `${first.name}: a port cannot be connected to itself` };
  if (first.direction === second.direction) {
    const what = first.direction === 'out' ? 'outputs' : 'inputs';
    return { error: `${first.name} and ${second.name} are both ${what}: a connection goes from an output to an input` };
  }
  return first.direction === 'out' ? { output: first.name, input: second.name } : { output: second.name, input: first.name };
}

/** Adds a connection to a tab, refusing one the tab has already. */
export function addConnection(project, tab, connection) {
  const list = connectionsOf(project, tab);
  if (list.some((c) => c.output === connection.output && c.input === connection.input)) {
    throw new Error(`${connection.output} -> ${connection.input} is connected already`);
  }
  list.push({ output: connection.output, input: connection.input, conn_policy: { type: 'data', ...connection.conn_policy } });
}

export function removeConnection(project, tab, output, input) {
  const list = connectionsOf(project, tab);
  const i = list.findIndex((c) => c.output === output && c.input === input);
  if (i >= 0) list.splice(i, 1);
}

/**
 * A connection policy from the inspector's fields (texts): `type` data|buffer|circular, `size` a
 * positive integer for buffer and circular (samples), transport and topic kept when given, qos a
 * JSON object of texts.
 * Throws a message naming the field.
 */
export function parsePolicy(fields) {
  if (!POLICY_TYPES.includes(fields.type)) throw new Error(`policy type '${fields.type}': expected one of ${POLICY_TYPES.join(', ')}`);
  const policy = { type: fields.type };
  if (fields.type !== 'data') {
    const size = Number(fields.size);
    if (!Number.isInteger(size) || size < 1) throw new Error(`policy size '${fields.size ?? ''}': expected a whole number of samples >= 1 for a ${fields.type}`);
    policy.size = size;
  }
  for (const key of ['transport', 'topic']) if (fields[key]) policy[key] = fields[key];
  if (fields.qos) {
    // QoS settings are a table of texts (the dds transport's connections):
    // { "reliability": "reliable", ... }.
    let qos;
    try {
      qos = JSON.parse(fields.qos);
    } catch {
      qos = null;
    }
    if (qos === null || typeof qos !== 'object' || Array.isArray(qos) || Object.values(qos).some((v) => typeof v !== 'string')) {
      throw new Error(`policy qos '${fields.qos}': expected a JSON object of texts, e.g. { "reliability": "reliable" }`);
    }
    policy.qos = qos;
  }
  return policy;
}

/** Sets a property's text ('' puts the type's default back: the file then does not set it). */
export function setProperty(component, name, text) {
  if (text.trim() === '') delete component.properties[name];
  else component.properties[name] = text.trim();
}

/**
 * The activity from the inspector's fields: period (s, >= 0; 0 or empty: triggered, no
 * activity entry), priority (an integer), scheduler. Throws a message naming the field.
 */
export function parseActivity(fields) {
  if (fields.period === '' || fields.period == null) return null;
  const period = Number(fields.period);
  if (!Number.isFinite(period) || period < 0) throw new Error(`activity period '${fields.period}': expected seconds >= 0`);
  const priority = fields.priority === '' || fields.priority == null ? 0 : Number(fields.priority);
  if (!Number.isInteger(priority)) throw new Error(`activity priority '${fields.priority}': expected an integer`);
  const scheduler = fields.scheduler || 'other';
  if (!SCHEDULERS.includes(scheduler)) throw new Error(`activity scheduler '${scheduler}': expected one of ${SCHEDULERS.join(', ')}`);
  return { period, priority, scheduler };
}

/** The peers of a component (names it may call), set as a whole; an empty list removes the entry. */
export function setPeers(project, name, peers) {
  project.peers = project.peers.filter((p) => p.component !== name);
  if (peers.length > 0) project.peers.push({ component: name, peers: [...peers] });
}

export function peersOf(project, name) {
  return project.peers.find((p) => p.component === name)?.peers ?? [];
}

/** Whether the deployment `tab` runs component `name` (ignored on the base tab, which runs all). */
export function setInDeployment(project, tab, name, member) {
  const d = deploymentOf(project, tab);
  if (!d) return;
  d.components = d.components.filter((c) => c !== name);
  if (member) d.components.push(name);
}

export function addDeployment(project, name, scope) {
  if (!isIdentifier(name)) throw new Error(`deployment '${name}': a name is an identifier`);
  if (project.deployments.some((d) => d.name === name)) throw new Error(`a deployment named '${name}' exists already`);
  const d = { name, components: [], connections: [] };
  if (scope) d.scope = scope;
  project.deployments.push(d);
  return d;
}

export function addConfiguration(project, name) {
  if (!isIdentifier(name)) throw new Error(`configuration '${name}': a name is an identifier`);
  if (project.configurations.some((c) => c.name === name)) throw new Error(`a configuration named '${name}' exists already`);
  const c = { name, values: {} };
  project.configurations.push(c);
  return c;
}

/** Sets "Comp.property" in a configuration ('' removes it); the property must exist. */
export function setConfigurationValue(palette, project, configuration, key, text) {
  const [name, property] = key.split('.');
  const component = project.components.find((c) => c.name === name);
  if (!component) throw new Error(`configuration '${configuration.name}': no component '${name}'`);
  if (!typeOf(palette, component.type)?.properties.some((p) => p.name === property)) {
    throw new Error(`configuration '${configuration.name}': ${component.type} '${name}' has no property '${property}'`);
  }
  if (text.trim() === '') delete configuration.values[key];
  else configuration.values[key] = text.trim();
}

/** Logic data (events, state names) or pure data (numbers, geometry): as cobra's DataKind. */
export function kindOf(typeName) {
  return LOGIC_TYPES.has(typeName) ? 'logic' : 'pure';
}

/**
 * The palette grouped by package (packages in the palette's order), keeping the types whose name,
 * role, doc, port or property names contain every word of `query` (case-insensitive).
 */
export function paletteGroups(palette, query = '') {
  const words = query.toLowerCase().split(/\s+/).filter(Boolean);
  const text = (t) => [t.type, t.role, t.doc, ...t.ports.map((p) => p.name), ...t.properties.map((p) => p.name)].join(' ').toLowerCase();
  const kept = palette.types.filter((t) => words.every((w) => text(t).includes(w)));
  const packages = [...palette.packages, ...kept.map((t) => t.package).filter((p) => !palette.packages.includes(p))];
  return [...new Set(packages)]
    .map((name) => ({ package: name, types: kept.filter((t) => t.package === name) }))
    .filter((g) => g.types.length > 0);
}

/**
 * The data types the component generator writes ports and properties of, by their palette names,
 * in the palette's order: its `data_types` flagged `generate` (registered with a C++ spelling),
 * cobra's own and those of the loaded packages (a package's record, e.g. example.ForceSample).
 */
export function generatorTypes(palette) {
  return (palette.data_types ?? []).filter((d) => d.generate).map((d) => d.name);
}

/**
 * The palette entry of a generated type (POST /api/editor/generate's request): shown in the
 * palette, marked generated, and not placeable until its package is built and loaded.
 */
export function generatedType(spec) {
  const port = (direction, event) => (p) => ({ name: p.name, direction, type: p.type, event, unit: p.unit ?? '', doc: p.doc ?? '' });
  return {
    type: spec.name, package: spec.package, role: spec.role.charAt(0).toUpperCase() + spec.role.slice(1), doc: spec.doc ?? '', generated: true,
    ports: [...spec.inputs.map(port('in', false)), ...spec.event_inputs.map(port('in', true)), ...spec.outputs.map(port('out', false))],
    properties: spec.properties.map((p) => ({ name: p.name, type: p.type, unit: p.unit ?? '', doc: p.doc ?? '', range: null, default: '', read_only: false })),
    operations: [],
  };
}

/** Problems of a validate answer keyed by their `where` ("component 'Adm' property 'stiffness'", ...). */
export function problemsByWhere(problems) {
  const map = new Map();
  for (const p of problems) map.set(p.where, [...(map.get(p.where) ?? []), p.message]);
  return map;
}

/** The `where` text the server gives a property's problem (studio/PROTOCOL.md). */
export function propertyWhere(component, property) {
  return `component '${component}' property '${property}'`;
}

/**
 * The undo history: copies of the project taken before each edit, the newest `limit` kept.
 * `undo(current)` gives the project before the last edit, or null when there is none.
 */
export function createHistory(limit = 100) {
  const before = [];
  return {
    remember(project) {
      before.push(structuredClone(project));
      if (before.length > limit) before.shift();
    },
    undo: () => before.pop() ?? null,
    clear: () => { before.length = 0; },
    get size() { return before.length; },
  };
}
