#!/usr/bin/env bash
# The Python package's test (run by `make test`): builds `contactmap` (python/, maturin, the
# dev profile so that target/debug's dependencies are reused) into .venv-python, installing
# python/requirements-test.txt there when it changed, then runs pytest on python/tests, which
# compares every function with cooler / cooltools references and with the command line
# CONTACTMAP (default target/debug/contactmap), then checks the .pyi stubs (mypy's stubtest).
# usage: scripts/test_python.sh [CONTACTMAP] [--release]
set -euo pipefail
cd "$(dirname "$0")/.."
export CONTACTMAP_BIN
CONTACTMAP_BIN=$(realpath "${1:-target/debug/contactmap}")
profile=()
[ "${2:-}" = "--release" ] && profile=(--release)
venv=.venv-python
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
# (re)install when the requirements changed since the last install
if ! cmp -s python/requirements-test.txt "$venv/.requirements-test.txt"; then
  "$venv/bin/pip" install -q --disable-pip-version-check -r python/requirements-test.txt
  cp python/requirements-test.txt "$venv/.requirements-test.txt"
fi
VIRTUAL_ENV="$(realpath "$venv")" "$venv/bin/maturin" develop -q -m python/Cargo.toml "${profile[@]}"
"$venv/bin/python" -m pytest -q python/tests
# the stubs against the built module
(cd python && "../$venv/bin/python" -m mypy.stubtest contactmap --mypy-config-file pyproject.toml \
  --allowlist stubtest-allowlist.txt)
