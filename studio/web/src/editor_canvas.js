// The editor's canvas (SVG): one block per component instance, its input ports as handles on the
// left (event inputs as diamonds), outputs on the right; connections as curves from an output to
// an input with the role linter's verdict as a badge (its message on hover). Blocks are placed by
// dropping a palette type and moved by dragging their body; a connection is drawn by clicking one
// port and then the other (either end first). The canvas only draws and reports gestures: the
// page (editor.js) edits the project and asks the server.
import { connectionsOf, deploymentOf, inTab, typeOf } from './editor_model.js';

const SVG = 'http://www.w3.org/2000/svg';
export const BLOCK_WIDTH = 210;
const HEADER = 38;
const ROW = 18;
const CURVE = 70;

function el(name, attrs = {}, parent = null) {
  const node = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, String(v));
  parent?.appendChild(node);
  return node;
}

function text(parent, x, y, content, cls, anchor = 'start') {
  const t = el('text', { x, y, class: cls, 'text-anchor': anchor }, parent);
  t.textContent = content;
  return t;
}

/** Squeezes `label` into `room` px when it is longer (its text stays whole: tests and titles read it). */
function fit(label, room) {
  if (label.getComputedTextLength() <= room) return;
  label.setAttribute('textLength', room);
  label.setAttribute('lengthAdjust', 'spacingAndGlyphs');
}

/**
 * The rows of a block: inputs and outputs each from the top, in the palette's order, then the
 * ports the project's connections name that the palette's fresh instance does not have (made when
 * the component configures, e.g. a trajectory generator's desCartPose_1), marked `configured`.
 */
function layout(palette, project, component) {
  const ports = [...(typeOf(palette, component.type)?.ports ?? [])];
  const known = new Set(ports.map((p) => p.name));
  const all = [...project.connections, ...project.deployments.flatMap((d) => d.connections)];
  for (const c of all) {
    for (const [end, direction] of [[c.output, 'out'], [c.input, 'in']]) {
      const [name, port] = end.split('.');
      if (name !== component.name || known.has(port)) continue;
      known.add(port);
      ports.push({ name: port, direction, type: '?', event: false, unit: '', doc: 'made when the component configures (not in the palette)', configured: true });
    }
  }
  const inputs = ports.filter((p) => p.direction === 'in');
  const outputs = ports.filter((p) => p.direction === 'out');
  return { inputs, outputs, height: HEADER + Math.max(inputs.length, outputs.length, 1) * ROW + 8 };
}

/**
 * The height of a component's block in px: its type's ports from the palette and, given the
 * project, the ports its connections name that the palette's instance lacks (drawn too).
 */
export function blockHeight(palette, component, project = { connections: [], deployments: [] }) {
  return layout(palette, project, component).height;
}

/** Where a port's handle is, in canvas px, or null when the component or port is unknown. */
export function portPosition(palette, project, full) {
  const [name, portName] = full.split('.');
  const c = project.components.find((k) => k.name === name);
  if (!c) return null;
  const { inputs, outputs } = layout(palette, project, c);
  let i = inputs.findIndex((p) => p.name === portName);
  if (i >= 0) return { x: c.x, y: c.y + HEADER + i * ROW + ROW / 2, side: 'in' };
  i = outputs.findIndex((p) => p.name === portName);
  if (i >= 0) return { x: c.x + BLOCK_WIDTH, y: c.y + HEADER + i * ROW + ROW / 2, side: 'out' };
  return null;
}

/**
 * Creates the canvas in `svg`. `view()` gives { palette, project, tab, selection, pending,
 * refusal, lint } at each draw (lint: Map "out->in" -> [{rule, message}]); `on` has
 * select(selection | null), move(name, x, y), port({name, direction}), drop(typeName, x, y).
 */
