#!/usr/bin/env python3
"""Known-truth study of `contactmap diff compartments` (issue 55): precision, recall and F1 of the
compartment switches called against the truth of simulated conditions, as curves against depth
for 2 and 3 replicates, and the observed false-discovery rate at q < 0.05 over null comparisons
(A against A with other seeds) and over comparisons with true differences. The companion of
scripts/diff_study.py (loops and boundaries), with the same conventions.

usage: scripts/diff_study_compartments.py [--binary target/release/contactmap]
                                          [--diff-binary BIN] [--out DIR] [--scale small|full]
                                          [--seed N] [--device cpu|auto|gpu] [--alpha Q]
                                          [--edge BINS]

Python 3 standard library only. Every command it runs is printed (and kept in DIR/commands.log).

Design
------
Condition A: one chain of 5 kb beads (one bead per bin) in a sphere (density 0.3), an A/B block
copolymer given as one explicit pattern covering the whole chain (`--types`, e.g.
A50B50A40B60A50B40A60B50 for 400 beads: eight blocks of 40-60 beads), beads of equal type
attracting each other (`--attraction`, 0.8 kT at --scale full: strong enough that one ensemble's
E1 has the sign of the truth on every bin, checked below).
Condition B: the same pattern with two blocks flipped, one A block turned B (A->B) and one B block
turned A (B->A), so that the two conditions keep the same share of A.

Replicates are biological: independent ensembles with their own --seed (A: seeds 1001.., B:
2001.., offset by 10000 x --seed). Depths: each replicate thinned with `contactmap sample
--fraction F` (its own sample seed), then `balance --store` (ICE, cooler's defaults; stored even
when unconverged, which the log says). Depth 1 is the simulation itself.

Truth
-----
Each condition's `--truth-compartments` (every bin's majority type; all ensembles of a condition
share it). A bin is switched A->B when its type is A in A and B in B (B->A the other way); the
other bins are unswitched. Bins within --edge bins of an edge of a flipped block (the bins e-edge
.. e+edge-1 around each position e where the switch status changes) are ambiguous: E1 is smooth
across a compartment edge, so a call there is left out of precision and such a bin is not asked
for by recall. The strict figures (no ambiguous bins) are in study.tsv (`*_strict`) and pooled
in summary.md.
A call is a bin with `switch` A->B or B->A in PREFIX.compartments.tsv (q < --alpha and the sign
of the mean E1 changed): true when the bin is switched in that direction, false when it is
unswitched or switched the other way. Precision = true / (true + false), recall = switched bins
found / switched bins, per bin.

Phasing: every comparison gets A's truth track as `--phasing-track TRUTH_A:5` (the fraction of
A beads of each bin), which only sets the sign of each replicate's E1 (A positive).

E1 check: every map of every ensemble at every depth goes through `contactmap compartments
--phasing-track` (its own condition's truth) and `contactmap score compartments` against its own
truth: sign accuracy and Pearson r of E1 with +-1, per ensemble at full depth and averaged per
depth.

Comparisons
-----------
`true`: A replicates against B replicates, the replicates of one comparison disjoint from those
of the others at the same depth and replicate number. `null`: A against A' -- disjoint sets of
A's ensembles drawn at random (--seed) from the nA ensembles; different null comparisons share
ensembles (and each depth reuses the same ensembles thinned), so they are not independent: the
number of distinct disjoint splits is what bounds their independence (summary.md gives it).
Every call of a null comparison is false. The observed FDR is the mean over comparisons of the
false-discovery proportion (false calls / scored calls, 0 without calls); for null comparisons
it is the fraction of comparisons with any call. The pooled false / calls is given too.

Outputs: DIR/study.tsv (one row per comparison), DIR/summary.md (tables), DIR/e1_check.tsv,
DIR/sims/, DIR/maps/, DIR/e1/, DIR/diff/ (caches: a rerun reuses every file whose parameters
match).
"""
import argparse
import importlib.util
import math
import os
import time

HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location("diff_study", os.path.join(HERE, "diff_study.py"))
ds = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ds)

# diff_study's helpers, shared as they are (run and log write to diff_study's LOG, set in main)
log, run, cached, mark = ds.log, ds.run, ds.cached, ds.mark
read_table = ds.read_table
prf, clopper_pearson, fmt = ds.prf, ds.clopper_pearson, ds.fmt

