// The surgeon's console beside the 3D view: every chart's active state, the deployments and
// configurations in force, the event log, the inputs as buttons, the clearance and the outcome.

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

export class Panel {
  constructor(doc, model) {
    this.doc = doc;
    this.model = model;
    this.events = doc.getElementById('events');
    const run = `${model.app ?? ''}${model.scenario ? ` / ${model.scenario}` : ''}`;
    doc.getElementById('mode').textContent = `${run} · ${model.mode}`;
    doc.title = `${run} · cobra studio`;
    fillTable(doc.getElementById('charts'), (model.charts ?? []).map((c) => [c.name, '–']));
  }

  /** Shows a frame's time, chart states, deployments, configurations and clearance. */
  showFrame(frame) {
    const doc = this.doc;
    doc.getElementById('clock').textContent = `t = ${frame.t.toFixed(2)} s`;
    const charts = frame.charts ?? {};
    fillTable(doc.getElementById('charts'), (this.model.charts ?? []).map((c) => [c.name, charts[c.name] ?? '–']));
    const rows = [
      ...Object.entries(frame.deployments ?? {}).map(([k, v]) => [`deployment ${k}`, v]),
      ...Object.entries(frame.configurations ?? {}).map(([k, v]) => [`configuration ${k}`, v]),
    ];
    fillTable(doc.getElementById('deployments'), rows);
    const badge = doc.getElementById('clearance');
    const c = frame.clearance;
    if (c && Number.isFinite(c.min)) {
      badge.textContent = `clearance ${(c.min * 1000).toFixed(1)} mm (min ${(c.threshold * 1000).toFixed(1)} mm) ${c.valid ? 'valid' : 'INVALID'}`;
      badge.className = `clearance ${c.valid ? 'valid' : 'invalid'}`;
    }
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
    this.events.append(li);
    if (this.model.mode !== 'replay' && this.events.children.length > MAX_LIVE_EVENTS) this.events.firstElementChild.remove();
    this.events.scrollTop = this.events.scrollHeight; // the log's own scroll only, not the console's
  }

  setOutcome(msg) {
    this.doc.getElementById('outcome').textContent =
      msg ? `outcome: ${msg.outcome}${msg.message ? ` — ${msg.message}` : ''}` : '';
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

  /** One button per model input; `send(name)` returns a promise that rejects with the reason. */
  addInputs(send, onError) {
    const box = this.doc.getElementById('inputs');
    const inputs = this.model.inputs ?? [];
    if (inputs.length === 0) this.doc.getElementById('inputs-section').hidden = true;
    for (const input of inputs) {
      const button = this.doc.createElement('button');
      button.type = 'button';
      button.textContent = input.label ?? input.name;
      button.title = `${input.name} -> ${input.target ?? ''}`;
      button.dataset.input = input.name;
      button.disabled = this.model.mode === 'replay';
      button.addEventListener('click', () => {
        button.disabled = true;
        send(input.name).catch((err) => onError(err.message)).finally(() => { button.disabled = false; });
      });
      box.append(button);
    }
  }
}
