#!/bin/sh
# Installs studio/web's npm packages with `npm ci` when node_modules/ was not installed from the
# current package-lock.json; otherwise does nothing and needs no network (offline builds work).
# Called by ./do build and by the CMake target studio_web.
set -eu
cd "$(dirname "$0")/.."
# Without Node.js >= 20 the CMake of studio/web skips the page with a warning saying so.
command -v npm >/dev/null && command -v node >/dev/null || exit 0
[ "$(node -p 'process.versions.node.split(".")[0]')" -ge 20 ] || exit 0
stamp=node_modules/.cobra-package-lock.sha256
want=$(sha256sum package-lock.json | cut -d' ' -f1)
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then exit 0; fi
echo "studio/web: npm ci (package-lock.json changed or node_modules/ missing)"
npm ci --no-audit --no-fund --loglevel=error
echo "$want" >"$stamp"
