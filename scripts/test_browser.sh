#!/usr/bin/env bash
# The viewer page of `contactmap serve` in a real browser (issue 54; the last step of `make test`):
# serve on a free loopback port, then web/test/browser.mjs drives headless Chromium (Debian's
# chromium, through playwright-core) over the page: the heatmap drawn and darker along the diagonal
# than off it, a TAD track drawn, the mouse wheel zooming in and the new tiles served, the
# normalisation switch asking for tiles with the chosen transform, and two maps of one genome locked
# together. Two runs:
#   1. data/cooler_test_file.mcool with its insulation domains (`contactmap tads --domains`) as a
#      BED track (only the map when serve takes no BED);
#   2. data/tiles/square.mcool under two names (it stores KR and ICE weights at every level).
# SAVE_SCREENSHOT=1 writes run 1's page to docs/serve-screenshot.png.
# Skips (exit 0, saying why) without chromium or node, and without npm when web/dist is not built.
# usage: scripts/test_browser.sh [CONTACTMAP]   (default: target/debug/contactmap)
set -euo pipefail
cd "$(dirname "$0")/.."
cm=$(realpath "${1:-${CONTACTMAP:-target/debug/contactmap}}")
skip() { echo "browser test skipped: $*"; exit 0; }
fail() { echo "test_browser: FAIL: $*" >&2; exit 1; }

chromium=${CHROMIUM:-$(command -v chromium || command -v chromium-browser || true)}
[ -n "$chromium" ] || skip "no chromium (apt-get install chromium)"
command -v node >/dev/null || skip "no node (apt-get install nodejs npm)"
scripts/build_web.sh --if-stale
[ -f web/dist/index.html ] || skip "web/dist is not built (see the line above)"
[ -d web/node_modules/playwright-core ] || skip "web/node_modules has no playwright-core (cd web && npm ci)"
"$cm" serve --help >/dev/null || fail "$cm serve --help"

work=$(mktemp -d)
server=
cleanup() {
  [ -n "$server" ] && kill "$server" 2>/dev/null && wait "$server" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT

# serve FILE...: start `contactmap serve` on a free port; sets $url, or returns 1 (the server stopped
# at start; its messages are in $work/serve.log).
serve() {
  url=
  "$cm" serve --port 0 --web "$PWD/web/dist" "$@" >"$work/serve.out" 2>"$work/serve.log" &
  server=$!
  for _ in $(seq 600); do
    url=$(sed -n 's|^contactmap serve: \(http://[^ ]*\)$|\1|p' "$work/serve.log" | head -1)
    [ -n "$url" ] && return 0
    if ! kill -0 "$server" 2>/dev/null; then
      wait "$server" 2>/dev/null || true
      server=
      return 1
    fi
    sleep 0.1
  done
  fail "serve $*: no URL printed in 60 s"
}
stop() {
  kill "$server" 2>/dev/null || true
  wait "$server" 2>/dev/null || true
  server=
}

passed=0
failed=0
# browse NAME ARGS...: run the page's checks, count them
browse() {
  local name=$1
  shift
  echo "== browser run $name: $url"
  local rc=0
  timeout 600 node web/test/browser.mjs "$url" --chromium "$chromium" "$@" | tee "$work/browser.log" || rc=$?
  local counts
  counts=$(sed -n 's/^browser: \([0-9]*\) passed, \([0-9]*\) failed$/\1 \2/p' "$work/browser.log" | tail -1)
  if [ -z "$counts" ]; then
    failed=$((failed + 1))
    echo "browser run $name: no result (exit $rc)"
    return
  fi
  passed=$((passed + ${counts% *}))
  failed=$((failed + ${counts#* }))
  [ "$rc" = 0 ] || [ "${counts#* }" != 0 ] || failed=$((failed + 1))
}

# Run 1: a map and its TADs.
"$cm" tads data/cooler_test_file.mcool::/resolutions/100000 --domains "$work/tads.bed" \
  -o "$work/insulation.tsv" 2>/dev/null || fail "contactmap tads"
track=(--track bedlike)
if ! serve data/cooler_test_file.mcool "$work/tads.bed"; then
  echo "serve takes no BED ($(tail -1 "$work/serve.log")): the TAD track is not checked"
  track=()
  serve data/cooler_test_file.mcool || fail "serve data/cooler_test_file.mcool: $(cat "$work/serve.log")"
fi
shot=()
[ "${SAVE_SCREENSHOT:-}" = 1 ] && shot=(--screenshot docs/serve-screenshot.png)
browse 1 "${track[@]}" "${shot[@]}"
stop

# Run 2: two maps of one genome side by side, with stored normalisations.
cp data/tiles/square.mcool "$work/replicate.mcool"
serve data/tiles/square.mcool "$work/replicate.mcool" \
  || fail "serve square.mcool replicate.mcool: $(cat "$work/serve.log")"
browse 2
stop

# Run 3: juicebox.js' reader (hic-straw, node) opens a served .hic by URL (range requests, CORS)
# and reads chr2L's records as contactmap dump reads them.
if [ -d web/node_modules/hic-straw ]; then
  serve data/hic_test_file.hic || fail "serve data/hic_test_file.hic: $(cat "$work/serve.log")"
  want=$("$cm" dump data/hic_test_file.hic -r chr2L | awk '{s += $NF; n++} END {printf "records %d sum %d", n, s}')
  got=$(timeout 120 node web/test/straw.mjs "${url}files/hic_test_file.hic" chr2L 100000 | tee "$work/straw.log" | sed -n 's/^straw: \(records .*\)$/\1/p')
  cat "$work/straw.log"
  if [ -n "$got" ] && [ "$got" = "$want" ]; then
    echo "ok     hic-straw read the served .hic by URL: $got, as contactmap dump"
    passed=$((passed + 1))
  else
    echo "FAIL   hic-straw on the served .hic: '$got', contactmap dump: '$want'"
    failed=$((failed + 1))
  fi
  stop
else
  echo "hic-straw check skipped: web/node_modules has no hic-straw (cd web && npm ci)"
fi

echo "browser: $passed passed, $failed failed"
[ "$failed" = 0 ]
