// What the console works out from the model's chart descriptions (studio/PROTOCOL.md, "charts"):
// which states are active, which inputs some chart waits for now, and which failure led there.
// Plain functions of the model and a frame: the page and the tests use the same ones.

/** True when `state` is the active leaf `leaf` or one of its ancestors ("root.a" of "root.a.b"). */
export function isActive(state, leaf) {
  return typeof leaf === 'string' && (leaf === state || leaf.startsWith(`${state}.`));
}

/** True when a transition waiting for `events` is triggered by `event` (sent by any component:
 *  a Supervisor raises N and N@source; no events at all: any event triggers it). */
export function triggers(events, event) {
  return events.length === 0 || events.some((e) => e === event || e.startsWith(`${event}@`));
}

/**
 * The inputs each chart accepts in the frame's active configuration: { chart: [input, ...] } for
 * the charts that accept at least one, in the model's orders. An input accepted by a chart has an
 * `event` and the chart a transition, leaving its active leaf or an ancestor, that the event
 * triggers (its guard is the chart's to decide: the input is offered, the chart may still refuse).
 */
export function offersByChart(model, frame) {
  const out = {};
  for (const chart of model.charts ?? []) {
    const leaf = frame?.charts?.[chart.name];
    const accepting = (chart.transitions ?? []).filter((t) => isActive(t.src, leaf));
    const inputs = (model.inputs ?? []).filter((i) => i.event && accepting.some((t) => triggers(t.events, i.event)));
    if (inputs.length > 0) out[chart.name] = inputs;
  }
  return out;
}

/**
 * Whether the page can tell when an input is accepted: the model describes the charts'
 * transitions (older recordings and servers do not) and the input names its event.
 */
export function gated(model, input) {
  return Boolean(input.event) && (model.charts ?? []).some((c) => Array.isArray(c.transitions));
}

/**
 * The failure that led a chart to where it is at `t`: the last event named in model.failures at
 * or before `t` and not before `since` (when the chart entered the state it was in before its
 * current one), or null.
 */
export function failureLeadingTo(model, events, since, t) {
  const failures = model.failures ?? [];
  for (let i = events.length - 1; i >= 0; i -= 1) {
    const e = events[i];
    if (e.type !== 'event' || e.t > t + 1e-9) continue;
    if (e.t < since - 1e-9) return null;
    if (failures.includes(e.name)) return e;
  }
  return null;
}
