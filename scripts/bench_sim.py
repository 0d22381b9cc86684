#!/usr/bin/env python3
"""Stepping throughput of `contactmap simulate polymer`, in monomer-steps per second, on the
systems of issue 12 (polychrom's: harmonic bonds wiggle 0.1, polynomial repulsion 3 kT / 1.05,
periodic box at density 0.2), side by side with OpenMM when it is importable.

usage: scripts/bench_sim.py [BINARY] [--device gpu|cpu] [--threads N] [--only 10k,100k,1M,64x10k]
                            [--openmm CUDA|CPU] [--scale X]

Each system runs twice with different step counts (one sample at the end, no equilibration) and
the rate is the extra monomer-steps over the extra seconds, so set-up (initial conformations,
shader compilation, writing the .cool) cancels out. --scale multiplies the step counts (default 1:
a few seconds per run on the CPU; on an H100 / H200 use --scale 10, since at scale 1 the extra
steps of the GPU runs last well under a second and start-up noise swamps them: a rate whose extra
time is under 1 s is flagged as unreliable). With --openmm, scripts/openmm_baseline.py runs the single-chain
systems on that platform (mixed precision on CUDA) and the ratio is printed.
"""
import os
import subprocess
import sys
import tempfile
import time


def option(name, default):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


flags = {"--device", "--threads", "--only", "--openmm", "--scale"}
positional = [a for k, a in enumerate(sys.argv[1:], 1) if not a.startswith("--") and sys.argv[k - 1] not in flags]
binary = positional[0] if positional else "target/release/contactmap"
device = option("--device", "gpu")
threads = option("--threads", None)
openmm = option("--openmm", None)
scale = float(option("--scale", "1"))
# name: (beads per chain, replicas, steps of the short run, steps of the long run)
systems = {
    "10k": (10_000, 1, 4_000, 20_000),
    "100k": (100_000, 1, 1_000, 5_000),
    "1M": (1_000_000, 1, 200, 1_000),
    "64x10k": (10_000, 64, 200, 1_000),
}
only = option("--only", ",".join(systems)).split(",")
work = tempfile.mkdtemp(prefix="bench_sim_")


def run(n, replicas, steps):
    cool = os.path.join(work, "bench.cool")
    command = [binary, "simulate", "polymer", "-o", cool, "--chains", str(n), "--density", "0.2",
               "--confinement", "box", "--replicas", str(replicas), "--equilibration", "0",
               "--samples", "1", "--sample-every", str(steps), "--device", device, "--seed", "1"]
    if threads:
        command += ["--threads", threads]
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if done.returncode != 0:
        sys.exit(f"failed: {' '.join(command)}\n{done.stderr}")
    where = [line for line in done.stderr.splitlines() if line.startswith("simulate polymer: on")]
    return elapsed, where[0] if where else ""


def openmm_rate(n):
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "openmm_baseline.py")
    done = subprocess.run([sys.executable, script, str(n), "0.2", "2000", threads or "16", openmm],
                          capture_output=True, text=True)
    for line in done.stdout.splitlines():
        if "M monomer-steps/s" in line:
            return float(line.split(",")[-1].split()[0]) * 1e6, line
    return None, done.stdout + done.stderr


for name in only:
    n, replicas, short, long = systems[name]
    short, long = max(1, int(short * scale)), max(2, int(long * scale))
    t_short, where = run(n, replicas, short)
    t_long, _ = run(n, replicas, long)
    rate = n * replicas * (long - short) / max(t_long - t_short, 1e-9)
    if t_long - t_short < 1.0:
        where += "; UNRELIABLE: the extra steps took under 1 s, raise --scale"
    print(f"{name}: {n} beads x {replicas} replicas, {short} and {long} steps: {t_short:.2f} s and {t_long:.2f} s "
          f"-> {rate / 1e6:.1f} M monomer-steps/s ({where})", flush=True)
    if openmm and replicas == 1:
        peer, line = openmm_rate(n)
        if peer:
            print(f"  OpenMM {openmm}: {peer / 1e6:.1f} M monomer-steps/s -> contactmap / OpenMM = {rate / peer:.2f}", flush=True)
        else:
            print(f"  OpenMM {openmm}: no figure ({line.strip()[:300]})", flush=True)
