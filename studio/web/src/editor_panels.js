// The editor's side panels: the palette (types by package, searchable, each with its role, ports,
// properties and operations), the inspector of the selected block or connection, the tabs
// (base deployment first, then named deployments and configurations), a configuration's values
// and the problems list. They draw from the page's state and report edits through `on`.
import {
  BASE_TAB, POLICY_TYPES, SCHEDULERS, deploymentOf, findPort, inTab, paletteGroups, peersOf, problemsByWhere,
  propertyWhere, typeOf,
} from './editor_model.js';

/** A DOM element: h('div', { class: 'x', onclick: f }, child, 'text', ...). */
export function h(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v == null || v === false) continue;
    if (k.startsWith('on')) node.addEventListener(k.slice(2), v);
    else if (k === 'value') node.value = v;
    else if (v === true) node.setAttribute(k, '');
    else node.setAttribute(k, String(v));
  }
  for (const c of children.flat()) if (c != null && c !== false) node.append(c);
  return node;
}

const unitText = (unit) => (unit ? ` [${unit}]` : '');
const rangeText = (range) => (range ? ` in [${range[0]}, ${range[1]}]` : '');

/** The palette: `state.palette` grouped by package, filtered by the search field's words. */
export function drawPalette(list, state, query) {
  list.replaceChildren();
  for (const group of paletteGroups(state.palette, query)) {
    const types = group.types.map((t) => {
      const summary = h('summary', { draggable: t.generated ? null : 'true', 'data-type': t.type, class: `palette-type role-${t.role}${t.generated ? ' generated' : ''}` },
        h('span', { class: 'type-name' }, t.type), ' ', h('span', { class: 'role' }, t.role),
        t.generated ? h('span', { class: 'generated-note' }, 'generated (build the package to use it)') : null);
      if (!t.generated) summary.addEventListener('dragstart', (e) => {
        e.dataTransfer.setData('text/x-cobra-type', t.type);
        e.dataTransfer.effectAllowed = 'copy';
      });
      return h('details', { class: 'palette-entry' }, summary,
        h('p', { class: 'doc' }, t.doc),
        h('ul', { class: 'ports' }, t.ports.map((p) => h('li', { 'data-port': p.name },
          h('b', {}, p.direction === 'in' ? (p.event ? 'in (event)' : 'in') : 'out'), ` ${p.name} : ${p.type}${unitText(p.unit)}`,
          p.doc ? h('span', { class: 'doc' }, ` — ${p.doc}`) : null))),
        t.properties.length ? h('ul', { class: 'properties' }, t.properties.map((p) => h('li', {},
          h('b', {}, 'property'), ` ${p.name} : ${p.type}${unitText(p.unit)}${rangeText(p.range)}`,
          p.doc ? h('span', { class: 'doc' }, ` — ${p.doc}`) : null))) : null,
        t.operations.length ? h('ul', { class: 'operations' }, t.operations.map((o) => h('li', {},
          h('b', {}, 'operation'), ` ${o.signature}`, o.doc ? h('span', { class: 'doc' }, ` — ${o.doc}`) : null))) : null);
    });
    list.append(h('section', { class: 'package', 'data-package': group.package }, h('h3', {}, group.package), types));
  }
  if (!list.firstChild) list.append(h('p', { class: 'empty' }, `no type matches '${query}'`));
  if (state.palette.errors?.length) {
    list.append(h('section', { class: 'palette-errors' }, h('h3', {}, 'not loaded'), h('ul', {}, state.palette.errors.map((e) => h('li', {}, e)))));
  }
}

