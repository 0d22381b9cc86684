#!/usr/bin/env python3
"""Known-truth study of `contactmap diff loops` and `diff boundaries` (issue 55): precision, recall
and F1 of the differential calls against the truth of simulated conditions, as curves against
depth for 2 and 3 replicates, and the observed false-discovery rate at q < 0.05 over null
comparisons (A against A with other seeds) and over comparisons with true differences.

usage: scripts/diff_study.py [--binary target/release/contactmap] [--diff-binary BIN]
                             [--out DIR] [--scale small|full] [--seed N] [--device cpu|auto|gpu]
                             [--window BP] [--match-bins N] [--tolerance BINS] [--alpha Q]
                             [--no-called]

Python 3 standard library only. Every command it runs is printed (and kept in DIR/commands.log).

Design
------
Condition A: one chain of 5 kb beads (one bead per 5 kb bin) in a sphere at density 0.2 with loop
extrusion (capture 1, release 0, processivity 300, one LEF per 30 beads: the set-up of
scripts/loops_f1_depth.sh) and convergent pairs of boundary elements: loop k is `x_k+` .. `y_k-`
with y_k - x_k drawn uniformly in 20..40 beads (--seed), and the next loop starts 4 beads after
(`y_k-`, `y_k+4 +`: a *junction*; four beads apart so that no spurious dot appears between the
outer anchors of two neighbouring loops, docs/loops.md).
Condition B: the same with a quarter of the inner junctions removed (both elements, never two
neighbouring junctions): in B the two loops on either side of a removed junction are lost, the
loop that spans both (held in A only by the few LEFs loaded inside the 4-bead gap) is gained,
and the junction's boundary is lost. Removing a whole junction, not one element, is what makes a
boundary disappear: one element of a junction alone still insulates.

Replicates are biological: independent ensembles with their own --seed (A: seeds 1001.., B:
2001.., offset by 10000 x --seed). Depths: each replicate thinned with `contactmap sample
--fraction F` (its own sample seed), then `balance --store` (ICE, cooler's defaults; stored even
when unconverged, which the log says). Depth 1 is the simulation itself.

Truth
-----
Loops: each condition's fraction of samples that held a bin pair (--truth-loops), averaged over
all of that condition's ensembles (equal numbers of samples). With f_max = max(f_A, f_B) and the
ratio r = (f_max + 0.005) / (f_min + 0.005):
  changed    f_max >= 0.1 and r >= 2 (up in B when f_B > f_A)  -- the truth difference
  unchanged  r < 1.5                                              -- a call here is false
  ambiguous  the rest (a weak pair, or a change under 2-fold)    -- calls left out of precision,
                                                                     not asked for by recall
The loops tested with --loops are the union of A's and B's truth pairs with f_max >= 0.02.
A loop call (direction up / down at q < alpha) is true when its pair is changed in the same
direction, false when unchanged or changed the other way.
Without --loops (`diff loops` calls dots itself; kind `loops_called`) a call is placed on the
truth pair whose two anchors are both within --tolerance bins (the nearest), then scored as above;
a call near no truth pair is false.
Second scoring of `loops_called` (reported beside the strict one above, which is unchanged; columns
freq_* of study.tsv, section "loops_called, second scoring" of summary.md): a call near no truth
pair is judged by the true change of contact frequency at its pixel instead of counted false.
Each full-depth simulated ensemble's pixels (`contactmap dump`) are divided by its total
contacts; a condition's frequency at a call is the sum over the call's 3x3 neighbourhood, averaged
over that condition's *held-out* ensembles (A's ensembles other than the comparison's A
replicates, B's other than its B replicates; all of a condition's ensembles, flagged
freq_held_out=no, when none is left). With the pseudo-count p = 0.005 x k, k the neighbourhood
frequency per unit of loop fraction (sum of neighbourhood frequencies / sum of fractions over
the truth pairs and conditions with f >= 0.1: the truth's own 0.005 in frequency units), and the
fold g = (F_B + p) / (F_A + p) taken in the call's direction (g for up, 1 / g for down):
  g >= 2      a real contact change, not a loop: left out of precision (freq_change_calls)
  g < 1.5     false (also any change the other way)
  otherwise   ambiguous: left out (freq_ambiguous_calls)
Calls placed on a truth pair are scored as in the strict scoring; recall is unchanged; calls of
null comparisons stay false (A against A' has no true change). Per call: loops_called_freq.tsv.
Boundaries: the truth difference is the removed junctions (lost in B). A boundary call (status
lost, gained, shifted, stronger or weaker at q < alpha) is true when it lies within --tolerance
bins of an element of a removed junction and its status is lost, weaker or shifted; any other
call is false (including gained / stronger at a removed junction, and changes that the removal
caused at untouched boundaries: they are not in the truth). Recall: removed junctions with a
true call.

Comparisons
-----------
`true`: A replicates against B replicates, the replicates of one comparison disjoint from those
of the others at the same depth and replicate number. `null`: A against A' -- disjoint sets of
A's ensembles drawn at random (--seed) from the nA ensembles; different null comparisons share
ensembles (and each depth reuses the same ensembles thinned), so they are not independent: the
number of distinct disjoint splits is what bounds their independence (documented in summary.md).
Every call of a null comparison is false. The observed FDR is the mean over comparisons of the
false-discovery proportion (false calls / calls, 0 without calls), which for null comparisons is
the fraction of comparisons with any call; the pooled false calls / calls is given too.

Outputs: DIR/study.tsv (one row per comparison and kind), DIR/summary.md (tables),
DIR/loops_called_freq.tsv (the second scoring's calls near no truth pair), DIR/sims/,
DIR/maps/, DIR/diff/ (caches: a rerun reuses every file whose parameters match).
"""
import argparse
import json
import math
import os
import random
import shlex
import shutil
import subprocess
import sys
import time

BEAD_BP = 5000

