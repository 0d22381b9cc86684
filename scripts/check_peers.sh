#!/usr/bin/env bash
# Compare contactmap with cooler 0.11 / hictkpy on every .cool, .mcool and .hic under DATA_DIR:
#  1. `contactmap info` nbins, nnz and count sum against the peers' figures;
#  2. convert each matrix to .cool and .mcool with contactmap, open the outputs with cooler and
#     check pixels, bins and weights against the source as cooler / hictkpy read it.
# Needs a venv with cooler and hictkpy (python3 -m venv .venv && .venv/bin/pip install cooler hictkpy).
# Usage: scripts/check_peers.sh [DATA_DIR] [VENV]   (defaults ../shared/data/hic and .venv)
set -euo pipefail
cd "$(dirname "$0")/.."
data="${1:-../shared/data/hic}"
venv="${2:-.venv}"
exec "$venv/bin/python" scripts/check_peers.py "$data" target/release/contactmap
