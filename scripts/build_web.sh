#!/usr/bin/env bash
# The viewer page of `contactmap serve` (web/) built into web/dist: `npm ci` from the committed
# lockfile (packages from the npm registry only: no browser or other download), then `vite build`.
# Without npm, or with a Node.js older than vite 7 needs, it says so and exits 0: serve's API works
# without the page, and serve says where the page is missing.
# usage: scripts/build_web.sh            (make web)
#        scripts/build_web.sh --if-stale (only when web/dist or web/node_modules is older than
#                                         what it is built from; the browser test's call)
set -euo pipefail
cd "$(dirname "$0")/../web"
say() { echo "web: $*" >&2; }
if ! command -v npm >/dev/null || ! command -v node >/dev/null; then
  say "no npm: the viewer page (web/dist) is not built (apt-get install nodejs npm)"
  exit 0
fi
# vite 7 needs Node.js ^20.19 or >= 22.12 (Debian 12's own nodejs is 18).
if ! node -e 'const [a, b] = process.versions.node.split(".").map(Number);
  process.exit(a > 22 || (a === 22 && b >= 12) || (a === 20 && b >= 19) ? 0 : 1)'; then
  say "Node.js $(node --version) is older than vite 7 needs (20.19): the viewer page is not built"
  exit 0
fi
install=1
build=1
if [ "${1:-}" = --if-stale ]; then
  [ -f node_modules/.package-lock.json ] && [ ! package-lock.json -nt node_modules/.package-lock.json ] \
    && install=
  [ -z "$install" ] && [ -f dist/index.html ] \
    && [ -z "$(find src index.html vite.config.js package-lock.json -newer dist/index.html | head -1)" ] \
    && build=
fi
if [ -n "$install" ]; then
  npm ci --no-audit --no-fund --loglevel=error
fi
if [ -n "$build" ]; then
  npx vite build --logLevel warn
  say "built web/dist ($(du -sh dist | cut -f1))"
fi
