#!/usr/bin/env python3
"""The Python API against cooler / cooltools in one process (issue 31), on a balanced cooler
(big_bal.cool: `make_big_cool.py`, then `contactmap balance --store`).

Each job runs in a fresh subprocess (so that peak memory is its own), contactmap and the peer
alternately, REPEATS times; prints wall time of the call (not of the interpreter start-up) and
the process's peak RSS, then the medians and their ratio, and checks that the answers agree.

usage: python scripts/bench_python.py BIG_BALANCED.cool [REPEATS=3] [NPROC=2]
(a venv with cooler, cooltools and contactmap installed: `maturin develop --release -m
python/Cargo.toml` in that venv)
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys

JOB = r"""
import json, resource, sys, time
import numpy as np
uri, job, tool, nproc = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
import cooler, cooltools, contactmap as cm
clr = cooler.Cooler(uri)
region = "chr2:50,000,000-100,000,000"          # 5,000 x 5,000 bins at 10 kb
rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
t0 = time.perf_counter()
if job == "dense":
    if tool == "contactmap":
        out = cm.File(uri).fetch(region, normalization="weight").to_numpy()
    else:
        out = clr.matrix(balance=True).fetch(region)
    digest = [float(np.nansum(out)), int(np.isnan(out).sum()), list(out.shape)]
elif job == "expected_cis":
    if tool == "contactmap":
        out = cm.expected_cis(uri, ignore_diags=2)
    else:
        out = cooltools.expected_cis(clr, ignore_diags=2, nproc=nproc)
    digest = [float(np.nansum(out["balanced.avg.smoothed.agg"])), len(out)]
elif job == "insulation":
    if tool == "contactmap":
        out = cm.insulation(uri, [100_000, 200_000])
    else:
        out = cooltools.insulation(clr, [100_000, 200_000], nproc=nproc)
    digest = [float(np.nansum(out["log2_insulation_score_100000"])), len(out)]
elapsed = time.perf_counter() - t0
rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({"s": elapsed, "peak_mb": rss / 1024, "rise_mb": (rss - rss0) / 1024, "digest": digest}))
"""


def main() -> None:
    uri = sys.argv[1]
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    nproc = sys.argv[3] if len(sys.argv) > 3 else "2"
    peers = {"dense": "cooler", "expected_cis": "cooltools", "insulation": "cooltools"}
    for job, peer in peers.items():
        runs: dict[str, list[dict]] = {"contactmap": [], peer: []}
        for _ in range(repeats):
            for tool in ("contactmap", peer):
                out = subprocess.run(
                    [sys.executable, "-c", JOB, uri, job, tool, nproc],
                    check=True, capture_output=True, text=True,
                ).stdout
                runs[tool].append(json.loads(out.strip().splitlines()[-1]))
        ours, theirs = runs["contactmap"], runs[peer]
        t_ours = statistics.median(r["s"] for r in ours)
        t_theirs = statistics.median(r["s"] for r in theirs)
        def times(rs: list[dict]) -> str:
            return ", ".join("%.3f" % r["s"] for r in rs)

        def memory(rs: list[dict]) -> str:
            return "peak %.0f MB, rise %.0f MB" % (
                max(r["peak_mb"] for r in rs),
                max(r["rise_mb"] for r in rs),
            )

        print(
            f"{job}: contactmap {times(ours)} s ({memory(ours)}); "
            f"{peer} {times(theirs)} s ({memory(theirs)}); "
            f"median ratio {t_theirs / t_ours:.1f}x"
        )
        a, b = ours[0]["digest"], theirs[0]["digest"]
        same = all(
            (abs(x - y) <= 1e-9 * max(abs(x), abs(y), 1)) if isinstance(x, float) else x == y
            for x, y in zip(a, b)
        )
        print(f"  answers: contactmap {a} vs {peer} {b}: {'same' if same else 'DIFFERENT'}")


if __name__ == "__main__":
    main()
