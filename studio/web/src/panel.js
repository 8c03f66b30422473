// The surgeon's console beside the 3D view: every chart's active state and its states (the active
// ones highlighted), each scope's deployment and configuration in force, the event log, the inputs
// as buttons (enabled when a chart accepts their event), the choices a chart offers after a
// failure, the clearance and how the run ended.
import { failureLeadingTo, gated, isActive, offersByChart } from './console_logic.js';

const MAX_LIVE_EVENTS = 2000; // a live log keeps the newest; a replay shows the whole recording

function fillTable(table, rows) {
  table.replaceChildren(...rows.map(([key, value]) => {
    const tr = document.createElement('tr');
    const k = document.createElement('td');
    const v = document.createElement('td');
    k.textContent = key;
    v.textContent = value;
    tr.dataset.key = key;
    tr.append(k, v);
    return tr;
  }));
}

const scopeName = (scope) => (scope === '' ? '(default)' : scope);

export class Panel {
  constructor(doc, model) {
    this.doc = doc;
    this.model = model;
    this.events = doc.getElementById('events');
    this.log = []; // the event messages shown, in order (live: the newest MAX_LIVE_EVENTS)
    this.send = null;
    this.onError = null;
    this.buttons = new Map(); // input name -> its button in the inputs section
    this.offers = {};
    const run = `${model.app ?? ''}${model.scenario ? ` / ${model.scenario}` : ''}`;
    doc.getElementById('mode').textContent = `${run} · ${model.mode}`;
    doc.title = `${run} · cobra studio`;
    fillTable(doc.getElementById('charts'), (model.charts ?? []).map((c) => [c.name, '–']));
    this.buildStateTrees();
  }

  /** One list per chart of its states (indented by depth), from the model's description. */
  buildStateTrees() {
    const box = this.doc.getElementById('states');
    this.stateItems = new Map(); // chart -> [[path, li], ...]
    for (const chart of this.model.charts ?? []) {
      const states = chart.states ?? [];
      if (states.length === 0) continue;
      const details = this.doc.createElement('details');
      details.dataset.chart = chart.name;
      details.open = true;
      const summary = this.doc.createElement('summary');
      summary.textContent = `${chart.name}: ${states.length} states`;
      const list = this.doc.createElement('ul');
      list.className = 'state-tree';
      const items = states.map((path) => {
        const li = this.doc.createElement('li');
        li.dataset.path = path;
        li.textContent = path.split('.').at(-1);
        li.title = path;
        li.style.paddingLeft = `${(path.split('.').length - 1) * 12}px`;
        list.append(li);
        return [path, li];
      });
      this.stateItems.set(chart.name, { items, list, leaf: null });
      details.append(summary, list);
      box.append(details);
    }
    this.doc.getElementById('states-section').hidden = this.stateItems.size === 0;
  }

  /**
   * Shows a frame: time, chart states, deployments and configurations per scope, clearance, and
   * which inputs the charts accept. `since` (optional): per chart, the time it entered the state
   * before its current one, for the failure that led to a choice.
   */
  showFrame(frame, since = {}) {
    const doc = this.doc;
    doc.getElementById('clock').textContent = `t = ${frame.t.toFixed(2)} s`;
    const charts = frame.charts ?? {};
    fillTable(doc.getElementById('charts'), (this.model.charts ?? []).map((c) => [c.name, charts[c.name] ?? '–']));
    for (const [chart, tree] of this.stateItems) {
      if (tree.leaf === charts[chart]) continue;
      tree.leaf = charts[chart];
      let leaf = null;
      for (const [path, li] of tree.items) {
        li.classList.toggle('active', isActive(path, tree.leaf));
        if (path === tree.leaf) leaf = li;
      }
      // The list scrolls (itself only) to keep the active leaf in the middle of its view.
      if (leaf) tree.list.scrollTop = leaf.offsetTop - (tree.list.clientHeight - leaf.offsetHeight) / 2;
    }
    const deployments = frame.deployments ?? {};
    const configurations = frame.configurations ?? {};
    const scopes = [...new Set([...(this.model.scopes ?? []), ...Object.keys(deployments), ...Object.keys(configurations)])];
    fillTable(doc.getElementById('deployments'), scopes.flatMap((s) => [
      ...(s in deployments ? [[`deployment ${scopeName(s)}`, deployments[s] || '–']] : []),
      ...(s in configurations ? [[`configuration ${scopeName(s)}`, configurations[s] || '–']] : []),
    ]));
    const badge = doc.getElementById('clearance');
    const c = frame.clearance;
    if (c && Number.isFinite(c.min)) {
      badge.textContent = `clearance ${(c.min * 1000).toFixed(1)} mm (min ${(c.threshold * 1000).toFixed(1)} mm) ${c.valid ? 'valid' : 'INVALID'}`;
      badge.className = `clearance ${c.valid ? 'valid' : 'invalid'}`;
    }
    this.showOffers(frame, since);
  }

