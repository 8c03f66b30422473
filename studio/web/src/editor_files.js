// The editor's files: the read-only text view of the opened or saved file (a file that does not
// load shows its text with the failing line marked, and the page never saves over it) and the
// new-component form (POST /api/editor/generate: `cobra new component`'s generator).
import { h } from './editor_panels.js';
import { generatedType, generatorTypes, isIdentifier } from './editor_model.js';

/** Shows `text` in the file view, `title` above it, line `errorLine` (1-based) marked, or hides it. */
export function showFile(section, { title, text, errorLine = null, error = null }) {
  section.hidden = text == null;
  if (text == null) return;
  const lines = text.split('\n');
  if (lines.at(-1) === '') lines.pop();
  // replaceChildren would write a null as the text "null": only the parts there are.
  section.replaceChildren(...[
    h('h2', {}, title),
    error ? h('p', { class: 'file-error', role: 'alert' }, error) : null,
    h('pre', { id: 'file-text', class: 'file-text' }, lines.map((line, i) => h('span', {
      class: `line${i + 1 === errorLine ? ' error-line' : ''}`, 'data-line': i + 1,
    }, h('span', { class: 'line-number' }, String(i + 1).padStart(4)), ` ${line}\n`))),
  ].filter((part) => part !== null));
  section.querySelector('.error-line')?.scrollIntoView({ block: 'center' });
}

const ROLES = ['Calculation', 'Decision', 'Supervision', 'Bridge'];
const LISTS = [
  ['inputs', 'Inputs', 'input'], ['event_inputs', 'Event inputs', 'event input'], ['outputs', 'Outputs', 'output'],
  ['properties', 'Properties', 'property'],
];

function memberRow(typesList) {
  const row = h('div', { class: 'member' },
    h('input', { type: 'text', class: 'member-name', placeholder: 'name', size: 12 }),
    h('input', { type: 'text', class: 'member-type', placeholder: 'type', list: typesList, size: 20 }),
    h('input', { type: 'text', class: 'member-unit', placeholder: 'unit (SI)', size: 8 }),
    h('button', { type: 'button', class: 'member-remove', title: 'remove', onclick: () => row.remove() }, '×'));
  return row;
}

/** The form's content as generate's `component` ({ name, role, package, doc, inputs, ... }). */
export function readTypeForm(form) {
  const spec = {
    name: form.querySelector('#type-name').value.trim(),
    role: form.querySelector('#type-role').value.toLowerCase(), // the generator's spelling
    package: form.querySelector('#type-package').value.trim(),
    doc: form.querySelector('#type-doc').value.trim(),
  };
  for (const [key] of LISTS) {
    spec[key] = [...form.querySelectorAll(`[data-list="${key}"] .member`)]
      .map((row) => ({
        name: row.querySelector('.member-name').value.trim(),
        type: row.querySelector('.member-type').value.trim(),
        unit: row.querySelector('.member-unit').value.trim(),
      }))
      .filter((m) => m.name !== '' || m.type !== '');
  }
  return spec;
}

/** What the page checks before asking the server (which checks everything again). */
export function typeFormError(spec, palette) {
  if (!isIdentifier(spec.name)) return `component type '${spec.name}': a name is an identifier`;
  if (palette.types.some((t) => t.type === spec.name)) return `a component type named '${spec.name}' exists already (package ${palette.types.find((t) => t.type === spec.name).package})`;
  if (!spec.package) return 'the package of the new type is missing';
  const known = generatorTypes(palette);
  for (const [key, label] of LISTS) {
    for (const m of spec[key]) {
      if (!isIdentifier(m.name)) return `${label.toLowerCase()}: '${m.name}' is not an identifier`;
      if (!m.type) return `${label.toLowerCase()}: '${m.name}' has no type`;
      if (!known.includes(m.type)) return `${label.toLowerCase()}: '${m.name}' has type '${m.type}', which the generator does not know; it knows ${known.join(', ')}`;
    }
  }
  return null;
}

/**
 * Fills the new-component dialog (types offered from the palette) and wires it: Generate posts the
 * form, lists the files written and adds the type to the palette marked generated.
 */
export function setUpTypeDialog(dialog, { palette, generate, added }) {
  const typesList = 'palette-data-types';
  // The palette's data types the generator knows (its data_types flagged generate), by name.
  const known = generatorTypes(palette());
  dialog.replaceChildren(h('form', { method: 'dialog', id: 'type-form' },
    h('h2', {}, 'New component type'),
    h('datalist', { id: typesList }, known.map((t) => h('option', { value: t }))),
    h('label', {}, 'name ', h('input', { type: 'text', id: 'type-name', placeholder: 'ForceWatch' })),
    h('label', {}, 'role ', h('select', { id: 'type-role' }, ROLES.map((r) => h('option', { value: r }, r)))),
    h('label', {}, 'package ', h('input', { type: 'text', id: 'type-package', placeholder: 'my_package' })),
    h('label', {}, 'folder ', h('input', { type: 'text', id: 'type-folder', placeholder: 'the package folder' })),
    h('label', { class: 'wide' }, 'doc ', h('input', { type: 'text', id: 'type-doc', size: 50 })),
    LISTS.map(([key, label, one]) => h('fieldset', { 'data-list': key }, h('legend', {}, label),
      h('button', { type: 'button', class: 'member-add', onclick: (e) => e.target.before(memberRow(typesList)) }, `+ ${one}`))),
    h('p', { id: 'type-known', class: 'type-known' }, `port and property types: ${known.join(', ')}`),
    h('p', { id: 'type-error', class: 'field-problem', role: 'alert' }),
    h('ul', { id: 'type-files' }),
    h('div', { class: 'buttons' },
      h('button', { type: 'button', id: 'type-generate' }, 'Generate'),
      h('button', { type: 'button', id: 'type-close', onclick: () => dialog.close() }, 'Close'))));
  const form = dialog.querySelector('form');
  const error = dialog.querySelector('#type-error');
  const files = dialog.querySelector('#type-files');
  dialog.querySelector('#type-generate').addEventListener('click', async () => {
    const spec = readTypeForm(form);
    error.textContent = typeFormError(spec, palette()) ?? '';
    files.replaceChildren();
    if (error.textContent) return;
    try {
      const answer = await generate(form.querySelector('#type-folder').value.trim(), spec);
      files.replaceChildren(...answer.files.map((f) => h('li', {}, f)));
      added(generatedType(spec));
    } catch (err) {
      error.textContent = err.message;
    }
  });
}