SCALES = {
    # chain length, replicas per ensemble, samples per replica, A ensembles, B ensembles, depths,
    # null comparisons per (replicates, depth), true comparisons per (replicates, depth) at most
    "small": dict(chain=400, replicas=6, samples=5, equilibration=12000, sample_every=4000,
                  n_a=6, n_b=3, depths=[0.25, 0.5, 1.0], null_per=1, true_per=1),
    "full": dict(chain=900, replicas=14, samples=5, equilibration=12000, sample_every=4000,
                 n_a=10, n_b=6, depths=[0.03, 0.1, 0.3, 1.0], null_per=4, true_per=3),
}

LOG = None


def log(msg):
    print(msg, flush=True)
    if LOG:
        LOG.write(msg + "\n")
        LOG.flush()


def run(cmd, stdout=None, may_fail=False):
    """Run a command (printed first); stop the study with its stderr when it fails (with
    may_fail, return None instead)."""
    log("$ " + " ".join(shlex.quote(str(c)) for c in cmd))
    t0 = time.time()
    p = subprocess.run([str(c) for c in cmd], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True)
    if p.returncode != 0 and may_fail:
        log("  failed: " + p.stderr.strip())
        return None
    if p.returncode != 0:
        sys.stderr.write(p.stderr)
        raise SystemExit(f"command failed (exit {p.returncode}): {' '.join(map(str, cmd))}")
    for line in p.stderr.splitlines():
        if "warning" in line.lower() and "sampled before they relaxed" not in line:
            log("  " + line)
    return p.stdout, p.stderr, time.time() - t0


# ---------------------------------------------------------------- design

def design(chain, rng):
    """Loops (x_k, y_k) of 20..40 beads, 4 beads between neighbouring loops."""
    loops, x = [], 20
    while True:
        length = rng.randint(20, 40)
        if x + length > chain - 20:
            break
        loops.append((x, x + length))
        x += length + 4
    # inner junctions: between loop k and k+1 (elements y_k- and x_{k+1}+)
    n_j = len(loops) - 1
    n_remove = max(1, round(n_j / 4))
    while True:
        removed = sorted(rng.sample(range(n_j), n_remove))
        if all(b - a > 1 for a, b in zip(removed, removed[1:])):
            break
    return loops, removed


def ctcf_list(loops, removed=()):
    gone = set()
    for j in removed:
        gone.add(("-", loops[j][1]))
        gone.add(("+", loops[j + 1][0]))
    out = []
    for x, y in loops:
        if ("+", x) not in gone:
            out.append(f"{x}+")
        if ("-", y) not in gone:
            out.append(f"{y}-")
    return ",".join(out)


# ---------------------------------------------------------------- caching helpers

def comparison_name(kind, reps, depth, a, b):
    """The name of a comparison's outputs (DIR/diff/NAME.*): kind (true / null), replicates,
    depth and the two conditions' ensemble seeds."""
    return f"{kind}.r{reps}.d{depth:g}.{'-'.join(map(str, a))}_vs_{'-'.join(map(str, b))}"


def study_rows(path):
    """DIR/study.tsv with its counts as int and its rates as float (for the peer scripts)."""
    rows = []
    for r in read_table(path):
        for k in ("replicates", "contacts", "n_tested", "n_calls", "true_calls", "false_calls",
                  "excluded_calls", "n_truth", "found"):
            r[k] = int(r[k])
        for k in ("depth", "precision", "recall", "F1", "FDP"):
            r[k] = float(r[k])
        rows.append(r)
    return rows


def study_row_name(r):
    """comparison_name of a study_rows row."""
    return comparison_name(r["comparison"], r["replicates"], r["depth"], r["a"].split(","),
                           r["b"].split(","))


def cached(path, params):
    meta = path + ".params.json"
    if os.path.exists(path) and os.path.exists(meta):
        with open(meta) as f:
            return json.load(f) == params
    return False


def mark(path, params):
    with open(path + ".params.json", "w") as f:
        json.dump(params, f, sort_keys=True)


def simulate(cm, out, ctcf, seed, sc, device):
    cool = os.path.join(out, "sims", f"s{seed}.cool")
    truth = os.path.join(out, "sims", f"s{seed}.truth_loops.bedpe")
    params = dict(ctcf=ctcf, seed=seed, device=device,
                  **{k: sc[k] for k in ("chain", "replicas", "samples", "equilibration",
                                        "sample_every")})
    if cached(cool, params) and os.path.exists(truth):
        return cool, truth, 0.0
    tmp = cool + ".tmp.cool"
    for p in (tmp, cool, cool + ".params.json"):
        if os.path.exists(p):
            os.remove(p)
    _, _, dt = run(["nice", "-n", "19", cm, "simulate", "polymer", "-o", tmp,
                    "--chains", sc["chain"], "--monomer-bp", BEAD_BP, "--density", "0.2",
                    "--extrusion", "--ctcf", ctcf, "--capture", "1", "--release", "0",
                    "--processivity", "300", "--separation", "30",
                    "--replicas", sc["replicas"], "--equilibration", sc["equilibration"],
                    "--sample-every", sc["sample_every"], "--samples", sc["samples"],
                    "--seed", seed, "--device", device, "--truth-loops", truth])
    os.replace(tmp, cool)
    mark(cool, params)
    return cool, truth, dt


def contacts_sum(cm, cool):
    stdout, _, _ = run([cm, "info", cool])
    for line in stdout.splitlines():
        f = line.split()
        if f and f[0] == "sum":
            return float(f[1])
    return float("nan")