  /** Enables the inputs some chart accepts now and lists each waiting chart's choices. */
  showOffers(frame, since) {
    const offers = offersByChart(this.model, frame);
    const key = JSON.stringify(Object.entries(offers).map(([c, inputs]) => [c, frame.charts[c], inputs.map((i) => i.name)]));
    const offered = new Set(Object.values(offers).flat().map((i) => i.name));
    for (const [name, button] of this.buttons) {
      const input = this.model.inputs.find((i) => i.name === name);
      const accepted = !gated(this.model, input) || offered.has(name);
      button.classList.toggle('offered', offered.has(name));
      if (!button.classList.contains('sending')) button.disabled = this.model.mode === 'replay' || !accepted;
    }
    const failureKey = Object.keys(offers).map((c) => {
      const f = failureLeadingTo(this.model, this.log, since[c] ?? Infinity, frame.t);
      return f ? `${f.t}/${f.source}/${f.name}` : '';
    }).join('|');
    if (key === this.offersKey && failureKey === this.failureKey) return;
    this.offersKey = key;
    this.failureKey = failureKey;
    const box = this.doc.getElementById('choices');
    box.replaceChildren();
    // Only a person is asked: a live run given --interactive (the model's `interactive`); in
    // another run the application's own script answers the charts, and a replay asks no one.
    const asked = this.model.mode === 'live' && this.model.interactive === true;
    for (const [chart, inputs] of asked ? Object.entries(offers) : []) {
      const row = this.doc.createElement('div');
      row.className = 'choice-row';
      row.dataset.chart = chart;
      const what = this.doc.createElement('div');
      const failure = failureLeadingTo(this.model, this.log, since[chart] ?? Infinity, frame.t);
      what.className = 'choice-what';
      what.textContent = `${chart} waits in ${frame.charts[chart]}`
        + (failure ? ` after ${failure.source}: ${failure.name} at ${failure.t.toFixed(2)} s` : '');
      row.append(what);
      for (const input of inputs) row.append(this.makeButton(input, 'choice'));
      box.append(row);
    }
    this.doc.getElementById('choices-section').hidden = box.children.length === 0;
  }

  /** Appends one event (or end) message to the log; the end sets the outcome. */
  addEvent(msg) {
    const li = this.doc.createElement('li');
    li.dataset.t = msg.t ?? '';
    if (msg.type === 'end') {
      li.textContent = `end: ${msg.outcome}${msg.message ? ` (${msg.message})` : ''}`;
      this.setOutcome(msg);
    } else {
      li.textContent = `${Number(msg.t ?? 0).toFixed(2)} s  ${msg.source}: ${msg.name}`;
    }
    this.log.push(msg);
    this.events.append(li);
    if (this.model.mode !== 'replay' && this.events.children.length > MAX_LIVE_EVENTS) {
      this.events.firstElementChild.remove();
      this.log.shift();
    }
    this.events.scrollTop = this.events.scrollHeight; // the log's own scroll only, not the console's
  }

  /** How the run ended: outcome and reason in the bar; the exit status, the line `cobra run`
   *  printed and the final states in the console's outcome section. */
  setOutcome(msg) {
    this.doc.getElementById('outcome').textContent =
      msg ? `outcome: ${msg.outcome}${msg.message ? ` — ${msg.message}` : ''}` : '';
    const section = this.doc.getElementById('end-section');
    section.hidden = !msg;
    if (!msg) return;
    const rows = [['outcome', msg.outcome]];
    if (msg.status !== undefined) rows.push(['exit status', String(msg.status)]);
    if (msg.line) rows.push(['cobra run', msg.line]);
    else if (msg.message) rows.push(['reason', msg.message]);
    for (const [chart, state] of Object.entries(msg.states ?? {})) rows.push([`final ${chart}`, state]);
    // On the wall clock: how the executor kept time (deadline misses, wake-up latency, compute).
    if (msg.executor) rows.push(['executor (wall clock)', msg.executor.replace(/^executor: /, '')]);
    fillTable(this.doc.getElementById('end'), rows);
  }

  /** Replay: greys out the events after `t` and shows the outcome only once the end is reached. */
  showEventsUntil(t, end) {
    let last = null;
    for (const li of this.events.children) {
      const future = Number(li.dataset.t) > t + 1e-9;
      li.classList.toggle('future', future);
      if (!future) last = li;
    }
    // Scrolls the log (only) so the newest past event is its last visible line.
    this.events.scrollTop = last ? last.offsetTop + last.offsetHeight - this.events.clientHeight : 0;
    this.setOutcome(end && t >= (end.t ?? Infinity) - 1e-9 ? end : null);
  }

  /** A button sending `input`; `kind` 'input' (the inputs section) or 'choice' (highlighted). */
  makeButton(input, kind) {
    const button = this.doc.createElement('button');
    button.type = 'button';
    button.className = kind;
    button.textContent = input.label ?? input.name;
    button.title = `${input.name} -> ${input.target ?? ''}${input.event ? ` (${input.event})` : ''}`;
    button.dataset.input = input.name;
    button.disabled = this.model.mode === 'replay' || !this.send;
    button.addEventListener('click', () => {
      button.disabled = true;
      button.classList.add('sending');
      this.send(input.name).catch((err) => this.onError(err.message)).finally(() => {
        button.classList.remove('sending');
        button.disabled = false;
      });
    });
    return button;
  }

  /** One button per model input; `send(name)` returns a promise that rejects with the reason. */
  addInputs(send, onError) {
    this.send = send;
    this.onError = onError;
    const box = this.doc.getElementById('inputs');
    const inputs = this.model.inputs ?? [];
    if (inputs.length === 0) this.doc.getElementById('inputs-section').hidden = true;
    for (const input of inputs) {
      const button = this.makeButton(input, 'input');
      this.buttons.set(input.name, button);
      box.append(button);
    }
  }
}