/** The tabs: the base deployment, each named deployment, each configuration, and the add buttons. */
export function drawTabs(nav, state, on) {
  const tab = (id, label, kind) => h('button', {
    type: 'button', class: `tab ${kind}${state.tab === id && state.tabKind === kind ? ' active' : ''}`, 'data-tab': id, 'data-kind': kind,
    onclick: () => on.tab(id, kind),
  }, label);
  nav.replaceChildren(...[
    tab(BASE_TAB, 'base deployment', 'deployment'),
    state.project.deployments.map((d) => tab(d.name, d.scope ? `${d.name} (${d.scope})` : d.name, 'deployment')),
    state.project.configurations.map((c) => tab(c.name, `⚙ ${c.name}`, 'configuration')),
    h('button', { type: 'button', id: 'add-deployment', class: 'add', onclick: () => on.addTab('deployment') }, '+ deployment'),
    h('button', { type: 'button', id: 'add-configuration', class: 'add', onclick: () => on.addTab('configuration') }, '+ configuration'),
  ].flat());
}

/** The problems of one field, kept up to date by refreshFieldProblems (empty: hidden). */
function fieldProblems(byWhere, where) {
  return h('div', { class: 'field-problem', 'data-where': where }, (byWhere.get(where) ?? []).join('; '));
}

/**
 * Writes the validate answer's problems into the drawn fields without drawing them again (a
 * field being typed in keeps its text and focus).
 */
export function refreshFieldProblems(root, state) {
  const byWhere = problemsByWhere(state.problems);
  for (const node of root.querySelectorAll('.field-problem[data-where]')) node.textContent = (byWhere.get(node.dataset.where) ?? []).join('; ');
}

function componentInspector(state, component, on) {
  const type = typeOf(state.palette, component.type);
  const byWhere = problemsByWhere(state.problems);
  const activity = component.activity ?? {};
  const others = state.project.components.filter((c) => c.name !== component.name).map((c) => c.name);
  const peers = peersOf(state.project, component.name);
  const inList = (list) => state.project[list].includes(component.name);
  const deployment = deploymentOf(state.project, state.tab);
  return [
    h('h3', {}, component.name),
    h('p', { class: 'meta' }, `${component.type} · ${type?.role ?? 'type not in the palette'}`),
    type?.doc ? h('p', { class: 'doc' }, type.doc) : null,
    fieldProblems(byWhere, `component '${component.name}'`),
    deployment ? h('label', { class: 'check' }, h('input', {
      type: 'checkbox', id: 'in-deployment', checked: inTab(state.project, state.tab, component.name),
      onchange: (e) => on.membership(component.name, e.target.checked),
    }), ` run in deployment '${deployment.name}'`) : null,
    h('h4', {}, 'Properties'),
    h('table', { class: 'properties' }, (type?.properties ?? []).map((p) => h('tr', { 'data-property': p.name },
      h('td', {}, h('div', { class: 'prop-name' }, p.name), h('div', { class: 'prop-type' }, `${p.type}${unitText(p.unit)}${rangeText(p.range)}`)),
      h('td', {},
        h('input', {
          type: 'text', value: component.properties[p.name] ?? '', placeholder: p.default ?? '', title: p.doc, disabled: p.read_only,
          onchange: (e) => on.property(component.name, p.name, e.target.value),
        }),
        fieldProblems(byWhere, propertyWhere(component.name, p.name)))))),
    h('h4', {}, 'Activity'),
    h('div', { class: 'activity' },
      h('label', {}, 'period [s] ', h('input', { type: 'text', id: 'activity-period', value: activity.period ?? '', placeholder: 'triggered', size: 6 })),
      h('label', {}, 'priority ', h('input', { type: 'text', id: 'activity-priority', value: activity.priority ?? 0, size: 3 })),
      h('label', {}, 'scheduler ', h('select', { id: 'activity-scheduler' },
        SCHEDULERS.map((s) => h('option', { value: s, selected: (activity.scheduler ?? 'other') === s }, s)))),
      h('button', {
        type: 'button', id: 'activity-apply',
        onclick: (e) => {
          const box = e.target.closest('.activity');
          on.activity(component.name, {
            period: box.querySelector('#activity-period').value.trim(),
            priority: box.querySelector('#activity-priority').value.trim(),
            scheduler: box.querySelector('#activity-scheduler').value,
          });
        },
      }, 'Apply'),
      fieldProblems(byWhere, `activity of '${component.name}'`)),
    h('h4', {}, 'Lifecycle'),
    h('div', { class: 'lifecycle' }, ['configure', 'start'].map((list) => h('label', { class: 'check' },
      h('input', { type: 'checkbox', 'data-list': list, checked: inList(list), onchange: (e) => on.lifecycle(component.name, list, e.target.checked) }),
      ` ${list} at deployment`))),
    h('h4', {}, 'Peers (components it may call)'),
    others.length ? h('div', { class: 'peers' }, others.map((name) => h('label', { class: 'check' },
      h('input', {
        type: 'checkbox', 'data-peer': name, checked: peers.includes(name),
        onchange: (e) => on.peers(component.name, e.target.checked ? [...peers, name] : peers.filter((p) => p !== name)),
      }), ` ${name}`))) : h('p', { class: 'empty' }, 'no other component'),
    fieldProblems(byWhere, `peers of '${component.name}'`),
    type?.operations.length ? h('h4', {}, 'Operations') : null,
    type?.operations.length ? h('ul', { class: 'operations' }, type.operations.map((o) => h('li', {}, o.signature))) : null,
    h('button', { type: 'button', id: 'delete-selected', class: 'danger', onclick: () => on.deleteComponent(component.name) }, 'Delete component'),
  ];
}