export function createCanvas(svg, view, on) {
  let drag = null;

  const toCanvas = (event) => {
    const box = svg.getBoundingClientRect();
    return { x: event.clientX - box.left, y: event.clientY - box.top };
  };

  function drawConnection(layer, state, c, own) {
    const from = portPosition(state.palette, state.project, c.output);
    const to = portPosition(state.palette, state.project, c.input);
    if (!from || !to) return;
    const key = `${c.output}->${c.input}`;
    const selected = state.selection?.kind === 'connection' && state.selection.key === key && own;
    const g = el('g', { class: `connection${own ? '' : ' base'}${selected ? ' selected' : ''}`, 'data-output': c.output, 'data-input': c.input }, layer);
    const d = `M${from.x},${from.y} C${from.x + CURVE},${from.y} ${to.x - CURVE},${to.y} ${to.x},${to.y}`;
    el('path', { d, class: 'wire-hit' }, g);
    el('path', { d, class: `wire policy-${c.conn_policy?.type ?? 'data'}` }, g);
    const lint = state.lint.get(key) ?? [];
    const mx = (from.x + to.x) / 2;
    const my = (from.y + to.y) / 2;
    if (lint.length > 0) {
      const badge = el('g', { class: 'lint-badge', transform: `translate(${mx},${my})` }, g);
      el('circle', { r: 9 }, badge);
      text(badge, 0, 4, '!', 'lint-mark', 'middle');
      el('title', {}, badge).textContent = lint.map((l) => l.message).join('\n');
    }
    if (c.conn_policy && c.conn_policy.type !== 'data') {
      text(g, mx, my - 12, `${c.conn_policy.type}(${c.conn_policy.size ?? ''})${c.conn_policy.transport ? ` ${c.conn_policy.transport}` : ''}`, 'policy-label', 'middle');
    }
    if (own) {
      g.addEventListener('click', (e) => {
        e.stopPropagation();
        on.select({ kind: 'connection', key, output: c.output, input: c.input });
      });
    }
  }

  function drawPort(g, state, component, port, x, y) {
    const full = `${component.name}.${port.name}`;
    const cls = ['port', port.direction, port.event ? 'event' : '', port.configured ? 'configured' : '', state.pending?.name === full ? 'pending' : ''].filter(Boolean).join(' ');
    const handle = el('g', { class: cls, 'data-port': full, transform: `translate(${x},${y})` }, g);
    if (port.event) el('path', { d: 'M0,-6 L6,0 L0,6 L-6,0 Z', class: 'handle' }, handle);
    else el('circle', { r: 5, class: 'handle' }, handle);
    const label = port.direction === 'in' ? text(handle, 9, 4, port.name, 'port-label') : text(handle, -9, 4, port.name, 'port-label', 'end');
    el('title', {}, handle).textContent =
      `${full}: ${port.direction === 'in' ? (port.event ? 'event input' : 'input') : 'output'} ${port.type}${port.unit ? ` [${port.unit}]` : ''}${port.doc ? ` — ${port.doc}` : ''}`;
    label.setAttribute('pointer-events', 'none');
    // A name longer than half the block is squeezed into its half, so an input's and an output's
    // on one row never run into each other.
    fit(label, BLOCK_WIDTH / 2 - 12);
    handle.addEventListener('click', (e) => {
      e.stopPropagation();
      on.port({ name: full, direction: port.direction });
    });
    handle.addEventListener('pointerdown', (e) => e.stopPropagation());
  }

  function drawBlock(layer, state, component) {
    const type = typeOf(state.palette, component.type);
    const { inputs, outputs, height } = layout(state.palette, state.project, component);
    const member = inTab(state.project, state.tab, component.name);
    const selected = state.selection?.kind === 'component' && state.selection.name === component.name;
    const role = type?.role ?? 'unknown';
    const g = el('g', {
      class: `block role-${role}${member ? '' : ' outside'}${selected ? ' selected' : ''}${type ? '' : ' unknown-type'}`,
      'data-name': component.name, transform: `translate(${component.x},${component.y})`,
    }, layer);
    el('rect', { width: BLOCK_WIDTH, height, rx: 5, class: 'body' }, g);
    el('rect', { width: BLOCK_WIDTH, height: HEADER - 4, rx: 5, class: 'header' }, g);
    fit(text(g, 8, 15, component.name, 'block-name'), BLOCK_WIDTH - 16);
    fit(text(g, 8, 29, `${component.type} · ${role}`, 'block-type'), BLOCK_WIDTH - 16);
    inputs.forEach((p, i) => drawPort(g, state, component, p, 0, HEADER + i * ROW + ROW / 2));
    outputs.forEach((p, i) => drawPort(g, state, component, p, BLOCK_WIDTH, HEADER + i * ROW + ROW / 2));
    g.addEventListener('pointerdown', (e) => {
      if (e.button !== 0) return;
      e.preventDefault(); // no text selection while dragging
      const at = toCanvas(e);
      // No pointer capture: it would send the click that selects the block to the canvas instead.
      drag = { name: component.name, dx: at.x - component.x, dy: at.y - component.y, g, moved: false };
    });
    g.addEventListener('click', (e) => {
      e.stopPropagation();
      on.select({ kind: 'component', name: component.name });
    });
  }

  function draw() {
    const state = view();
    svg.replaceChildren();
    // Room for every block and as much again to grow into.
    const right = Math.max(0, ...state.project.components.map((c) => c.x + BLOCK_WIDTH));
    const bottom = Math.max(0, ...state.project.components.map((c) => c.y + blockHeight(state.palette, c, state.project)));
    svg.setAttribute('width', Math.max(2400, right + 600));
    svg.setAttribute('height', Math.max(1600, bottom + 600));
    const wires = el('g', { class: 'wires' }, svg);
    const blocks = el('g', { class: 'blocks' }, svg);
    const own = connectionsOf(state.project, state.tab);
    if (deploymentOf(state.project, state.tab)) for (const c of state.project.connections) drawConnection(wires, state, c, false);
    for (const c of own) drawConnection(wires, state, c, true);
    for (const c of state.project.components) drawBlock(blocks, state, c);
    if (state.refusal) {
      const at = portPosition(state.palette, state.project, state.refusal.at);
      if (at) {
        // Beside the port, outside its block; moved inside the canvas when it would start left of it.
        const back = el('rect', { class: 'refusal-back', rx: 3 }, svg);
        const t = text(svg, at.x + (at.side === 'in' ? -10 : 10), at.y - 10, state.refusal.text, 'refusal', at.side === 'in' ? 'end' : 'start');
        t.setAttribute('data-port', state.refusal.at);
        const box = t.getBBox();
        if (box.x < 4) {
          t.setAttribute('text-anchor', 'start');
          t.setAttribute('x', 4);
          t.setAttribute('y', at.y - 24);
        }
        const fitted = t.getBBox();
        for (const [k, v] of Object.entries({ x: fitted.x - 3, y: fitted.y - 2, width: fitted.width + 6, height: fitted.height + 4 })) back.setAttribute(k, v);
      }
    }
  }

  // On the window: a drag that leaves the canvas still ends where the pointer is released.
  window.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const at = toCanvas(e);
    drag.moved = true;
    drag.x = Math.max(0, at.x - drag.dx);
    drag.y = Math.max(0, at.y - drag.dy);
    drag.g.setAttribute('transform', `translate(${drag.x},${drag.y})`);
  });
  window.addEventListener('pointerup', () => {
    const d = drag;
    drag = null;
    if (d?.moved) on.move(d.name, d.x, d.y);
  });
  svg.addEventListener('click', () => on.select(null));
  svg.addEventListener('dragover', (e) => {
    if (e.dataTransfer.types.includes('text/x-cobra-type')) e.preventDefault();
  });
  svg.addEventListener('drop', (e) => {
    const type = e.dataTransfer.getData('text/x-cobra-type');
    if (!type) return;
    e.preventDefault();
    const at = toCanvas(e);
    on.drop(type, Math.max(0, at.x - BLOCK_WIDTH / 2), Math.max(0, at.y - HEADER / 2));
  });
  return { draw };
}
