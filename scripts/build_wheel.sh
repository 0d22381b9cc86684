#!/usr/bin/env bash
# `make wheel`: the Python package as one wheel, built once and installed anywhere (issue 51).
# maturin builds python/ in the release profile into the workspace's target/, so the crates that
# `make build` (the command line) compiled are reused: only pyo3, numpy and the binding itself
# are compiled on top. The wheel is abi3 (CPython >= 3.10) and holds libhdf5: installing it
# needs no compiler, `pip install target/wheel/contactmap-*.whl` takes seconds. The wheel goes
# to target/wheel/ alone (an older one removed first): `pip install ./python` leaves its own wheel
# in maturin's target/wheels/, and a glob over both would ask pip for two copies of one package.
# usage: scripts/build_wheel.sh   (maturin from PyPI into .venv-wheel, once)
set -euo pipefail
cd "$(dirname "$0")/.."
venv=.venv-wheel
[ -x "$venv/bin/maturin" ] || {
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q --disable-pip-version-check "maturin>=1.16,<2"
}
rm -f target/wheel/contactmap-*.whl
"$venv/bin/maturin" build --release -m python/Cargo.toml --out target/wheel "$@"
ls -1 target/wheel/contactmap-*.whl
