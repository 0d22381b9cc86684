"""(Copied from the team's ../shared/tools/openmm_baseline.py so that it travels with the repository to a
GPU machine; the peer figures of issue 12 were measured with it.)

Peer baseline for the simulator: a polychrom-style chain run with OpenMM, the platform as a 5th argument:
CPU, or CUDA / OpenCL in mixed precision (the same system on each).

Harmonic bonds (length 1, wiggle 0.05 -> k = 2 kT / w^2 ... softened to polychrom's usual 0.1), polychrom's polynomial
repulsion (trunc 3 kT, r_c = 1.05), periodic box at density rho, Langevin integrator.
Prints monomer-steps per second.  usage: python openmm_baseline.py [N] [density] [steps] [threads] [platform]
steps is a minimum: after the warm-up, steps is raised so that the timed run lasts about $OM_TARGET_S (default 8) s.
"""
import sys, time, numpy as np
import openmm as mm
from openmm import unit as u

N = int(sys.argv[1]) if len(sys.argv) > 1 else 10000
rho = float(sys.argv[2]) if len(sys.argv) > 2 else 0.2
steps = int(sys.argv[3]) if len(sys.argv) > 3 else 2000
threads = sys.argv[4] if len(sys.argv) > 4 else "1"
platname = sys.argv[5] if len(sys.argv) > 5 else "CPU"
import os
target = float(os.environ.get("OM_TARGET_S", "8"))
t_setup = time.perf_counter()
L = (N / rho) ** (1 / 3)
nm = u.nanometer
sysm = mm.System()
for _ in range(N):
    sysm.addParticle(100.0)
sysm.setDefaultPeriodicBoxVectors(mm.Vec3(L, 0, 0), mm.Vec3(0, L, 0), mm.Vec3(0, 0, L))
kT = (u.BOLTZMANN_CONSTANT_kB * 300 * u.kelvin * u.AVOGADRO_CONSTANT_NA).value_in_unit(u.kilojoule_per_mole)
w = 0.1
bonds = mm.HarmonicBondForce()
for i in range(N - 1):
    bonds.addBond(i, i + 1, 1.0, 2 * kT / w**2)
bonds.setUsesPeriodicBoundaryConditions(True)
sysm.addForce(bonds)
rc, trunc = 1.05, 3.0
rep = mm.CustomNonbondedForce(
    "rsc12 * (rsc2 - 1.0) * REPe / emin12 + REPe;"
    "rsc12 = rsc4 * rsc4 * rsc4; rsc4 = rsc2 * rsc2; rsc2 = rsc * rsc; rsc = r / REPsigma * rmin12;")
rep.addGlobalParameter("REPe", trunc * kT)
rep.addGlobalParameter("REPsigma", rc)
rep.addGlobalParameter("emin12", 46656.0 / 823543.0)
rep.addGlobalParameter("rmin12", np.sqrt(6.0 / 7.0))
for _ in range(N):
    rep.addParticle(())
rep.setCutoffDistance(rc)
rep.setNonbondedMethod(mm.CustomNonbondedForce.CutoffPeriodic)
for i in range(N - 1):
    rep.addExclusion(i, i + 1)
sysm.addForce(rep)
integ = mm.LangevinMiddleIntegrator(300 * u.kelvin, 0.1 / u.picosecond, 0.07 * u.picosecond)
try:
    plat = mm.Platform.getPlatformByName(platname)
except Exception as e:
    print("platform", platname, "not available:", e, "; plugin load failures:", mm.Platform.getPluginLoadFailures()); sys.exit(3)
props = {"Threads": threads} if platname == "CPU" else {"Precision": "mixed"}
ctx = mm.Context(sysm, integ, plat, props)
rng = np.random.default_rng(0)
steps_xyz = rng.normal(size=(N, 3)); steps_xyz /= np.linalg.norm(steps_xyz, axis=1)[:, None]
pos = np.cumsum(steps_xyz, axis=0) % L
ctx.setPositions(pos * nm)
mm.LocalEnergyMinimizer.minimize(ctx, 10.0, 200)
ctx.setVelocitiesToTemperature(300 * u.kelvin)
integ.step(200)
ctx.getState(getPositions=True)
t = time.perf_counter(); integ.step(200); ctx.getState(getPositions=True); el = time.perf_counter() - t
steps = max(steps, int(target / (el / 200)))
print(f"setup+minimize+warm-up {time.perf_counter() - t_setup:.1f} s; calibration {200 / el:.1f} steps/s -> timed steps {steps}", flush=True)
t = time.perf_counter(); integ.step(steps); ctx.getState(getPositions=True); el = time.perf_counter() - t
print(f"openmm {mm.__version__} {platname} {ctx.getPlatform().getName()} {props} threads={threads} N={N} rho={rho} steps={steps}: {steps/el:.1f} steps/s, {N*steps/el/1e6:.2f} M monomer-steps/s")
