#!/usr/bin/env bash
# The Python package's test (run by `make test`): puts `contactmap` (python/) into .venv-python,
# installing python/requirements-test.txt there when it changed, then runs pytest on python/tests,
# which compares every function with cooler / cooltools references and with the command line
# CONTACTMAP (default target/debug/contactmap), then checks the .pyi stubs (mypy's stubtest).
# The native module is built by maturin (the dev profile, or --release), or, with --module SO,
# is a cdylib cargo already built (make test: `cargo test` builds python/ with
# PYO3_BUILD_EXTENSION_MODULE=1): it is copied into python/contactmap and python/ is put on the
# venv's path, as `maturin develop` does, without compiling anything again.
# usage: scripts/test_python.sh [CONTACTMAP] [--release | --module SO]
#        scripts/test_python.sh --prepare   (only the venv and its requirements: make test makes
#                                           them while cargo compiles)
set -euo pipefail
cd "$(dirname "$0")/.."
prepare() {
  [ -x "$venv/bin/python" ] || python3 -m venv "$venv"
  # (re)install when the requirements changed since the last install
  if ! cmp -s python/requirements-test.txt "$venv/.requirements-test.txt"; then
    "$venv/bin/pip" install -q --disable-pip-version-check -r python/requirements-test.txt
    cp python/requirements-test.txt "$venv/.requirements-test.txt"
  fi
}
venv=.venv-python
if [ "${1:-}" = "--prepare" ]; then
  prepare
  exit 0
fi
export CONTACTMAP_BIN
CONTACTMAP_BIN=$(realpath "${1:-target/debug/contactmap}")
profile=()
module=
case "${2:-}" in
  --release) profile=(--release) ;;
  --module) module=$(realpath "${3:?--module needs the path of the built cdylib}") ;;
  "") ;;
  *) echo "test_python.sh: unknown option $2 (expected --release or --module SO)" >&2; exit 2 ;;
esac
prepare
if [ -z "$module" ]; then
  VIRTUAL_ENV="$(realpath "$venv")" "$venv/bin/maturin" develop -q -m python/Cargo.toml "${profile[@]}"
else
  # an installed copy (a wheel, or maturin's editable install) would come first on the path
  "$venv/bin/pip" uninstall -q -y contactmap >/dev/null 2>&1 || true
  cp "$module" python/contactmap/_native.abi3.so
  site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
  realpath python > "$site/contactmap-source.pth"
  "$venv/bin/python" - "$(realpath python/contactmap)" <<'PY'
import os, sys
import contactmap
where = os.path.dirname(os.path.realpath(contactmap.__file__))
if where != sys.argv[1]:
    sys.exit(f"test_python.sh: the venv imports contactmap from {where}, not {sys.argv[1]}")
PY
fi
"$venv/bin/python" -m pytest -q python/tests
# the stubs against the built module
(cd python && "../$venv/bin/python" -m mypy.stubtest contactmap --mypy-config-file pyproject.toml \
  --allowlist stubtest-allowlist.txt)
