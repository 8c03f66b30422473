// Records the editor fixture's palette (test/fixtures/editor/palette.json) from cobra itself: every
// type of TYPES is created in one `cobra console --sim` (the trajectory generator configured, as its
// pose ports are made at configure) and `ls` of each instance is read back into the palette entry
// studio/PROTOCOL.md's "/api/editor/palette" names. Run again when a recorded type changes:
//   COBRA_BIN=build/release/tools/cobra/cobra node test/make_editor_fixtures.mjs
import { spawnSync } from 'node:child_process';
import { mkdtempSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
/** Package -> the types recorded from it (enough for the thesis' Fig. 3.4 and a role violation). */
export const TYPES = {
  cobra_sim: ['SimulatedUR5Robot', 'SimulatedISURRobot', 'SimulatedFTSens'],
  cobra_motion: ['CartesianTrajectoryGenerator', 'EquivalentWrench', 'WaypointPath'],
  cobra_control: ['VariableAdmittance', 'PassivityLayer'],
  cobra_signal: ['SineGenerator', 'Gain', 'ThresholdDetector', 'Constant'],
  cobra_monitoring: ['ContactMonitor'],
  cobra_coordination: ['Supervisor'],
};

/** The unit in "[m/s, rad/s]" and the doc after "--" of one `ls` line's rest. */
function unitAndDoc(rest) {
  const [head, ...doc] = rest.split('  -- ');
  const unit = /\[([^\]]*)\]\s*$/.exec(head.replace(/ in \[[^\]]*\]$/, ''));
  return { head, unit: unit ? unit[1] : '', doc: doc.join('  -- ').trim() };
}

/** One component's palette entry from its `ls` block (first line "NAME [Role, ...]"). */
export function parseListing(type, pkg, lines) {
  const role = /\[(\w+),/.exec(lines[0])[1];
  const entry = { type, package: pkg, role, doc: lines[1].trim(), ports: [], properties: [], operations: [] };
  for (const line of lines.slice(2)) {
    let m = /^ {2}(in|out|in\(event\))\s+(\w+) : (\S+)(.*)$/.exec(line);
    if (m) {
      const { unit, doc } = unitAndDoc(m[4].replace(/ <- .*?\)\)/, ''));
      entry.ports.push({ name: m[2], direction: m[1] === 'out' ? 'out' : 'in', type: m[3], event: m[1] === 'in(event)', unit, doc });
      continue;
    }
    m = /^ {2}property\s+(\w+) : (\S+) = (.*)$/.exec(line);
    if (m) {
      const { head, doc } = unitAndDoc(m[3]);
      const range = / in \[([^,\]]+), ([^\]]+)\]$/.exec(head);
      const withoutRange = range ? head.slice(0, range.index) : head;
      const unit = /^(.*?) \[([^\]]*)\]$/.exec(withoutRange);
      entry.properties.push({
        name: m[1], type: m[2], unit: unit ? unit[2] : '', doc,
        range: range ? [Number(range[1]), Number(range[2])] : null,
        default: unit ? unit[1] : withoutRange, read_only: false,
      });
      continue;
    }
    m = /^ {2}operation (.*?) {2}-- (.*)$/.exec(line);
    if (m) entry.operations.push({ name: /(\w+)\(/.exec(m[1])[1], signature: m[1], doc: m[2] });
  }
  return entry;
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const cobra = process.env.COBRA_BIN;
  if (!cobra) throw new Error('set COBRA_BIN to the cobra tool of a build tree');
  const names = [];
  const rows = [];
  for (const [pkg, types] of Object.entries(TYPES)) {
    for (const type of types) {
      names.push({ name: `P${names.length}`, type, pkg });
      rows.push(`  { peer_name = "P${names.length - 1}", component_type = "${type}" },`);
    }
  }
  const trajectory = names.find((n) => n.type === 'CartesianTrajectoryGenerator').name;
  const lua = `initConfigurator({ ${Object.keys(TYPES).map((p) => `"${p}"`).join(', ')} }, {\n${rows.join('\n')}\n})\ngetReferences()\nconfigureComponents({ "${trajectory}" })\n`;
  const file = join(mkdtempSync(join(tmpdir(), 'cobra-editor-fixture-')), 'palette.lua');
  writeFileSync(file, lua);
  const run = spawnSync(cobra, ['console', file, '--sim'], { input: names.map((n) => `ls ${n.name}\n`).join(''), encoding: 'utf8' });
  if (run.status !== 0) throw new Error(`cobra console ${file}: exit ${run.status}\n${run.stderr}`);
  const blocks = run.stdout.split(/\n(?=P\d+ \[)/).filter((b) => /^P\d+ \[/.test(b));
  const types = blocks.map((block) => {
    const lines = block.split('\n').filter((l) => l.length > 0);
    const n = names[Number(/^P(\d+)/.exec(lines[0])[1])];
    return parseListing(n.type, n.pkg, lines);
  });
  const palette = { packages: Object.keys(TYPES), types };
  writeFileSync(join(here, 'fixtures/editor/palette.json'), `${JSON.stringify(palette, null, 1)}\n`);
  console.log(`recorded ${types.length} types into test/fixtures/editor/palette.json`);
}