BEAD_BP = ds.BEAD_BP

SCALES = {
    # blocks of the A pattern (type, beads), blocks flipped in B, attraction (kT), density,
    # replicas per ensemble, samples per replica, A ensembles, B ensembles, depths,
    # null comparisons per (replicates, depth), true comparisons per (replicates, depth) at most
    "small": dict(blocks=[("A", 50), ("B", 50), ("A", 40), ("B", 60), ("A", 50), ("B", 40),
                          ("A", 60), ("B", 50)], flip=[2, 5], attraction=0.8, density=0.3,
                  replicas=4, samples=5, equilibration=20000, sample_every=2000,
                  n_a=6, n_b=2, depths=[0.1, 1.0], null_per=1, true_per=1),
    "full": dict(blocks=[("A", 50), ("B", 50), ("A", 40), ("B", 60), ("A", 50), ("B", 40),
                         ("A", 60), ("B", 50)], flip=[2, 5], attraction=0.8, density=0.3,
                 replicas=8, samples=10, equilibration=20000, sample_every=2000,
                 n_a=6, n_b=4, depths=[0.01, 0.015, 0.02, 0.03, 0.1, 0.3, 1.0], null_per=3,
                 true_per=2),
}


# ---------------------------------------------------------------- design

def pattern(blocks, flip=()):
    """The --types string of the blocks, with the blocks of index in `flip` turned over."""
    out = []
    for i, (t, n) in enumerate(blocks):
        if i in flip:
            t = "B" if t == "A" else "A"
        out.append(f"{t}{n}")
    return "".join(out)


# ---------------------------------------------------------------- caching helpers

def simulate(cm, out, types, seed, sc, chain, device):
    cool = os.path.join(out, "sims", f"s{seed}.cool")
    truth = os.path.join(out, "sims", f"s{seed}.truth_compartments.bed")
    params = dict(types=types, seed=seed, device=device, chain=chain,
                  **{k: sc[k] for k in ("attraction", "density", "replicas", "samples",
                                        "equilibration", "sample_every")})
    if cached(cool, params) and os.path.exists(truth):
        return cool, truth, 0.0
    tmp = cool + ".tmp.cool"
    for p in (tmp, cool, cool + ".params.json"):
        if os.path.exists(p):
            os.remove(p)
    _, _, dt = run(["nice", "-n", "19", cm, "simulate", "polymer", "-o", tmp,
                    "--chains", chain, "--monomer-bp", BEAD_BP, "--density", sc["density"],
                    "--types", types, "--attraction", sc["attraction"],
                    "--replicas", sc["replicas"], "--equilibration", sc["equilibration"],
                    "--sample-every", sc["sample_every"], "--samples", sc["samples"],
                    "--seed", seed, "--device", device, "--truth-compartments", truth])
    os.replace(tmp, cool)
    mark(cool, params)
    return cool, truth, dt


def e1_check(cm, out, cool, truth):
    """Sign accuracy and Pearson r of one map's E1 (phased by its own truth) against the truth;
    (nan, nan) when compartments fails (a map too sparse)."""
    prefix = os.path.join(out, "e1", os.path.basename(cool)[:-len(".cool")])
    result = prefix + ".score.tsv"
    params = dict(cool_mtime=os.path.getmtime(cool), truth=truth,
                  truth_mtime=os.path.getmtime(truth))
    if not cached(result, params):
        done = run(["nice", "-n", "19", cm, "compartments", cool, "--phasing-track",
                    f"{truth}:5", "-o", prefix], may_fail=True)
        if done is None:
            with open(result, "w") as f:
                f.write("chrom\tn_bins\tsign_accuracy\tsign_accuracy_up_to_sign\tpearson\n"
                        "all\t0\tnan\tnan\tnan\n")
        else:
            run(["nice", "-n", "19", cm, "score", "compartments", "--truth", truth,
                 prefix + ".cis.vecs.tsv", "-o", result])
        mark(result, params)
    for r in read_table(result):
        if r["chrom"] == "all":
            return float(r["sign_accuracy"]), float(r["pearson"]), int(r["n_bins"])
    return float("nan"), float("nan"), 0


# ---------------------------------------------------------------- truth