function connectionInspector(state, connection, on) {
  const policy = connection.conn_policy ?? { type: 'data' };
  const from = findPort(state.palette, state.project, connection.output);
  const to = findPort(state.palette, state.project, connection.input);
  const lint = state.lint.get(`${connection.output}->${connection.input}`) ?? [];
  const dds = ['transport', 'topic', 'qos'].some((k) => policy[k] != null);
  const where = `connection '${connection.output}' -> '${connection.input}'`;
  return [
    h('h3', {}, `${connection.output} → ${connection.input}`),
    h('p', { class: 'meta' }, `${from?.port.type ?? '?'} → ${to?.port.type ?? '?'}`),
    lint.length ? h('ul', { class: 'lint' }, lint.map((l) => h('li', {}, l.message))) : h('p', { class: 'lint-clean' }, 'role linter: clean'),
    fieldProblems(problemsByWhere(state.problems), where),
    h('h4', {}, 'Connection policy'),
    h('div', { class: 'policy' },
      h('label', {}, 'type ', h('select', { id: 'policy-type' }, POLICY_TYPES.map((t) => h('option', { value: t, selected: policy.type === t }, t)))),
      h('label', {}, 'size ', h('input', { type: 'text', id: 'policy-size', value: policy.size ?? '', size: 4, placeholder: 'samples' })),
      dds ? ['transport', 'topic', 'qos'].map((k) => h('label', {}, `${k} `, h('input', {
        type: 'text', id: `policy-${k}`, value: k === 'qos' && policy.qos != null ? JSON.stringify(policy.qos) : policy[k] ?? '',
      }))) : null,
      h('button', {
        type: 'button', id: 'policy-apply',
        onclick: (e) => {
          const box = e.target.closest('.policy');
          const fields = { type: box.querySelector('#policy-type').value, size: box.querySelector('#policy-size').value.trim() };
          for (const k of ['transport', 'topic', 'qos']) {
            const input = box.querySelector(`#policy-${k}`);
            if (input) fields[k] = input.value.trim();
          }
          on.policy(connection, fields);
        },
      }, 'Apply')),
    h('button', { type: 'button', id: 'delete-selected', class: 'danger', onclick: () => on.deleteConnection(connection) }, 'Delete connection'),
  ];
}

