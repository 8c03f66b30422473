// Records the editor fixture's palette (test/fixtures/editor/palette.json) from cobra itself: the
// answer of GET /api/editor/palette of `cobra edit` (every type of every package cobra can load,
// made and introspected by the server), as it is. editor_e2e_cobra.test.mjs checks that the
// fixture is still that palette; when a type changes, record it again:
//   COBRA_BIN=build/release/tools/cobra/cobra node test/make_editor_fixtures.mjs
import { readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { startCobra, stopCobras } from './cobra_process.mjs';

const here = dirname(fileURLToPath(import.meta.url));
export const PALETTE_FIXTURE = join(here, 'fixtures/editor/palette.json');

/** The palette `cobra edit` (COBRA_BIN) serves, parsed. */
export async function servedPalette() {
  const { url } = await startCobra(['edit', '--port', '0'], 'editor');
  const page = new URL(url);
  const answer = await fetch(new URL(`/api/editor/palette?token=${page.searchParams.get('token')}`, page));
  if (!answer.ok) throw new Error(`GET /api/editor/palette: HTTP ${answer.status}: ${await answer.text()}`);
  return answer.json();
}

/** The recorded palette. */
export function recordedPalette() {
  return JSON.parse(readFileSync(PALETTE_FIXTURE, 'utf8'));
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  if (!process.env.COBRA_BIN) throw new Error('set COBRA_BIN to the cobra tool of a build tree');
  try {
    const palette = await servedPalette();
    writeFileSync(PALETTE_FIXTURE, `${JSON.stringify(palette, null, 1)}\n`);
    console.log(`recorded ${palette.types.length} types of ${palette.packages.length} packages into test/fixtures/editor/palette.json`);
  } finally {
    stopCobras();
  }
}
