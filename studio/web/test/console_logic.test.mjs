// The console's logic (src/console_logic.js) on a model shaped as the bridge writes it: the
// inputs a chart accepts in its active configuration (the leaf and its ancestors), events sent
// as N or waited for as N@source, inputs the page cannot gate, and the failure that led a chart
// to a choice.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { failureLeadingTo, gated, isActive, offersByChart } from '../src/console_logic.js';

const input = (name, event) => ({ name, label: name, target: 'Surgeon.say', event });
const MODEL = {
  charts: [
    {
      name: 'needle', scope: 'needle',
      states: ['root', 'root.Work', 'root.Work.Insert', 'root.Work.WaitMounted', 'root.WaitReaction', 'root.Teleop'],
      transitions: [
        { src: 'root.Work', tgt: 'root.WaitReaction', events: ['e_forbidden_region'], guarded: false },
        { src: 'root.Work.WaitMounted', tgt: 'root.Work.Insert', events: ['e_needle_mounted@Surgeon'], guarded: false },
        { src: 'root.WaitReaction', tgt: 'root.Teleop', events: ['e_take_over'], guarded: false },
        { src: 'root.WaitReaction', tgt: 'root.Work.Insert', events: ['e_recover'], guarded: true },
        { src: 'root.Teleop', tgt: 'root.Work.Insert', events: ['e_teleop_done'], guarded: false },
      ],
    },
    { name: 'us', scope: 'probe', states: ['root', 'root.Idle', 'root.WaitReaction'],
      transitions: [{ src: 'root.WaitReaction', tgt: 'root.Idle', events: ['e_recover'], guarded: false }] },
  ],
  inputs: [input('needle_mounted', 'e_needle_mounted'), input('recover', 'e_recover'), input('take_over', 'e_take_over'),
    input('teleop_done', 'e_teleop_done'), { name: 'clear', label: 'Clear', target: 'Recorder.clear', event: '' }],
  failures: ['e_forbidden_region', 'e_plan_failed'],
};
const names = (offers) => Object.fromEntries(Object.entries(offers).map(([c, inputs]) => [c, inputs.map((i) => i.name)]));
const frame = (needle, us) => ({ t: 5, charts: { needle, us } });

test('a state is active when it is the leaf or one of its ancestors, not a sibling sharing a prefix', () => {
  assert.equal(isActive('root.Work', 'root.Work.Insert'), true);
  assert.equal(isActive('root.Work.Insert', 'root.Work.Insert'), true);
  assert.equal(isActive('root.Work', 'root.WorkDone'), false);
  assert.equal(isActive('root.Work', undefined), false);
});

test('each chart offers the inputs whose event a transition leaving its active configuration waits for', () => {
  assert.deepEqual(names(offersByChart(MODEL, frame('root.Work.WaitMounted', 'root.Idle'))), { needle: ['needle_mounted'] });
  assert.deepEqual(names(offersByChart(MODEL, frame('root.Work.Insert', 'root.Idle'))), {});
  // After a fault: recover and the takeover in the needle chart, recover in the probe's.
  assert.deepEqual(names(offersByChart(MODEL, frame('root.WaitReaction', 'root.WaitReaction'))),
    { needle: ['recover', 'take_over'], us: ['recover'] });
  assert.deepEqual(names(offersByChart(MODEL, frame('root.Teleop', 'root.Idle'))), { needle: ['teleop_done'] });
});

test('a transition without events accepts every input that names an event; an input without an event is not gated', () => {
  const any = { charts: [{ name: 'c', states: ['root', 'root.a'], transitions: [{ src: 'root.a', tgt: 'root', events: [] }] }], inputs: MODEL.inputs };
  assert.deepEqual(names(offersByChart(any, { charts: { c: 'root.a' } })), { c: ['needle_mounted', 'recover', 'take_over', 'teleop_done'] });
  assert.equal(gated(MODEL, MODEL.inputs[4]), false);
  assert.equal(gated(MODEL, MODEL.inputs[0]), true);
  // A model without transitions (an older recording): nothing is gated.
  assert.equal(gated({ charts: [{ name: 'c', states: [] }] }, MODEL.inputs[0]), false);
});

test('the failure that led to a choice is the last failure event since the chart entered its previous state', () => {
  const events = [
    { type: 'event', t: 1.0, source: 'NeedlePlanner', name: 'e_plan_failed' },
    { type: 'event', t: 3.0, source: 'needle', name: 'root.Work' },
    { type: 'event', t: 4.2, source: 'NeedleMonitor', name: 'e_forbidden_region' },
    { type: 'event', t: 4.2, source: 'needle', name: 'root.WaitReaction' },
    { type: 'event', t: 6.0, source: 'NeedleMonitor', name: 'e_forbidden_region' },
  ];
  assert.deepEqual(failureLeadingTo(MODEL, events, 3.0, 5.0), events[2]);
  assert.equal(failureLeadingTo(MODEL, events, 3.0, 4.0), null, 'none yet at 4 s');
  assert.equal(failureLeadingTo(MODEL, events, 1.5, 2.0), null, 'the failure at 1 s came before the previous state');
  assert.deepEqual(failureLeadingTo(MODEL, events, 3.0, 7.0), events[4]);
});
