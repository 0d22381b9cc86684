#!/usr/bin/env bash
# Print a directory holding a `cmake` executable, installing cmake from PyPI into .tools/ when the
# machine has none. hdf5-metno (feature "static") builds libhdf5 from source with cmake.
# Progress goes to stderr; stdout carries only the directory (empty when cmake is already on PATH).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if command -v cmake >/dev/null 2>&1; then
  exit 0
fi
tools="$root/.tools/cmake"
bin="$tools/cmake/data/bin"
if [ ! -x "$bin/cmake" ]; then
  echo "cmake not found: installing it from PyPI into $tools (python3 -m pip install cmake)" >&2
  python3 -m pip install --quiet --disable-pip-version-check --target "$tools" cmake >&2 \
    || python3 -m pip install --quiet --disable-pip-version-check --break-system-packages --target "$tools" cmake >&2
fi
echo "$bin"