def depth_map(cm, out, sim_cool, seed, depth_index, fraction):
    """Thinned (or copied) and balanced map of one ensemble at one depth."""
    dst = os.path.join(out, "maps", f"s{seed}.d{fraction:g}.cool")
    sample_seed = seed * 100 + depth_index + 1
    params = dict(src=os.path.basename(sim_cool), src_mtime=os.path.getmtime(sim_cool),
                  fraction=fraction, sample_seed=sample_seed)
    if cached(dst, params):
        return dst, 0.0
    t0 = time.time()
    tmp = dst + ".tmp.cool"
    for p in (tmp, dst, dst + ".params.json"):
        if os.path.exists(p):
            os.remove(p)
    if fraction >= 1:
        shutil.copyfile(sim_cool, tmp)
    else:
        run(["nice", "-n", "19", cm, "sample", sim_cool, "--fraction", fraction,
             "--seed", sample_seed, "-o", tmp])
    _, err, _ = run(["nice", "-n", "19", cm, "balance", tmp, "--store", "--force",
                     "--store-unconverged"])
    if "converged=false" in err:
        log(f"  note: ICE did not converge on {dst} (weights stored anyway)")
    os.replace(tmp, dst)
    mark(dst, params)
    return dst, time.time() - t0


# ---------------------------------------------------------------- truth