def read_truth(path):
    """[(chrom, start, end, type, fraction_A)] in file order."""
    rows = []
    with open(path) as f:
        for line in f:
            c = line.rstrip("\n").split("\t")
            if len(c) < 5 or c[0].startswith(("#", "track", "chrom")):
                continue
            rows.append((c[0], int(c[1]), int(c[2]), c[3], float(c[4])))
    return rows


def switch_truth(ta, tb, edge):
    """(chrom, start) -> (switch or None, ambiguous) from the two conditions' truths."""
    assert [r[:3] for r in ta] == [r[:3] for r in tb], "the conditions' bins differ"
    status = []
    for a, b in zip(ta, tb):
        s = None
        if a[3] == "A" and b[3] == "B":
            s = "A->B"
        elif a[3] == "B" and b[3] == "A":
            s = "B->A"
        status.append(s)
    amb = [False] * len(status)
    for i in range(1, len(status)):
        if ta[i][0] == ta[i - 1][0] and status[i] != status[i - 1]:
            for j in range(i - edge, i + edge):
                if 0 <= j < len(status) and ta[j][0] == ta[i][0]:
                    amb[j] = True
    return {(r[0], r[1]): (s, m) for r, s, m in zip(ta, status, amb)}


# ---------------------------------------------------------------- scoring

def score_switches(rows, truth, use_ambiguous):
    """Calls against the switch truth: (calls, true, false, excluded, found, truth switches).
    With use_ambiguous, calls on ambiguous bins are left out and ambiguous switched bins are not
    asked for; without it, every bin counts (the strict figures)."""
    n_calls = n_true = n_false = n_excl = 0
    found = set()
    for r in rows:
        call = r["switch"]
        if call not in ("A->B", "B->A"):
            continue
        n_calls += 1
        s, amb = truth.get((r["chrom"], int(r["start"])), (None, False))
        if use_ambiguous and amb:
            n_excl += 1
        elif s == call:
            n_true += 1
            found.add((r["chrom"], int(r["start"])))
        else:
            n_false += 1
    n_truth = sum(1 for s, amb in truth.values() if s and not (use_ambiguous and amb))
    return n_calls, n_true, n_false, n_excl, len(found), n_truth


# ---------------------------------------------------------------- statistics

def distinct_splits(n, reps):
    """Unordered pairs of disjoint sets of `reps` ensembles drawn from n."""
    return math.comb(n, reps) * math.comb(n - reps, reps) // 2


