// Bundles the pages into DIR (argument; default studio/web/dist): index.html, assets/studio.js (one
// classic script: module scripts do not load from file://, where a run folder's replay opens),
// assets/studio.css and the bundled packages' licences (assets/studio.js.LEGAL.txt); the deployment
// editor's editor.html, assets/editor.js and assets/editor.css.
// Usage: node build.mjs [DIR]   (CMake's studio_web target passes the build tree's folder)
import { build } from 'esbuild';
import { copyFileSync, mkdirSync, rmSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const dist = resolve(process.argv[2] ?? join(here, 'dist'));
rmSync(dist, { recursive: true, force: true });
mkdirSync(join(dist, 'assets'), { recursive: true });
await build({
  entryPoints: { studio: join(here, 'src/main.js'), editor: join(here, 'src/editor.js') },
  bundle: true,
  format: 'iife',
  minify: true,
  target: ['chrome110', 'firefox110', 'safari16'],
  outdir: join(dist, 'assets'),
  logLevel: 'warning',
  legalComments: 'linked',
});
copyFileSync(join(here, 'src/index.html'), join(dist, 'index.html'));
copyFileSync(join(here, 'src/editor.html'), join(dist, 'editor.html'));
console.log(`studio web: built ${dist}`);