def read_truth_loops(paths):
    held = {}
    for path in paths:
        with open(path) as f:
            next(f)
            for line in f:
                c = line.rstrip("\n").split("\t")
                if len(c) < 8:
                    continue
                key = (c[0], int(c[1]) // BEAD_BP, int(c[4]) // BEAD_BP)
                held[key] = held.get(key, 0.0) + float(c[6])
    return {k: v / len(paths) for k, v in held.items()}


def loop_truth(fa, fb):
    """pair -> (class, sign): class changed / unchanged / ambiguous, sign +1 up in B."""
    truth = {}
    for key in set(fa) | set(fb):
        a, b = fa.get(key, 0.0), fb.get(key, 0.0)
        hi, lo = max(a, b), min(a, b)
        r = (hi + 0.005) / (lo + 0.005)
        if hi >= 0.1 and r >= 2:
            cls = "changed"
        elif r < 1.5:
            cls = "unchanged"
        else:
            cls = "ambiguous"
        truth[key] = (cls, 1 if b > a else -1, a, b)
    return truth


# ---------------------------------------------------------------- scoring

def read_table(path):
    with open(path) as f:
        header = f.readline().rstrip("\n").split("\t")
        return [dict(zip(header, line.rstrip("\n").split("\t"))) for line in f if line.strip()]


def call_pixel(r):
    """A loop call's (sign, chrom, bin1, bin2): sign +1 for up in B."""
    sign = 1 if r["direction"] == "up" else -1
    i = (int(r["start1"]) + int(r["end1"])) // 2 // BEAD_BP
    j = (int(r["start2"]) + int(r["end2"])) // 2 // BEAD_BP
    return sign, r["chrom1"], i, j


def nearest_truth(truth, chrom, i, j, tolerance):
    """The truth pair with both anchors within tolerance bins of (i, j), the nearest (a changed
    one on ties); None when there is none."""
    best = None
    for k in truth:
        if k[0] != chrom:
            continue
        d = max(abs(k[1] - i), abs(k[2] - j))
        if d <= tolerance and (best is None or d < best[0]
                               or (d == best[0] and truth[k][0] == "changed")):
            best = (d, k)
    return best[1] if best else None


def truth_class(t, sign):
    """A loop call of direction sign against its truth pair t (None: the call is near none):
    true (changed that way), false (unchanged, changed the other way, or no pair) or excluded
    (an ambiguous pair)."""
    if t is None or t[0] == "unchanged":
        return "false"
    if t[0] == "ambiguous":
        return "excluded"
    return "true" if t[1] == sign else "false"


def score_loops(rows, truth, tolerance, matched_nearest):
    """Calls (direction up/down) against the loop truth: (calls, true, false, excluded, found)."""
    changed = {k for k, v in truth.items() if v[0] == "changed"}
    n = dict(true=0, false=0, excluded=0)
    found = set()
    calls = [r for r in rows if r["direction"] in ("up", "down")]
    for r in calls:
        sign, chrom, i, j = call_pixel(r)
        key = nearest_truth(truth, chrom, i, j, tolerance) if matched_nearest else (chrom, i, j)
        cls = truth_class(truth.get(key), sign)
        n[cls] += 1
        if cls == "true":
            found.add(key)
    return len(calls), n["true"], n["false"], n["excluded"], len(found), len(changed)


def read_frequencies(cm, cool):
    """One ensemble's contact frequencies: (chrom, bin1, bin2) -> count / total contacts."""
    stdout, _, _ = run(["nice", "-n", "19", cm, "dump", "--join", cool])
    counts, total = {}, 0.0
    for line in stdout.splitlines():
        c = line.split("\t")
        if len(c) < 7 or c[0] != c[3]:
            continue
        n = float(c[6])
        total += n
        counts[(c[0], int(c[1]) // BEAD_BP, int(c[4]) // BEAD_BP)] = n
    return {k: v / total for k, v in counts.items()} if total else counts


def neighbourhood(freq, chrom, i, j):
    """Sum of an ensemble's frequencies over the 3x3 pixels around (i, j)."""
    total = 0.0
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            u, v = i + di, j + dj
            total += freq.get((chrom, min(u, v), max(u, v)), 0.0)
    return total


def condition_frequency(freqs, seeds, chrom, i, j):
    return sum(neighbourhood(freqs[s], chrom, i, j) for s in seeds) / len(seeds)


def score_loops_change(rows, truth, tolerance, freqs, held_a, held_b, pseudo):
    """Second scoring of loops_called: as score_loops with matched_nearest, but a call near no
    truth pair is judged by the held-out change of contact frequency at its pixel (3x3
    neighbourhood; seeds held_a and held_b): real change (>= 2-fold in the call's direction,
    left out), false (< 1.5-fold, or the other way) or ambiguous (left out). Returns the counts
    (calls, true, false, excluded by the truth's ambiguous pairs, real change, ambiguous change,
    found, truth size) and one record per call near no truth pair."""
    changed = {k for k, v in truth.items() if v[0] == "changed"}
    n = dict(true=0, false=0, excluded=0, change=0, ambiguous=0)
    found, records = set(), []
    calls = [r for r in rows if r["direction"] in ("up", "down")]
    for r in calls:
        sign, chrom, i, j = call_pixel(r)
        key = nearest_truth(truth, chrom, i, j, tolerance)
        t = truth.get(key)
        if t is not None:
            cls = truth_class(t, sign)
            if cls == "true":
                found.add(key)
        else:
            fa = condition_frequency(freqs, held_a, chrom, i, j)
            fb = condition_frequency(freqs, held_b, chrom, i, j)
            g = (fb + pseudo) / (fa + pseudo)
            g = g if sign > 0 else 1 / g
            cls = "change" if g >= 2 else "false" if g < 1.5 else "ambiguous"
            records.append(dict(chrom=chrom, bin1=i, bin2=j, direction=r["direction"],
                                F_A=fa, F_B=fb, fold=g, cls=cls))
        n[cls] += 1
    return ((len(calls), n["true"], n["false"], n["excluded"], n["change"], n["ambiguous"],
             len(found), len(changed)), records)


def score_boundaries(rows, removed_junctions, tolerance):
    """removed_junctions: list of (bin_minus, bin_plus)."""
    n_calls = n_true = n_false = 0
    found = set()
    for r in rows:
        st = r["status"]
        if st in ("-", ""):
            continue
        n_calls += 1
        b = int(r["start"]) // BEAD_BP
        hit = None
        for idx, (u, v) in enumerate(removed_junctions):
            if min(abs(b - u), abs(b - v)) <= tolerance or u <= b <= v:
                hit = idx
                break
        if hit is not None and st in ("lost", "weaker", "shifted"):
            n_true += 1
            found.add(hit)
        else:
            n_false += 1
    return n_calls, n_true, n_false, 0, len(found), len(removed_junctions)


def prf(n_calls, n_true, n_false, found, n_truth):
    scored = n_true + n_false
    precision = n_true / scored if scored else float("nan")
    recall = found / n_truth if n_truth else float("nan")
    if n_truth == 0:
        f1 = float("nan")
    elif precision != precision or precision + recall == 0:
        f1 = 0.0
    else:
        f1 = 2 * precision * recall / (precision + recall)
    fdp = n_false / scored if scored else 0.0
    return precision, recall, f1, fdp


# ---------------------------------------------------------------- statistics

def binom_cdf(k, n, p):
    return sum(math.comb(n, i) * p ** i * (1 - p) ** (n - i) for i in range(k + 1))


def clopper_pearson(k, n, level=0.95):
    a = (1 - level) / 2

    def solve(f):
        lo, hi = 0.0, 1.0
        for _ in range(60):
            mid = (lo + hi) / 2
            if f(mid):
                lo = mid
            else:
                hi = mid
        return (lo + hi) / 2

    low = 0.0 if k == 0 else solve(lambda p: 1 - binom_cdf(k - 1, n, p) < a)
    high = 1.0 if k == n else solve(lambda p: binom_cdf(k, n, p) > a)
    return low, high


def fmt(x, d=3):
    if isinstance(x, float):
        return "nan" if x != x else f"{x:.{d}f}"
    return str(x)


def study_arguments(ap):
    """--study, --scale and --seed: the diff_study.py run a peer script reads."""
    ap.add_argument("--study", default="/tmp/ds/full", help="the diff_study.py --out directory")
    ap.add_argument("--scale", choices=sorted(SCALES), default="full",
                    help="diff_study.py --scale of that run")
    ap.add_argument("--seed", type=int, default=1, help="diff_study.py --seed of that run")


def write_tsv(path, rows, cols):
    """One row per dict: floats with 4 decimals (depth as it is), "-" where a row lacks a
    column."""
    with open(path, "w") as f:
        f.write("\t".join(cols) + "\n")
        for r in rows:
            f.write("\t".join(fmt(r.get(c, "-"), 4) if isinstance(r.get(c), float)
                              and c != "depth" else str(r.get(c, "-")) for c in cols) + "\n")


def pooled(sel, true="true_calls", false="false_calls", found="found", n_truth="n_truth",
           fdp="FDP"):
    """Rows of study.tsv pooled: calls, true, false, found, truth, precision, recall, F1 and the
    mean FDP over the rows (the column names of another scoring where given)."""
    calls = sum(r["n_calls"] for r in sel)
    t = sum(r[true] for r in sel)
    fl = sum(r[false] for r in sel)
    fo = sum(r[found] for r in sel)
    ntr = sum(r[n_truth] for r in sel)
    p, rc, f1, _ = prf(calls, t, fl, fo, ntr)
    fdr = sum(r[fdp] for r in sel) / len(sel) if sel else float("nan")
    return calls, t, fl, fo, ntr, p, rc, f1, fdr


def true_table_rows(sel, depths, contacts):
    """The markdown rows of a true-comparisons table (replicates, depth, contacts, comparisons,
    calls, true, false, found / truth, precision, recall, F1, FDR): one per cell of `sel`, then
    all of them pooled, then a blank line."""
    md = []
    for reps in (2, 3):
        for frac in depths:
            cell = [r for r in sel if r["replicates"] == reps and r["depth"] == frac]
            if not cell:
                continue
            calls, t, fl, found, ntr, p, rc, f1, fdr = pooled(cell)
            md.append(f"| {reps} | {frac:g} | {contacts[frac]:,.0f} | {len(cell)} | {calls} | "
                      f"{t} | {fl} | {found} / {ntr} | {fmt(p)} | {fmt(rc)} | **{fmt(f1)}** "
                      f"| {fmt(fdr)} |")
    calls, t, fl, found, ntr, p, rc, f1, fdr = pooled(sel)
    return md + [f"| all | | | {len(sel)} | {calls} | {t} | {fl} | {found} / {ntr} | {fmt(p)} | "
                 f"{fmt(rc)} | **{fmt(f1)}** | {fmt(fdr)} |", ""]


# ---------------------------------------------------------------- ensembles and comparisons

def ensemble_seeds(seed, sc):
    """A's ensemble seeds 10000 x seed + 1001.., B's + 2001.. (sc's n_a and n_b of them)."""
    base = 10000 * seed
    return ([base + 1001 + i for i in range(sc["n_a"])],
            [base + 2001 + i for i in range(sc["n_b"])])


def draw_comparisons(seeds_a, seeds_b, sc, seed):
    """(kind, replicates, depth, A seeds, B seeds) for 2 and 3 replicates at every depth.
    `true`: A's and B's ensembles in consecutive disjoint sets (sc's true_per at most); `null`:
    disjoint sets of A's ensembles drawn at random (sc's null_per, no split twice in a cell)."""
    if len(seeds_a) < 6:
        raise SystemExit("need at least 6 A ensembles for 3 + 3 null comparisons")
    comps = []
    crng = random.Random(seed * 7919 + 17)
    for reps in (2, 3):
        for frac in sc["depths"]:
            n_true = min(sc["true_per"], len(seeds_a) // reps, len(seeds_b) // reps)
            for c in range(n_true):
                comps.append(("true", reps, frac, seeds_a[c * reps:(c + 1) * reps],
                              seeds_b[c * reps:(c + 1) * reps]))
            seen = set()
            for c in range(sc["null_per"]):
                for _ in range(1000):
                    pick = crng.sample(seeds_a, 2 * reps)
                    a, b = sorted(pick[:reps]), sorted(pick[reps:])
                    key = tuple(sorted((tuple(a), tuple(b))))
                    if key not in seen:
                        break
                seen.add(key)
                comps.append(("null", reps, frac, a, b))
    return comps


def simulate_ensembles(seeds_a, seeds_b, simulate_one):
    """{seed: (condition, cool, truth)} and the seconds of the simulations run (cached ones
    not counted); simulate_one(condition, seed) -> (cool, truth, seconds)."""
    sims, t_sim = {}, []
    for cond, seeds in (("A", seeds_a), ("B", seeds_b)):
        for s in seeds:
            cool, truth, dt = simulate_one(cond, s)
            sims[s] = (cond, cool, truth)
            if dt:
                t_sim.append(dt)
    if t_sim:
        log(f"# {len(t_sim)} simulations, {sum(t_sim):.0f} s ({sum(t_sim) / len(t_sim):.1f} s each)")
    return sims, t_sim


def depth_maps(cm, out, sims, seeds, depths):
    """Every ensemble thinned to every depth and balanced: {(seed, depth): path}, the mean
    contacts per replicate at each depth, and the seconds spent."""
    maps, contacts, t_maps = {}, {}, 0.0
    for di, frac in enumerate(depths):
        sums = []
        for s in seeds:
            path, dt = depth_map(cm, out, sims[s][1], s, di, frac)
            t_maps += dt
            maps[(s, frac)] = path
            sums.append(contacts_sum(cm, path))
        contacts[frac] = sum(sums) / len(sums)
        log(f"# depth {frac:g}: {contacts[frac]:.0f} contacts per replicate on average")
    return maps, contacts, t_maps


# ---------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default="target/release/contactmap",
                    help="contactmap for simulate / sample / balance (and diff unless --diff-binary)")
    ap.add_argument("--diff-binary", help="contactmap for `diff loops` / `diff boundaries`")
    ap.add_argument("--out", default="/tmp/diff_study")
    ap.add_argument("--scale", choices=sorted(SCALES), default="small")
    ap.add_argument("--seed", type=int, default=1, help="design, seeds and null splits")
    ap.add_argument("--device", default="cpu", choices=["cpu", "auto", "gpu"],
                    help="simulate polymer --device (cached ensembles record it)")
    ap.add_argument("--window", type=int, default=100000,
                    help="diff boundaries --window (bp); 100 kb = 20 bins, about half a loop "
                         "domain of the design (20-40 beads): docs/diff.md compares 25-200 kb")
    ap.add_argument("--tolerance", type=int, default=2, help="bins for matching calls to truth")
    ap.add_argument("--alpha", type=float, default=0.05)
    ap.add_argument("--match-bins", type=int,
                    help="diff boundaries --match-bins (default: the command's, 2)")
    ap.add_argument("--no-called", action="store_true",
                    help="skip `diff loops` without --loops (dots called by diff loops)")
    args = ap.parse_args()
    cm = os.path.abspath(args.binary)
    cmd_diff = os.path.abspath(args.diff_binary) if args.diff_binary else cm
    sc = SCALES[args.scale]
    out = os.path.abspath(args.out)
    for d in ("sims", "maps", "diff"):
        os.makedirs(os.path.join(out, d), exist_ok=True)
    global LOG
    LOG = open(os.path.join(out, "commands.log"), "a")
    log(f"# diff_study.py --scale {args.scale} --seed {args.seed} ({time.strftime('%Y-%m-%d %H:%M:%S')})")
    t_start = time.time()

    rng = random.Random(args.seed)
    loops, removed = design(sc["chain"], rng)
    ctcf_a = ctcf_list(loops)
    ctcf_b = ctcf_list(loops, removed)
    junctions = [(loops[j][1], loops[j + 1][0]) for j in removed]
    log(f"# design: {sc['chain']} beads, {len(loops)} loops, {len(loops) - 1} inner junctions, "
        f"removed in B: {junctions}")
    log(f"# A --ctcf {ctcf_a}")
    log(f"# B --ctcf {ctcf_b}")

    seeds_a, seeds_b = ensemble_seeds(args.seed, sc)
    comps = draw_comparisons(seeds_a, seeds_b, sc, args.seed)
    ctcf = dict(A=ctcf_a, B=ctcf_b)
    sims, t_sim = simulate_ensembles(
        seeds_a, seeds_b, lambda cond, s: simulate(cm, out, ctcf[cond], s, sc, args.device))
    fa = read_truth_loops([sims[s][2] for s in seeds_a])
    fb = read_truth_loops([sims[s][2] for s in seeds_b])
    truth = loop_truth(fa, fb)
    union = sorted(k for k in truth if max(truth[k][2], truth[k][3]) >= 0.02)
    union_path = os.path.join(out, "union.loops.bedpe")
    text = "chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tclass\tfraction_A\tfraction_B\n"
    for k in union:
        cls, _, a, b = truth[k]
        text += (f"{k[0]}\t{k[1] * BEAD_BP}\t{(k[1] + 1) * BEAD_BP}\t{k[0]}\t{k[2] * BEAD_BP}"
                 f"\t{(k[2] + 1) * BEAD_BP}\t{cls}\t{a:.4f}\t{b:.4f}\n")
    old_text = None
    if os.path.exists(union_path):
        with open(union_path) as f:
            old_text = f.read()
    if text != old_text:  # rewritten only when it changes: its mtime keys the loops diffs' cache
        with open(union_path, "w") as f:
            f.write(text)
    n_changed_union = sum(1 for k in union if truth[k][0] == "changed")
    n_changed_all = sum(1 for v in truth.values() if v[0] == "changed")
    log(f"# truth: {len(union)} loops tested (f_max >= 0.02), {n_changed_union} changed "
        f"({n_changed_all} changed among all {len(truth)} truth pairs), "
        f"{sum(1 for k in union if truth[k][0] == 'ambiguous')} ambiguous")

    # second scoring of loops_called: each full-depth ensemble's contact frequencies, and the
    # truth's pseudo-count 0.005 (in loop fraction) in neighbourhood-frequency units
    freqs, pseudo, k_freq = {}, float("nan"), float("nan")
    if not args.no_called:
        for s in seeds_a + seeds_b:
            freqs[s] = read_frequencies(cm, sims[s][1])
        num = den = 0.0
        for key, (_, _, a, b) in truth.items():
            for f, seeds in ((a, seeds_a), (b, seeds_b)):
                if f >= 0.1:
                    num += condition_frequency(freqs, seeds, *key)
                    den += f
        k_freq = num / den
        pseudo = 0.005 * k_freq
        log(f"# contact frequencies: a 3x3 neighbourhood holds {k_freq:.3g} of an ensemble's "
            f"contacts per unit of loop fraction; pseudo-count {pseudo:.3g}")

    maps, contacts, t_maps = depth_maps(cm, out, sims, seeds_a + seeds_b, sc["depths"])

    rows, t_diff, freq_records = [], 0.0, []
    kinds = ["loops", "boundaries"] + ([] if args.no_called else ["loops_called"])
    removed_bins = junctions
    for ci, (ctype, reps, frac, a, b) in enumerate(comps):
        name = comparison_name(ctype, reps, frac, a, b)
        amaps = [maps[(s, frac)] for s in a]
        bmaps = [maps[(s, frac)] for s in b]
        mt = [os.path.getmtime(p) for p in amaps + bmaps]
        for kind in kinds:
            prefix = os.path.join(out, "diff", f"{name}.{kind}")
            if kind == "boundaries":
                result = prefix + ".boundaries.tsv"
                cmd = [cmd_diff, "diff", "boundaries", "--a", *amaps, "--b", *bmaps,
                       "--window", args.window, "--alpha", args.alpha, "-o", prefix]
                if args.match_bins is not None:
                    cmd += ["--match-bins", args.match_bins]
            else:
                result = prefix + ".loops.bedpe"
                cmd = [cmd_diff, "diff", "loops", "--a", *amaps, "--b", *bmaps,
                       "--alpha", args.alpha, "-o", prefix]
                if kind == "loops":
                    cmd += ["--loops", union_path]
            params = dict(cmd=[str(c) for c in cmd[1:]], mtimes=mt,
                          union=os.path.getmtime(union_path) if kind == "loops" else 0,
                          binary_mtime=os.path.getmtime(cmd_diff))
            if not cached(result, params):
                done = run(["nice", "-n", "19", *cmd], may_fail=kind == "loops_called")
                if done is None:
                    # too sparse for dots to score any pixel: no loop called, none tested
                    with open(result, "w") as f:
                        f.write("chrom1\tstart1\tend1\tchrom2\tstart2\tend2\tbaseMean\t"
                                "log2FoldChange\tlfc_low\tlfc_high\tlfcSE\tpvalue\tqvalue\t"
                                "mean_A\tmean_B\tdirection\n")
                else:
                    t_diff += done[2]
                mark(result, params)
            table = read_table(result)
            if kind == "boundaries":
                sc_ = score_boundaries(table, removed_bins, args.tolerance)
            else:
                sc_ = score_loops(table, truth, args.tolerance, kind == "loops_called")
            n_calls, n_t, n_f, n_x, found, n_truth = sc_
            if ctype == "null":  # no truth difference: every call is false
                n_f, n_t, n_x, found, n_truth = n_calls, 0, 0, 0, 0
            p, r, f1, fdp = prf(n_calls, n_t, n_f, found, n_truth)
            rows.append(dict(kind=kind, comparison=ctype, replicates=reps, depth=frac,
                             contacts=round(contacts[frac]), a=",".join(map(str, a)),
                             b=",".join(map(str, b)), n_tested=len(table), n_calls=n_calls,
                             true_calls=n_t, false_calls=n_f, excluded_calls=n_x,
                             n_truth=n_truth, found=found, precision=p, recall=r, F1=f1,
                             FDP=fdp))
            if kind == "loops_called":  # the second scoring (contact change)
                row = rows[-1]
                if ctype == "null":  # A against A': no true change, every call stays false
                    row.update(freq_false_calls=n_calls, freq_change_calls=0,
                               freq_ambiguous_calls=0, freq_moved_change=0,
                               freq_moved_ambiguous=0, freq_precision=p, freq_F1=f1,
                               freq_FDP=fdp, freq_held_out="-")
                    continue
                held_a = [s for s in seeds_a if s not in a]
                held_b = [s for s in seeds_b if s not in b]
                held = "yes" if held_a and held_b else "no"
                counts, recs = score_loops_change(table, truth, args.tolerance, freqs,
                                                  held_a or seeds_a, held_b or seeds_b, pseudo)
                c_calls, c_t, c_f, c_x, c_chg, c_amb, c_found, c_truth = counts
                assert (c_calls, c_t, c_found, c_truth) == (n_calls, n_t, found, n_truth)
                assert c_f + c_chg + c_amb == n_f and c_x == n_x
                cp, _, cf1, cfdp = prf(c_calls, c_t, c_f, c_found, c_truth)
                row.update(freq_false_calls=c_f, freq_change_calls=c_chg,
                           freq_ambiguous_calls=c_amb, freq_moved_change=c_chg,
                           freq_moved_ambiguous=c_amb, freq_precision=cp, freq_F1=cf1,
                           freq_FDP=cfdp, freq_held_out=held)
                for rec in recs:
                    freq_records.append(dict(comparison=name, replicates=reps, depth=frac,
                                             held_out=held, **rec))

    cols = ["kind", "comparison", "replicates", "depth", "contacts", "a", "b", "n_tested",
            "n_calls", "true_calls", "false_calls", "excluded_calls", "n_truth", "found",
            "precision", "recall", "F1", "FDP"]
    # the second scoring's columns, after study.tsv's own (readers look columns up by name);
    # "-" on rows of the other kinds
    freq_cols = ["freq_false_calls", "freq_change_calls", "freq_ambiguous_calls",
                 "freq_precision", "freq_F1", "freq_FDP", "freq_held_out"] if freqs else []
    write_tsv(os.path.join(out, "study.tsv"), rows, cols + freq_cols)
    if freqs:
        rcols = ["comparison", "replicates", "depth", "held_out", "chrom", "bin1", "bin2",
                 "direction", "F_A", "F_B", "fold", "cls"]
        with open(os.path.join(out, "loops_called_freq.tsv"), "w") as f:
            f.write("\t".join(rcols) + "\n")
            for rec in freq_records:
                f.write("\t".join(f"{rec[c]:.4g}" if c in ("F_A", "F_B", "fold")
                                  else str(rec[c]) for c in rcols) + "\n")

    # summary
    elapsed = time.time() - t_start
    md = [f"# Differential known-truth study (`scripts/diff_study.py --scale {args.scale} "
          f"--seed {args.seed}`)", "",
          f"Generated {time.strftime('%Y-%m-%d %H:%M')}; binaries `{args.binary}` "
          f"(simulate, sample, balance) and `{args.diff_binary or args.binary}` (diff). "
          f"Wall time of this run {elapsed:.0f} s (simulations {sum(t_sim):.0f} s, "
          f"thinning + balancing {t_maps:.0f} s, diffs {t_diff:.0f} s; cached steps count 0).",
          "",
          "## Design", "",
          f"- Chain of {sc['chain']} beads of 5 kb (one bead per bin), {len(loops)} convergent "
          f"loops of 20-40 beads, junctions of 4 beads; extrusion with capture 1, release 0, "
          f"processivity 300, separation 30; {sc['replicas']} replicas x {sc['samples']} samples "
          f"per ensemble ({sc['equilibration']} steps of equilibration, one sample every "
          f"{sc['sample_every']}).",
          f"- B: junctions at beads {', '.join(f'{u}-/{v}+' for u, v in junctions)} removed "
          f"(lost boundaries: {len(junctions)}).",
          f"- Ensembles: {len(seeds_a)} of A (seeds {seeds_a[0]}..{seeds_a[-1]}), {len(seeds_b)} "
          f"of B (seeds {seeds_b[0]}..{seeds_b[-1]}). Depths (fractions kept by `sample`): "
          + ", ".join(f"{d:g} (~{contacts[d]:,.0f} contacts per replicate)" for d in sc["depths"])
          + ".",
          f"- Loop truth: {len(union)} loops tested (`--loops`, union of A's and B's pairs held "
          f"in >= 2% of samples), of which {n_changed_union} changed (f_max >= 0.1 and >= 2-fold), "
          f"{sum(1 for k in union if truth[k][0] == 'ambiguous')} ambiguous (left out), the rest "
          f"unchanged (< 1.5-fold).",
          f"- Calls at q < {args.alpha}; boundary and `loops_called` calls matched within "
          f"{args.tolerance} bins; `diff boundaries --window {args.window}`.",
          "- Null comparisons draw disjoint A sets from the same ensembles, and every depth thins "
          "the same ensembles: they share replicates, so they are not independent trials.", ""]

    md += ["## Comparisons with true differences (A against B)", "",
           "Pooled over the comparisons of each cell: precision = true / (true + false) calls, "
           "recall = truth differences found / truth differences, F1 of the two; FDR = mean over "
           "comparisons of false / scored calls.", ""]
    for kind in kinds:
        md += [f"### {kind}", "",
               "| replicates | depth | contacts / replicate | comparisons | calls | true | false "
               "| found / truth | precision | recall | F1 | observed FDR |",
               "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        md += true_table_rows([r for r in rows if r["kind"] == kind and r["comparison"] == "true"],
                              sc["depths"], contacts)

    if freqs:
        sel_all = [r for r in rows if r["kind"] == "loops_called"]
        sel_true = [r for r in sel_all if r["comparison"] == "true"]
        moved_c = sum(r["freq_moved_change"] for r in sel_true)
        moved_a = sum(r["freq_moved_ambiguous"] for r in sel_true)
        stay = sum(r["freq_false_calls"] for r in sel_true)
        not_held = sum(1 for r in sel_true if r["freq_held_out"] != "yes")
        md += ["### loops_called, second scoring: calls near no truth pair judged by the true "
               "contact change", "",
               "The strict table above counts a call near no truth pair (no pair with both "
               f"anchors within {args.tolerance} bins) as false. Here such a call is judged by "
               "the change of contact frequency at its pixel: each full-depth ensemble's "
               "contacts divided by its total, summed over the call's 3x3 neighbourhood, "
               "averaged over the condition's held-out ensembles (A's other than the "
               "comparison's A replicates, B's other than its B replicates"
               + (f"; {not_held} comparisons had none left for a condition and used all of "
                  "its ensembles" if not_held else "; every comparison had some left")
               + f"). Fold g = (F_B + p) / (F_A + p) in the call's direction, p = 0.005 x "
               f"{k_freq:.3g} = {pseudo:.3g} (the truth's pseudo-count 0.005 in loop "
               f"fraction, times the neighbourhood frequency per unit of loop fraction over the "
               f"truth pairs held in >= 10% of samples): g >= 2 a real contact change, not a "
               f"loop (left out); g < 1.5 or the other way false; in between ambiguous (left "
               f"out). Calls on truth pairs are scored as above; recall is unchanged; calls of "
               f"null comparisons stay false. Of the {sum(r['false_calls'] for r in sel_true)} "
               f"strict false calls of the true comparisons, {moved_c} move to real change, "
               f"{moved_a} to ambiguous, {stay} stay false. Per call: `loops_called_freq.tsv`.",
               "",
               "| replicates | depth | contacts / replicate | comparisons | calls | true | false "
               "| real change | ambiguous change | found / truth | precision | recall | F1 "
               "| observed FDR |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]

        def agg_freq(sel):
            calls, t, fl, found, ntr, p, rc, f1, fdr = pooled(sel, false="freq_false_calls",
                                                              fdp="freq_FDP")
            chg = sum(r["freq_change_calls"] for r in sel)
            amb = sum(r["freq_ambiguous_calls"] for r in sel)
            return (f"{calls} | {t} | {fl} | {chg} | {amb} | {found} / {ntr} | {fmt(p)} | "
                    f"{fmt(rc)} | **{fmt(f1)}** | {fmt(fdr)} |")
        for reps in (2, 3):
            for frac in sc["depths"]:
                sel = [r for r in sel_true if r["replicates"] == reps and r["depth"] == frac]
                if sel:
                    md.append(f"| {reps} | {frac:g} | {contacts[frac]:,.0f} | {len(sel)} | "
                              + agg_freq(sel))
        md.append(f"| all | | | {len(sel_true)} | " + agg_freq(sel_true))
        nn = sum(1 for r in sel_all if r["comparison"] == "null")
        calls = sum(r["n_calls"] - r["excluded_calls"] - r["freq_change_calls"]
                    - r["freq_ambiguous_calls"] for r in sel_all)
        fl = sum(r["freq_false_calls"] for r in sel_all)
        md += ["", f"Over all {len(sel_all)} comparisons ({nn} null + {len(sel_all) - nn} "
               f"true): mean FDP **{fmt(sum(r['freq_FDP'] for r in sel_all) / len(sel_all))}** "
               f"(strict: {fmt(sum(r['FDP'] for r in sel_all) / len(sel_all))}); pooled false / "
               f"scored calls {fl} / {calls} = {fmt(fl / calls if calls else float('nan'))}.",
               ""]

    md += ["## Null comparisons (A against A' with other seeds)", "",
           "Every call is false; the observed FDR (mean false-discovery proportion) is the "
           "fraction of comparisons with any call, given with its Clopper-Pearson 95% interval "
           "(which treats the comparisons as independent: they are not, see above).", "",
           "| kind | replicates | comparisons | with a call | calls | tested per comparison "
           "| observed FDR | 95% interval |", "|---|---|---|---|---|---|---|---|"]
    for kind in kinds:
        for reps in (2, 3, "all"):
            sel = [r for r in rows if r["kind"] == kind and r["comparison"] == "null"
                   and (reps == "all" or r["replicates"] == reps)]
            if not sel:
                continue
            k = sum(1 for r in sel if r["n_calls"] > 0)
            lo, hi = clopper_pearson(k, len(sel))
            tested = sum(r["n_tested"] for r in sel) / len(sel)
            md.append(f"| {kind} | {reps} | {len(sel)} | {k} | {sum(r['n_calls'] for r in sel)} "
                      f"| {tested:.1f} | {'**' if reps == 'all' else ''}{k / len(sel):.3f}"
                      f"{'**' if reps == 'all' else ''} | [{lo:.3f}, {hi:.3f}] |")
    md += ["", "## Observed FDR over all comparisons", "",
           "| kind | comparisons (null + true) | calls | false calls | pooled false / calls "
           "| mean FDP |", "|---|---|---|---|---|---|"]
    for kind in kinds:
        sel = [r for r in rows if r["kind"] == kind]
        calls = sum(r["n_calls"] - r["excluded_calls"] for r in sel)
        fl = sum(r["false_calls"] for r in sel)
        nn = sum(1 for r in sel if r["comparison"] == "null")
        md.append(f"| {kind} | {len(sel)} ({nn} + {len(sel) - nn}) | {calls} | {fl} | "
                  f"{fmt(fl / calls if calls else float('nan'))} | "
                  f"{fmt(sum(r['FDP'] for r in sel) / len(sel))} |")
    md += ["", "One row per comparison: `study.tsv`; commands: `commands.log`.", ""]
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("\n".join(md))
    log(f"# wrote {os.path.join(out, 'study.tsv')} ({len(rows)} rows) and summary.md "
        f"in {elapsed:.0f} s")
    print("\n".join(md))


if __name__ == "__main__":
    main()