# ---------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default="target/release/contactmap",
                    help="contactmap for simulate / sample / balance / compartments (and diff "
                         "unless --diff-binary)")
    ap.add_argument("--diff-binary", help="contactmap for `diff compartments`")
    ap.add_argument("--out", default="/tmp/diff_study_compartments")
    ap.add_argument("--scale", choices=sorted(SCALES), default="small")
    ap.add_argument("--seed", type=int, default=1, help="seeds and null splits")
    ap.add_argument("--device", default="cpu", choices=["cpu", "auto", "gpu"],
                    help="simulate polymer --device (cached ensembles record it)")
    ap.add_argument("--alpha", type=float, default=0.05)
    ap.add_argument("--edge", type=int, default=2,
                    help="bins on each side of a flipped block's edge counted ambiguous")
    args = ap.parse_args()
    cm = os.path.abspath(args.binary)
    cmd_diff = os.path.abspath(args.diff_binary) if args.diff_binary else cm
    sc = SCALES[args.scale]
    out = os.path.abspath(args.out)
    for d in ("sims", "maps", "e1", "diff"):
        os.makedirs(os.path.join(out, d), exist_ok=True)
    ds.LOG = open(os.path.join(out, "commands.log"), "a")
    log(f"# diff_study_compartments.py --scale {args.scale} --seed {args.seed} "
        f"({time.strftime('%Y-%m-%d %H:%M:%S')})")
    t_start = time.time()

    chain = sum(n for _, n in sc["blocks"])
    types_a = pattern(sc["blocks"])
    types_b = pattern(sc["blocks"], sc["flip"])
    starts = [sum(n for _, n in sc["blocks"][:i]) for i in range(len(sc["blocks"]))]
    flipped = [(starts[i], starts[i] + sc["blocks"][i][1], sc["blocks"][i][0]) for i in sc["flip"]]
    log(f"# design: {chain} beads; A --types {types_a}; B --types {types_b}; flipped blocks "
        + ", ".join(f"beads {s}-{e} ({t}->{'B' if t == 'A' else 'A'})" for s, e, t in flipped))

    seeds_a, seeds_b = ds.ensemble_seeds(args.seed, sc)
    comps = ds.draw_comparisons(seeds_a, seeds_b, sc, args.seed)
    types = dict(A=types_a, B=types_b)
    sims, t_sim = ds.simulate_ensembles(
        seeds_a, seeds_b, lambda cond, s: simulate(cm, out, types[cond], s, sc, chain, args.device))
    truth_a_path, truth_b_path = sims[seeds_a[0]][2], sims[seeds_b[0]][2]
    ta, tb = read_truth(truth_a_path), read_truth(truth_b_path)
    for s in seeds_a + seeds_b:
        ref = ta if sims[s][0] == "A" else tb
        if [r[:4] for r in read_truth(sims[s][2])] != [r[:4] for r in ref]:
            raise SystemExit(f"ensemble {s}: its truth differs from its condition's first")
    truth = switch_truth(ta, tb, args.edge)
    truth_strict = switch_truth(ta, tb, 0)
    n_sw = sum(1 for s, _ in truth.values() if s)
    n_amb = sum(1 for _, m in truth.values() if m)
    n_sw_core = sum(1 for s, m in truth.values() if s and not m)
    log(f"# truth: {len(truth)} bins, {n_sw} switched "
        f"({sum(1 for s, _ in truth.values() if s == 'A->B')} A->B, "
        f"{sum(1 for s, _ in truth.values() if s == 'B->A')} B->A); {n_amb} ambiguous within "
        f"{args.edge} bins of a flipped edge, leaving {n_sw_core} switched bins to find")

    maps, contacts, t_maps = ds.depth_maps(cm, out, sims, seeds_a + seeds_b, sc["depths"])

    # E1 of each map against its own truth
    e1 = {}
    for s in seeds_a + seeds_b:
        for frac in sc["depths"]:
            e1[(s, frac)] = e1_check(cm, out, maps[(s, frac)], sims[s][2])
    with open(os.path.join(out, "e1_check.tsv"), "w") as f:
        f.write("seed\tcondition\tdepth\tcontacts\tn_bins\tsign_accuracy\tpearson\n")
        for s in seeds_a + seeds_b:
            for frac in sc["depths"]:
                acc, r, nb = e1[(s, frac)]
                f.write(f"{s}\t{sims[s][0]}\t{frac:g}\t{contacts[frac]:.0f}\t{nb}\t{fmt(acc, 4)}"
                        f"\t{fmt(r, 4)}\n")
    full = max(sc["depths"])
    for s in seeds_a + seeds_b:
        acc, r, _ = e1[(s, full)]
        log(f"# E1 check, ensemble {s} ({sims[s][0]}), depth {full:g}: sign accuracy "
            f"{fmt(acc)}, Pearson r {fmt(r)}")

    rows, t_diff, failed = [], 0.0, 0
    for ctype, reps, frac, a, b in comps:
        name = ds.comparison_name(ctype, reps, frac, a, b)
        amaps = [maps[(s, frac)] for s in a]
        bmaps = [maps[(s, frac)] for s in b]
        mt = [os.path.getmtime(p) for p in amaps + bmaps]
        prefix = os.path.join(out, "diff", name)
        result = prefix + ".compartments.tsv"
        cmd = [cmd_diff, "diff", "compartments", "--a", *amaps, "--b", *bmaps,
               "--phasing-track", f"{truth_a_path}:5", "--alpha", args.alpha, "-o", prefix]
        params = dict(cmd=[str(c) for c in cmd[1:]], mtimes=mt,
                      truth_mtime=os.path.getmtime(truth_a_path),
                      binary_mtime=os.path.getmtime(cmd_diff))
        ok = True
        if not cached(result, params):
            done = run(["nice", "-n", "19", *cmd], may_fail=True)
            if done is None:
                # a map too sparse for an eigenvector: nothing tested, nothing called
                ok = False
                with open(result, "w") as f:
                    f.write("chrom\tstart\tend\tE1_A\tE1_B\tdifference\tse\tt\tdf\tpvalue\t"
                            "qvalue\tswitch\n")
                with open(prefix + ".failed", "w") as f:
                    f.write("diff compartments failed\n")
            else:
                t_diff += done[2]
                if os.path.exists(prefix + ".failed"):
                    os.remove(prefix + ".failed")
            mark(result, params)
        if os.path.exists(prefix + ".failed"):
            ok = False
            failed += 1
        table = read_table(result)
        n_seg = 0
        if os.path.exists(prefix + ".switches.bed") and ok:
            with open(prefix + ".switches.bed") as f:
                n_seg = sum(1 for line in f if line.strip()) - 1
        n_calls, n_t, n_f, n_x, found, n_truth = score_switches(table, truth, True)
        _, n_ts, n_fs, _, found_s, n_truth_s = score_switches(table, truth_strict, False)
        if ctype == "null":  # no truth difference: every call is false
            n_f, n_t, n_x, found, n_truth = n_calls, 0, 0, 0, 0
            n_fs, n_ts, found_s, n_truth_s = n_calls, 0, 0, 0
        p, r, f1, fdp = prf(n_calls, n_t, n_f, found, n_truth)
        ps, rs, f1s, fdps = prf(n_calls, n_ts, n_fs, found_s, n_truth_s)
        n_ab = sum(1 for x in table if x["switch"] == "A->B")
        pv = [float(x["pvalue"]) for x in table if x.get("pvalue", "nan") not in ("nan", "NaN", "")]
        n_sig = sum(1 for x in table if x.get("qvalue", "nan") not in ("nan", "NaN", "")
                    and float(x["qvalue"]) < args.alpha)
        rows.append(dict(comparison=ctype, replicates=reps, depth=frac,
                         contacts=round(contacts[frac]), a=",".join(map(str, a)),
                         b=",".join(map(str, b)), ok=int(ok),
                         n_tested=sum(1 for x in table if x.get("qvalue", "nan") not in
                                      ("nan", "NaN", "")),
                         n_calls=n_calls, calls_AtoB=n_ab, calls_BtoA=n_calls - n_ab,
                         segments=n_seg, n_q=n_sig, p05=sum(1 for x in pv if x < 0.05),
                         true_calls=n_t, false_calls=n_f, excluded_calls=n_x,
                         n_truth=n_truth, found=found, precision=p, recall=r, F1=f1, FDP=fdp,
                         true_strict=n_ts, false_strict=n_fs, found_strict=found_s,
                         n_truth_strict=n_truth_s, F1_strict=f1s, FDP_strict=fdps))

    cols = ["comparison", "replicates", "depth", "contacts", "a", "b", "ok", "n_tested",
            "n_calls", "calls_AtoB", "calls_BtoA", "segments", "n_q", "p05", "true_calls", "false_calls",
            "excluded_calls", "n_truth", "found", "precision", "recall", "F1", "FDP",
            "true_strict", "false_strict", "found_strict", "n_truth_strict", "F1_strict",
            "FDP_strict"]
    ds.write_tsv(os.path.join(out, "study.tsv"), rows, cols)

    # summary
    elapsed = time.time() - t_start
    n_null = sum(1 for r in rows if r["comparison"] == "null")
    md = [f"# Differential compartments, known-truth study (`scripts/diff_study_compartments.py "
          f"--scale {args.scale} --seed {args.seed}`)", "",
          f"Generated {time.strftime('%Y-%m-%d %H:%M')}; binaries `{args.binary}` "
          f"(simulate, sample, balance, compartments) and `{args.diff_binary or args.binary}` "
          f"(diff). Wall time of this run {elapsed:.0f} s (simulations {sum(t_sim):.0f} s, "
          f"thinning + balancing {t_maps:.0f} s, diffs {t_diff:.0f} s; cached steps count 0).",
          "",
          "## Design", "",
          f"- One chain of {chain} beads of 5 kb (one bead per bin) in a sphere at density "
          f"{sc['density']}, attraction {sc['attraction']} kT between beads of equal type; "
          f"{sc['replicas']} replicas x {sc['samples']} samples per ensemble "
          f"({sc['equilibration']} steps of equilibration, one sample every "
          f"{sc['sample_every']}).",
          f"- A: `--types {types_a}`; B: `--types {types_b}` (flipped: "
          + ", ".join(f"beads {s}-{e} {t}->{'B' if t == 'A' else 'A'}" for s, e, t in flipped)
          + ").",
          f"- Truth: {n_sw} switched bins of {len(truth)}; {n_amb} bins within {args.edge} of a "
          f"flipped edge ambiguous (calls there left out, not asked for), {n_sw_core} switched "
          f"bins to find. Strict figures (every bin scored) in the last table.",
          f"- Ensembles: {len(seeds_a)} of A (seeds {seeds_a[0]}..{seeds_a[-1]}), {len(seeds_b)} "
          f"of B (seeds {seeds_b[0]}..{seeds_b[-1]}). Depths (fractions kept by `sample`): "
          + ", ".join(f"{d:g} (~{contacts[d]:,.0f} contacts per replicate)" for d in sc["depths"])
          + ".",
          f"- `diff compartments --phasing-track {os.path.basename(truth_a_path)}:5 --alpha "
          f"{args.alpha}` (A's fraction of A beads per bin) for every comparison.",
          f"- Null comparisons draw disjoint A sets from the same {len(seeds_a)} ensembles "
          f"({distinct_splits(len(seeds_a), 2)} distinct 2 + 2 splits, "
          f"{distinct_splits(len(seeds_a), 3)} distinct 3 + 3 splits), and every depth thins the "
          "same ensembles: they share replicates, so they are not independent trials.", ""]
    if failed:
        md += [f"- {failed} comparisons failed (`diff compartments` exited non-zero: counted as "
               "no call; `*.failed` in diff/).", ""]

    md += ["## E1 against the truth (one ensemble, `compartments` + `score compartments`)", "",
           "Each map's E1 phased by its own condition's truth, mean (min) over the ensembles.", "",
           "| depth | contacts / replicate | sign accuracy A | Pearson r A | sign accuracy B "
           "| Pearson r B |", "|---|---|---|---|---|---|"]
    for frac in sc["depths"]:
        cells = []
        for seeds in (seeds_a, seeds_b):
            accs = [e1[(s, frac)][0] for s in seeds]
            rs = [e1[(s, frac)][1] for s in seeds]
            fa = [x for x in accs if x == x]
            fr = [x for x in rs if x == x]
            cells.append(f"{fmt(sum(fa) / len(fa)) if fa else 'nan'} "
                         f"({fmt(min(fa)) if fa else 'nan'})")
            cells.append(f"{fmt(sum(fr) / len(fr)) if fr else 'nan'} "
                         f"({fmt(min(fr)) if fr else 'nan'})")
        md.append(f"| {frac:g} | {contacts[frac]:,.0f} | " + " | ".join(cells) + " |")
    md.append("")

    def agg(sel, strict=False):
        if strict:
            return ds.pooled(sel, true="true_strict", false="false_strict", found="found_strict",
                             n_truth="n_truth_strict", fdp="FDP_strict")
        return ds.pooled(sel)

    md += ["## F1 against depth (comparisons with true differences, pooled per cell)", "",
           "| replicates | " + " | ".join(f"{d:g} ({contacts[d]:,.0f})" for d in sc["depths"])
           + " |", "|---|" + "---|" * len(sc["depths"])]
    for reps in (2, 3):
        cells = []
        for frac in sc["depths"]:
            sel = [r for r in rows if r["comparison"] == "true" and r["replicates"] == reps
                   and r["depth"] == frac]
            cells.append(fmt(agg(sel)[7]) if sel else "")
        md.append(f"| {reps} | " + " | ".join(cells) + " |")
    md += ["", "## Comparisons with true differences (A against B)", "",
           "Pooled over the comparisons of each cell: precision = true / (true + false) calls "
           "(calls on ambiguous bins left out), recall = switched bins found / switched bins, F1 "
           "of the two; FDR = mean over comparisons of false / scored calls.", "",
           "| replicates | depth | contacts / replicate | comparisons | calls | true | false "
           "| ambiguous | found / truth | precision | recall | F1 | observed FDR |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for reps in (2, 3):
        for frac in sc["depths"]:
            sel = [r for r in rows if r["comparison"] == "true" and r["replicates"] == reps
                   and r["depth"] == frac]
            if not sel:
                continue
            calls, t, fl, found, ntr, p, rc, f1, fdr = agg(sel)
            nx = sum(r["excluded_calls"] for r in sel)
            md.append(f"| {reps} | {frac:g} | {contacts[frac]:,.0f} | {len(sel)} | {calls} | "
                      f"{t} | {fl} | {nx} | {found} / {ntr} | {fmt(p)} | {fmt(rc)} | "
                      f"**{fmt(f1)}** | {fmt(fdr)} |")
    sel = [r for r in rows if r["comparison"] == "true"]
    calls, t, fl, found, ntr, p, rc, f1, fdr = agg(sel)
    nx = sum(r["excluded_calls"] for r in sel)
    md += [f"| all | | | {len(sel)} | {calls} | {t} | {fl} | {nx} | {found} / {ntr} | {fmt(p)} "
           f"| {fmt(rc)} | **{fmt(f1)}** | {fmt(fdr)} |", ""]
    calls, t, fl, found, ntr, p, rc, f1, fdr = agg(sel, strict=True)
    md += [f"Strict (no ambiguous bins, every switched bin asked for): {t} true, {fl} false, "
           f"{found} / {ntr} found; precision {fmt(p)}, recall {fmt(rc)}, F1 {fmt(f1)}, mean "
           f"FDP {fmt(fdr)}.", ""]

    md += ["## Null comparisons (A against A' with other seeds)", "",
           "Every call is false; the observed FDR (mean false-discovery proportion) is the "
           "fraction of comparisons with any call, given with its Clopper-Pearson 95% interval "
           "(which treats the comparisons as independent: they are not, see above). A call "
           "needs q < alpha and the sign of the mean E1 changed; `q < alpha` counts the bins "
           "under alpha whatever the signs, `p < 0.05` the share of tested bins (about 0.05 when "
           "the test is calibrated; neighbouring bins' E1 are correlated, so it is noisy).", "",
           "| replicates | depth | comparisons | with a call | calls | bins tested per comparison "
           "| q < alpha | p < 0.05 | observed FDR | 95% interval |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for reps in (2, 3, "all"):
        for frac in (sc["depths"] if reps != "all" else ["all"]):
            sel = [r for r in rows if r["comparison"] == "null"
                   and (reps == "all" or (r["replicates"] == reps and r["depth"] == frac))]
            if not sel:
                continue
            k = sum(1 for r in sel if r["n_calls"] > 0)
            lo, hi = clopper_pearson(k, len(sel))
            tested = sum(r["n_tested"] for r in sel) / len(sel)
            dlabel = f"{frac:g}" if frac != "all" else "all"
            nq = sum(r["n_q"] for r in sel)
            p05 = sum(r["p05"] for r in sel) / max(1, sum(r["n_tested"] for r in sel))
            md.append(f"| {reps} | {dlabel} | {len(sel)} | {k} | "
                      f"{sum(r['n_calls'] for r in sel)} | {tested:.1f} | {nq} | {p05:.3f} | "
                      f"{'**' if reps == 'all' else ''}{k / len(sel):.3f}"
                      f"{'**' if reps == 'all' else ''} | [{lo:.3f}, {hi:.3f}] |")
    sel = rows
    calls = sum(r["n_calls"] - r["excluded_calls"] for r in sel)
    fl = sum(r["false_calls"] for r in sel)
    md += ["", "## Observed FDR over all comparisons", "",
           "| comparisons (null + true) | scored calls | false calls | pooled false / calls "
           "| mean FDP | mean FDP, strict |", "|---|---|---|---|---|---|",
           f"| {len(sel)} ({n_null} + {len(sel) - n_null}) | {calls} | {fl} | "
           f"{fmt(fl / calls if calls else float('nan'))} | "
           f"**{fmt(sum(r['FDP'] for r in sel) / len(sel))}** | "
           f"{fmt(sum(r['FDP_strict'] for r in sel) / len(sel))} |",
           "", "One row per comparison: `study.tsv`; E1 per map: `e1_check.tsv`; commands: "
           "`commands.log`.", ""]
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("\n".join(md))
    log(f"# wrote {os.path.join(out, 'study.tsv')} ({len(rows)} rows) and summary.md "
        f"in {elapsed:.0f} s")
    print("\n".join(md))


if __name__ == "__main__":
    main()