/** The inspector of the selected block or connection (the tab's own), or a hint. */
export function drawInspector(box, state, on) {
  const sel = state.selection;
  let content = [h('p', { class: 'empty' }, 'Select a block or a connection.')];
  if (sel?.kind === 'component') {
    const component = state.project.components.find((c) => c.name === sel.name);
    if (component) content = componentInspector(state, component, on);
  } else if (sel?.kind === 'connection') {
    const list = state.tab === BASE_TAB ? state.project.connections : deploymentOf(state.project, state.tab)?.connections ?? [];
    const connection = list.find((c) => c.output === sel.output && c.input === sel.input);
    if (connection) content = connectionInspector(state, connection, on);
  }
  box.replaceChildren(...content.filter(Boolean));
}

/** A configuration tab: its values ("Comp.property" = text) and a row to add one. */
export function drawConfiguration(box, state, on) {
  const configuration = state.project.configurations.find((c) => c.name === state.tab);
  if (!configuration) return box.replaceChildren();
  const byWhere = problemsByWhere(state.problems);
  const options = state.project.components.flatMap((c) => (typeOf(state.palette, c.type)?.properties ?? []).map((p) => `${c.name}.${p.name}`));
  const row = (key, value) => {
    const [name, property] = key.split('.');
    const p = typeOf(state.palette, state.project.components.find((c) => c.name === name)?.type)?.properties.find((q) => q.name === property);
    return h('tr', { 'data-key': key },
      h('td', {}, key, h('div', { class: 'prop-type' }, p ? `${p.type}${unitText(p.unit)}${rangeText(p.range)}` : '')),
      h('td', {}, h('input', { type: 'text', value, onchange: (e) => on.configurationValue(configuration, key, e.target.value) }),
        fieldProblems(byWhere, `configuration '${configuration.name}' value '${key}'`)));
  };
  return box.replaceChildren(...[
    h('h3', {}, `Configuration '${configuration.name}'`),
    h('p', { class: 'doc' }, 'Property values this configuration sets when applied (an empty value removes it).'),
    h('table', { class: 'configuration' }, Object.entries(configuration.values).map(([k, v]) => row(k, v))),
    h('div', { class: 'add-value' },
      h('select', { id: 'value-key' }, options.map((o) => h('option', { value: o }, o))),
      h('input', { type: 'text', id: 'value-text', placeholder: 'value' }),
      h('button', {
        type: 'button', id: 'value-add',
        onclick: () => on.configurationValue(configuration, box.querySelector('#value-key').value, box.querySelector('#value-text').value),
      }, 'Set')),
  ]);
}

/** What a problem's `where` names: a component or a connection (for `select`), or null. */
export function selectionOf(where) {
  let m = /^(?:component|activity of|peers of|deployment '\w+' activity of) '(\w+)'/.exec(where);
  if (m) return { kind: 'component', name: m[1] };
  m = /^(?:deployment '\w+' )?connection '([\w.]+)' -> '([\w.]+)'/.exec(where);
  return m ? { kind: 'connection', key: `${m[1]}->${m[2]}`, output: m[1], input: m[2] } : null;
}

/**
 * The problems list: the validate answer's problems and every drawn connection's lint; a click
 * selects what the problem is about (`select(selection)`).
 */
export function drawProblems(list, state, select) {
  const drawn = new Set([...state.project.connections, ...state.project.deployments.flatMap((d) => d.connections)].map((c) => `${c.output}->${c.input}`));
  const item = (cls, head, message, selection) => h('li', { class: cls, onclick: selection ? () => select(selection) : null }, h('b', {}, head), `: ${message}`);
  const items = [
    ...state.problems.map((p) => item('problem', p.where, p.message, selectionOf(p.where))),
    ...[...state.lint].filter(([key]) => drawn.has(key)).flatMap(([key, lint]) => lint.map((l) => {
      const [output, input] = key.split('->');
      return item('lint', l.rule, l.message, { kind: 'connection', key, output, input });
    })),
  ];
  list.replaceChildren(...(items.length ? items : [h('li', { class: 'clean' }, 'no problems')]));
}
