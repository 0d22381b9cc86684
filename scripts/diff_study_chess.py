#!/usr/bin/env python3
"""Peer run of the differential known-truth study (scripts/diff_study.py): CHESS (`contactmap diff
regions`, which computes chess sim 0.3.8 exactly) on every comparison of the study, scored at the
level of windows against the study's own truth, next to contactmap's own calls (`diff loops`
without --loops and `diff boundaries`, read from the study's outputs) scored on the same windows.

usage: scripts/diff_study_chess.py [--study DIR] [--scale full] [--seed 1]
                                   [--binary target/release/contactmap] [--out DIR/chess]
                                   [--window 250000] [--step 50000] [--z -1] [--sn 0.5]
                                   [--nice 19]

Python 3 standard library only. Needs a finished `scripts/diff_study.py --out DIR` (its maps,
simulations, diff outputs and study.tsv; run with the same --scale and --seed given here). Every
command it runs is printed (and kept in OUT/commands.log).

Per comparison (each distinct comparison of DIR/study.tsv: null and true, 2 and 3 replicates,
every depth):
- each condition's replicate maps (DIR/maps/sSEED.dDEPTH.cool) are summed with `BINARY merge` and
  the sum balanced with `BINARY balance --store --force --store-unconverged` (ICE, cooler's
  defaults): CHESS takes one map per condition. A merged map is made once per (seeds, depth) and
  shared by the comparisons that use it (OUT/maps/);
- `BINARY diff regions --a A.cool --b B.cool --window W --step S -o OUT/regions/NAME` (A, the
  reference; as `chess pairs` + `chess sim` with its defaults);
- a window is called by CHESS when z_ssim < --z and SN > --sn (defaults -1 and 0.5: the cut-offs
  of CHESS's documented example analysis, docs/example_analysis.rst of vaquerizaslab/chess,
  "regions with a signal-to-noise ratio > 0.5 and a z-normalised similarity score < -1"); a NaN
  window (too small or too empty) is not called;
- a window is called by contactmap when it holds a call of the study's `diff loops` without
  --loops (DIR/diff/NAME.loops_called.loops.bedpe, direction up or down: q < 0.05; both anchors
  inside the window) or of its `diff boundaries` (DIR/diff/NAME.boundaries.boundaries.tsv, any
  status but `-`: q < 0.05; the boundary bin inside the window). The same with `diff loops
  --loops` (DIR/diff/NAME.loops.loops.bedpe) is given as a second row.

Window truth (the study's truth, built as diff_study.main() builds it: the truth-loop fractions of
all A ensembles against all B ensembles, diff_study.loop_truth; the removed junctions of
diff_study.design). A window is the bins it overlaps, [start, end):
  different  it holds a changed loop (both anchors inside) or a removed junction (both of its
             elements inside);
  unchanged  it holds no anchor of a changed loop, no element of a removed junction and no
             ambiguous loop (both anchors inside; ambiguous loops: those of the study's tested
             union, held in >= 2% of samples, as union.loops.bedpe);
  ambiguous  the rest (left out of precision, not asked for by recall).
Per comparison: a called different window is a true call, a called unchanged window a false one,
a called ambiguous window is left out; recall = different windows called / different windows. In a
null comparison every called window is false (no truth difference). The observed FDR is the mean
over comparisons of the false-discovery proportion (false / scored calls, 0 without calls), which
for null comparisons is the fraction of comparisons with any call.

As a check that the truth is the study's, the study's loops_called and boundaries outputs are
rescored with diff_study's functions and must reproduce study.tsv's counts (the script stops
otherwise).

Outputs: OUT/chess.tsv (one row per comparison and method: study.tsv's columns with windows as
the unit), OUT/chess_summary.md, OUT/maps/ (merged maps), OUT/regions/ (diff regions outputs);
caches: a rerun reuses every file whose inputs and command are unchanged.
"""
import argparse
import importlib.util
import math
import os
import random
import time

HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location("diff_study", os.path.join(HERE, "diff_study.py"))
ds = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ds)

BEAD_BP = ds.BEAD_BP
log, run = ds.log, ds.run





def merged_map(cm, nice, out, seeds, depth, study):
    """One condition's replicates summed and balanced (cached per seeds and depth)."""
    maps = [os.path.join(study, "maps", f"s{s}.d{depth:g}.cool") for s in seeds]
    dst = os.path.join(out, "maps", f"{'-'.join(seeds)}.d{depth:g}.cool")
    params = dict(maps=maps, mtimes=[os.path.getmtime(p) for p in maps],
                  binary_mtime=os.path.getmtime(cm))
    conv_path = dst + ".converged"
    if ds.cached(dst, params) and os.path.exists(conv_path):
        with open(conv_path) as f:
            return dst, f.read().strip() == "true", 0.0
    t0 = time.time()
    tmp = dst + ".tmp.cool"
    for p in (tmp, dst, dst + ".params.json", conv_path):
        if os.path.exists(p):
            os.remove(p)
    run([*nice, cm, "merge", *maps, "-o", tmp])
    _, err, _ = run([*nice, cm, "balance", tmp, "--store", "--force", "--store-unconverged"])
    converged = "converged=false" not in err
    if not converged:
        log(f"  note: ICE did not converge on {dst} (weights stored anyway)")
    os.replace(tmp, dst)
    ds.mark(dst, params)
    with open(conv_path, "w") as f:
        f.write("true\n" if converged else "false\n")
    return dst, converged, time.time() - t0


def regions(cm, nice, out, name, amap, bmap, window, step):
    prefix = os.path.join(out, "regions", name)
    result = prefix + ".regions.tsv"
    cmd = [cm, "diff", "regions", "--a", amap, "--b", bmap, "--window", window, "--step", step,
           "-o", prefix]
    params = dict(cmd=[str(c) for c in cmd[1:]],
                  mtimes=[os.path.getmtime(amap), os.path.getmtime(bmap)],
                  binary_mtime=os.path.getmtime(cm))
    dt = 0.0
    if not ds.cached(result, params):
        _, _, dt = run([*nice, *cmd])
        ds.mark(result, params)
    return ds.read_table(result), dt


def ffloat(x):
    try:
        return float(x)
    except ValueError:
        return float("nan")


def window_truth(windows, truth, union, junctions):
    """windows: list of (chrom, first bin, end bin). -> list of 'different' / 'unchanged' /
    'ambiguous'."""
    changed = [k for k, v in truth.items() if v[0] == "changed"]
    ambiguous = [k for k in union if truth[k][0] == "ambiguous"]
    out = []
    for chrom, s, e in windows:
        inside = lambda i: s <= i < e  # noqa: E731
        holds = lambda k: k[0] == chrom and inside(k[1]) and inside(k[2])  # noqa: E731
        if any(holds(k) for k in changed) or any(inside(u) and inside(v) for u, v in junctions):
            out.append("different")
        elif (any(k[0] == chrom and (inside(k[1]) or inside(k[2])) for k in changed)
              or any(inside(u) or inside(v) for u, v in junctions)
              or any(holds(k) for k in ambiguous)):
            out.append("ambiguous")
        else:
            out.append("unchanged")
    return out


def contactmap_called(windows, loop_rows, boundary_rows):
    """Windows holding a loop call (both anchors) or a boundary call (its bin)."""
    loops, bounds = [], []
    for r in loop_rows:
        if r["direction"] in ("up", "down"):
            i = (int(r["start1"]) + int(r["end1"])) // 2 // BEAD_BP
            j = (int(r["start2"]) + int(r["end2"])) // 2 // BEAD_BP
            loops.append((r["chrom1"], i, j))
    for r in boundary_rows:
        if r["status"] not in ("-", ""):
            bounds.append((r["chrom"], int(r["start"]) // BEAD_BP))
    called = []
    for chrom, s, e in windows:
        called.append(any(c == chrom and s <= i < e and s <= j < e for c, i, j in loops)
                      or any(c == chrom and s <= b < e for c, b in bounds))
    return called


def score_windows(called, classes, ctype):
    """(n_calls, true, false, excluded, found, n_truth) over windows."""
    n_calls = sum(called)
    n_t = sum(1 for c, k in zip(called, classes) if c and k == "different")
    n_f = sum(1 for c, k in zip(called, classes) if c and k == "unchanged")
    n_x = n_calls - n_t - n_f
    n_truth = sum(1 for k in classes if k == "different")
    if ctype == "null":
        return n_calls, 0, n_calls, 0, 0, 0
    return n_calls, n_t, n_f, n_x, n_t, n_truth


agg = ds.pooled


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ds.study_arguments(ap)
    ap.add_argument("--binary", default=os.path.join(os.path.dirname(HERE),
                                                     "target/release/contactmap"),
                    help="contactmap for merge / balance / diff regions")
    ap.add_argument("--out", help="output directory (default STUDY/chess)")
    ap.add_argument("--window", type=int, default=250000, help="diff regions --window (bp)")
    ap.add_argument("--step", type=int, default=50000, help="diff regions --step (bp)")
    ap.add_argument("--z", type=float, default=-1.0, help="CHESS call: z_ssim below this")
    ap.add_argument("--sn", type=float, default=0.5, help="CHESS call: SN above this")
    ap.add_argument("--tolerance", type=int, default=2,
                    help="diff_study's --tolerance (only for the check against study.tsv)")
    ap.add_argument("--nice", type=int, default=19, help="niceness of every command run")
    args = ap.parse_args()
    study = os.path.abspath(args.study)
    out = os.path.abspath(args.out or os.path.join(study, "chess"))
    cm = os.path.abspath(args.binary)
    nice = ["nice", "-n", str(args.nice)]
    for d in ("maps", "regions"):
        os.makedirs(os.path.join(out, d), exist_ok=True)
    ds.LOG = open(os.path.join(out, "commands.log"), "a")
    log(f"# diff_study_chess.py --study {study} --scale {args.scale} --seed {args.seed} "
        f"--window {args.window} --step {args.step} --z {args.z:g} --sn {args.sn:g} "
        f"({time.strftime('%Y-%m-%d %H:%M:%S')})")
    t_start = time.time()

    # truth, exactly as diff_study.main() builds it
    sc = ds.SCALES[args.scale]
    loops, removed = ds.design(sc["chain"], random.Random(args.seed))
    junctions = [(loops[j][1], loops[j + 1][0]) for j in removed]
    base = 10000 * args.seed
    seeds_a = [base + 1001 + i for i in range(sc["n_a"])]
    seeds_b = [base + 2001 + i for i in range(sc["n_b"])]
    tpath = lambda s: os.path.join(study, "sims", f"s{s}.truth_loops.bedpe")  # noqa: E731
    fa = ds.read_truth_loops([tpath(s) for s in seeds_a])
    fb = ds.read_truth_loops([tpath(s) for s in seeds_b])
    truth = ds.loop_truth(fa, fb)
    union = sorted(k for k in truth if max(truth[k][2], truth[k][3]) >= 0.02)
    n_changed = sum(1 for v in truth.values() if v[0] == "changed")
    n_amb = sum(1 for k in union if truth[k][0] == "ambiguous")
    log(f"# truth: {len(truth)} pairs, {n_changed} changed, {n_amb} ambiguous in the tested union; "
        f"removed junctions {junctions}")

    srows = ds.study_rows(os.path.join(study, "study.tsv"))
    # the study's own outputs rescored here must give study.tsv's numbers
    n_checked = 0
    for r in srows:
        if r["kind"] not in ("loops_called", "boundaries"):
            continue
        if r["kind"] == "boundaries":
            path = os.path.join(study, "diff", ds.study_row_name(r) + ".boundaries.boundaries.tsv")
            got = ds.score_boundaries(ds.read_table(path), junctions, args.tolerance)
        else:
            path = os.path.join(study, "diff", ds.study_row_name(r) + ".loops_called.loops.bedpe")
            got = ds.score_loops(ds.read_table(path), truth, args.tolerance, True)
        n_calls, n_t, n_f, n_x, found, n_truth = got
        if r["comparison"] == "null":
            n_f, n_t, n_x, found, n_truth = n_calls, 0, 0, 0, 0
        want = (r["n_calls"], r["true_calls"], r["false_calls"], r["excluded_calls"], r["found"],
                r["n_truth"])
        if (n_calls, n_t, n_f, n_x, found, n_truth) != want:
            raise SystemExit(f"truth differs from the study's: {ds.study_row_name(r)} {r['kind']} "
                             f"rescored {got}, study.tsv {want}")
        n_checked += 1
    log(f"# truth check: the study's {n_checked} loops_called and boundaries outputs rescore to "
        f"study.tsv")

    comps, seen = [], set()
    for r in srows:
        key = (r["comparison"], r["replicates"], r["depth"], r["a"], r["b"])
        if key not in seen:
            seen.add(key)
            comps.append(r)

    methods = ["CHESS", "contactmap", "contactmap_given"]
    labels = {"CHESS": f"CHESS (z_ssim < {args.z:g} and SN > {args.sn:g})",
              "contactmap": "contactmap (diff loops called + diff boundaries)",
              "contactmap_given": "contactmap (diff loops --loops + diff boundaries)"}
    rows, t_maps, t_regions, unconverged, classes0 = [], 0.0, 0.0, [], None
    nan_windows = {}
    z_sn = []  # (comparison row, [(z, SN, class)]) for the threshold table
    for ci, r in enumerate(comps):
        name = ds.study_row_name(r)
        a, b = r["a"].split(","), r["b"].split(",")
        amap, conv_a, dt_a = merged_map(cm, nice, out, a, r["depth"], study)
        bmap, conv_b, dt_b = merged_map(cm, nice, out, b, r["depth"], study)
        t_maps += dt_a + dt_b
        for conv, seeds in ((conv_a, a), (conv_b, b)):
            tag = f"{'-'.join(seeds)}.d{r['depth']:g}"
            if not conv and tag not in unconverged:
                unconverged.append(tag)
        table, dt = regions(cm, nice, out, name, amap, bmap, args.window, args.step)
        t_regions += dt
        windows = [(w["chrom1"], int(w["start1"]) // BEAD_BP,
                    -(-int(w["end1"]) // BEAD_BP)) for w in table]
        classes = window_truth(windows, truth, union, junctions)
        if classes0 is None:
            classes0 = (windows, classes)
        elif windows != classes0[0]:
            raise SystemExit(f"{name}: windows differ from the first comparison's")
        z = [ffloat(w["z_ssim"]) for w in table]
        sn = [ffloat(w["SN"]) for w in table]
        nan_windows[name] = sum(1 for x in z if x != x)
        z_sn.append((r, list(zip(z, sn, classes))))
        called = {
            "CHESS": [zz == zz and s_ == s_ and zz < args.z and s_ > args.sn
                      for zz, s_ in zip(z, sn)],
        }
        brows = ds.read_table(os.path.join(study, "diff", name + ".boundaries.boundaries.tsv"))
        for m, kind in (("contactmap", "loops_called"), ("contactmap_given", "loops")):
            lrows = ds.read_table(os.path.join(study, "diff", f"{name}.{kind}.loops.bedpe"))
            called[m] = contactmap_called(windows, lrows, brows)
        parts = []
        for m in methods:
            n_calls, n_t, n_f, n_x, found, n_truth = score_windows(called[m], classes,
                                                                   r["comparison"])
            p, rc, f1, fdp = ds.prf(n_calls, n_t, n_f, found, n_truth)
            rows.append(dict(kind=m, comparison=r["comparison"], replicates=r["replicates"],
                             depth=r["depth"], contacts=r["contacts"], a=r["a"], b=r["b"],
                             n_tested=len(windows) - (nan_windows[name] if m == "CHESS" else 0),
                             n_calls=n_calls, true_calls=n_t, false_calls=n_f,
                             excluded_calls=n_x, n_truth=n_truth, found=found, precision=p,
                             recall=rc, F1=f1, FDP=fdp, name=name))
            parts.append(f"{m} {n_calls} ({n_t} true, {n_f} false)")
        log(f"  [{ci + 1}/{len(comps)}] {name}: " + "; ".join(parts))

    cols = ["kind", "comparison", "replicates", "depth", "contacts", "a", "b", "n_tested",
            "n_calls", "true_calls", "false_calls", "excluded_calls", "n_truth", "found",
            "precision", "recall", "F1", "FDP"]
    ds.write_tsv(os.path.join(out, "chess.tsv"), rows, cols)
    windows, classes = classes0
    with open(os.path.join(out, "windows.tsv"), "w") as f:
        f.write("chrom\tstart\tend\ttruth\n")
        for (chrom, s, e), k in zip(windows, classes):
            f.write(f"{chrom}\t{s * BEAD_BP}\t{e * BEAD_BP}\t{k}\n")

    # ------------------------------------------------------------ summary
    fmt = ds.fmt
    depths = sorted({r["depth"] for r in rows})
    contacts = {r["depth"]: r["contacts"] for r in rows}
    n_cls = {k: classes.count(k) for k in ("different", "unchanged", "ambiguous")}
    n_fit = sum(1 for k, v in truth.items() if v[0] == "changed"
                and any(c == k[0] and s <= k[1] and k[2] < e for c, s, e in windows))

    def kilo(x):
        return f"{x / 1000:.1f} k" if x < 10000 else f"{x / 1000:.0f} k"
    elapsed = time.time() - t_start
    md = [f"# CHESS on the differential known-truth study (`scripts/diff_study_chess.py --study "
          f"{args.study} --scale {args.scale} --seed {args.seed} --window {args.window} --step "
          f"{args.step} --z {args.z:g} --sn {args.sn:g}`)", "",
          f"Generated {time.strftime('%Y-%m-%d %H:%M')}; binary `{args.binary}`. Wall time of "
          f"this run {elapsed:.0f} s (merge + balance {t_maps:.0f} s, diff regions "
          f"{t_regions:.0f} s; cached steps count 0).", "",
          "## Design", "",
          f"- The study's {len(comps)} comparisons ({sum(1 for r in comps if r['comparison'] == 'null')}"
          f" null, {sum(1 for r in comps if r['comparison'] == 'true')} true). CHESS takes one "
          f"map per condition: each condition's replicates summed (`merge`) and balanced "
          f"(`balance --store`, ICE), then `diff regions --a A.cool --b B.cool --window "
          f"{args.window} --step {args.step}` (chess sim 0.3.8 with its defaults: SSIM window "
          f"the whole matrix, 20 bins at least, 10% empty rows at most).",
          f"- Windows: {len(windows)} of {args.window // BEAD_BP} bins every "
          f"{args.step // BEAD_BP} bins on the {sc['chain']}-bin chromosome; {n_fit} of the "
          f"{n_changed} changed loops lie whole in at least one window"
          + (" (the others, loops gained in B across a removed junction, are longer than a "
             "window: the windows around them are different through the junction)."
             if n_fit < n_changed else "."),
          f"- CHESS call: z_ssim < {args.z:g} and SN > {args.sn:g} (the cut-offs of CHESS's "
          f"documented example analysis: \"regions with a signal-to-noise ratio > 0.5 and a "
          f"z-normalised similarity score < -1\", docs/example_analysis.rst of "
          f"vaquerizaslab/chess). z_ssim is relative to the comparison's own windows, so it "
          f"ranks windows; SN is what must tell noise from change.",
          "- contactmap call: the window holds a call of the study's `diff loops` without "
          "`--loops` (both anchors inside) or of its `diff boundaries` (the boundary bin inside), "
          "q < 0.05. A second row uses `diff loops --loops` (the truth union given) instead.",
          f"- Window truth: **different** when the window holds a changed loop (both anchors) or "
          f"a removed junction (both elements): {n_cls['different']} windows; **unchanged** when "
          f"it holds no anchor of a changed loop, no element of a removed junction and no "
          f"ambiguous loop of the tested union (both anchors): {n_cls['unchanged']}; the other "
          f"{n_cls['ambiguous']} are ambiguous (calls there left out, not asked for by "
          f"recall). Null comparisons: every called window is false. Per-window truth: "
          f"`windows.tsv`.",
          "- Windows overlap (step < window), so one change counts in several windows, for "
          "both methods alike.", ""]
    if unconverged:
        md += [f"ICE did not converge on {len(unconverged)} merged maps (weights stored anyway): "
               + ", ".join(unconverged) + ".", ""]
    nn = {d: [n for r, n in zip(comps, nan_windows.values()) if r["depth"] == d] for d in depths}
    if any(sum(v) for v in nn.values()):
        md += ["CHESS windows with NaN (too small or too empty; never called), mean per "
               "comparison by depth: " + ", ".join(f"{d:g}: {sum(nn[d]) / len(nn[d]):.1f}"
                                                   for d in depths) + ".", ""]

    md += ["## Comparisons with true differences (A against B)", "",
           "Pooled over the comparisons of each cell, windows as the unit: precision = true / "
           "(true + false) called windows, recall = different windows called / different "
           "windows, F1 of the two; FDR = mean over comparisons of false / scored calls.", ""]
    for m in methods:
        md += [f"### {labels[m]}", "",
               "| replicates | depth | contacts / replicate | comparisons | called windows | true "
               "| false | found / different | precision | recall | F1 | observed FDR |",
               "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        md += ds.true_table_rows([r for r in rows if r["kind"] == m and r["comparison"] == "true"],
                                 depths, contacts)

    md += ["### Side by side: F1 (2 / 3 replicates)", "",
           "| depth (contacts / replicate) | " + " | ".join(labels[m] for m in methods) + " |",
           "|---|" + "---|" * len(methods)]
    for frac in depths:
        cells = []
        for m in methods:
            f1s = [agg([r for r in rows if r["kind"] == m and r["comparison"] == "true"
                        and r["replicates"] == reps and r["depth"] == frac])[7] for reps in (2, 3)]
            both = agg([r for r in rows if r["kind"] == m and r["comparison"] == "true"
                        and r["depth"] == frac])[7]
            cells.append(f"{fmt(f1s[0])} / {fmt(f1s[1])} (both {fmt(both)})")
        md.append(f"| {frac:g} ({kilo(contacts[frac])}) | " + " | ".join(cells) + " |")
    cells = []
    for m in methods:
        _, _, _, _, _, p, rc, f1, _ = agg([r for r in rows if r["kind"] == m
                                           and r["comparison"] == "true"])
        cells.append(f"**{fmt(f1)}** (precision {fmt(p)}, recall {fmt(rc)})")
    md += [f"| all {sum(1 for r in comps if r['comparison'] == 'true')} true comparisons | "
           + " | ".join(cells) + " |", ""]

    md += ["## Null comparisons (A against A' with other seeds)", "",
           "Every called window is false; the observed FDR (mean false-discovery proportion) is "
           "the fraction of comparisons with any call, with its Clopper-Pearson 95% interval "
           "(which treats the comparisons as independent: they are not, they share ensembles).",
           "", "| method | replicates | comparisons | with a call | called windows "
           "| windows per comparison | observed FDR | 95% interval |",
           "|---|---|---|---|---|---|---|---|"]
    for m in methods:
        for reps in (2, 3, "all"):
            sel = [r for r in rows if r["kind"] == m and r["comparison"] == "null"
                   and (reps == "all" or r["replicates"] == reps)]
            if not sel:
                continue
            k = sum(1 for r in sel if r["n_calls"] > 0)
            lo, hi = ds.clopper_pearson(k, len(sel))
            tested = sum(r["n_tested"] for r in sel) / len(sel)
            b_ = "**" if reps == "all" else ""
            md.append(f"| {labels[m]} | {reps} | {len(sel)} | {k} | "
                      f"{sum(r['n_calls'] for r in sel)} | {tested:.1f} | "
                      f"{b_}{k / len(sel):.3f}{b_} | [{lo:.3f}, {hi:.3f}] |")
    md += ["", "Null comparisons with a call, by depth (with a call / comparisons, called "
           "windows):", "", "| method | " + " | ".join(f"{d:g}" for d in depths) + " |",
           "|---|" + "---|" * len(depths)]
    for m in methods:
        cells = []
        for frac in depths:
            sel = [r for r in rows if r["kind"] == m and r["comparison"] == "null"
                   and r["depth"] == frac]
            cells.append(f"{sum(1 for r in sel if r['n_calls'] > 0)} / {len(sel)} "
                         f"({sum(r['n_calls'] for r in sel)})")
        md.append(f"| {labels[m]} | " + " | ".join(cells) + " |")

    md += ["", "## Observed FDR over all comparisons", "",
           "| method | comparisons (null + true) | scored called windows | false | pooled false / "
           "scored | mean FDP |", "|---|---|---|---|---|---|"]
    for m in methods:
        sel = [r for r in rows if r["kind"] == m]
        calls = sum(r["n_calls"] - r["excluded_calls"] for r in sel)
        fl = sum(r["false_calls"] for r in sel)
        n0 = sum(1 for r in sel if r["comparison"] == "null")
        md.append(f"| {labels[m]} | {len(sel)} ({n0} + {len(sel) - n0}) | {calls} | {fl} | "
                  f"{fmt(fl / calls if calls else float('nan'))} | "
                  f"**{fmt(sum(r['FDP'] for r in sel) / len(sel))}** |")

    # CHESS's cut-offs: how the figures move with them (same windows, same truth)
    md += ["", "## CHESS with other cut-offs", "",
           "The same `diff regions` outputs, other call rules: F1 over the true comparisons, "
           "null comparisons with a call, mean FDP over all comparisons.", "",
           "| rule | F1 (true) | precision | recall | null with a call | mean FDP (all) |",
           "|---|---|---|---|---|---|"]
    rules = [(args.z, args.sn), (args.z, -math.inf), (args.z, 1.0), (-1.5, args.sn),
             (-2.0, args.sn), (-2.0, -math.inf)]
    for zc, snc in rules:
        rr = []
        for r, vals in z_sn:
            called = [zz == zz and s_ == s_ and zz < zc and s_ > snc for zz, s_, _ in vals]
            n_calls, n_t, n_f, n_x, found, n_truth = score_windows(
                called, [k for _, _, k in vals], r["comparison"])
            p, rc, f1, fdp = ds.prf(n_calls, n_t, n_f, found, n_truth)
            rr.append(dict(comparison=r["comparison"], n_calls=n_calls, true_calls=n_t,
                           false_calls=n_f, found=found, n_truth=n_truth, FDP=fdp))
        tr = [x for x in rr if x["comparison"] == "true"]
        nl = [x for x in rr if x["comparison"] == "null"]
        _, _, _, _, _, p, rc, f1, _ = agg(tr)
        rule = f"z_ssim < {zc:g}" + (f" and SN > {snc:g}" if snc != -math.inf else "")
        b_ = "**" if (zc, snc) == (args.z, args.sn) else ""
        md.append(f"| {b_}{rule}{b_} | {fmt(f1)} | {fmt(p)} | {fmt(rc)} | "
                  f"{sum(1 for x in nl if x['n_calls'] > 0)} / {len(nl)} | "
                  f"{fmt(sum(x['FDP'] for x in rr) / len(rr))} |")
    # SN of the windows by truth class, true comparisons, by depth
    md += ["", "Median SN of the CHESS windows by truth class (true comparisons) and in null "
           "comparisons, by depth:", "",
           "| depth | different | unchanged | null (all windows) |", "|---|---|---|---|"]

    def median(xs):
        xs = sorted(x for x in xs if x == x)
        if not xs:
            return float("nan")
        n = len(xs)
        return xs[n // 2] if n % 2 else (xs[n // 2 - 1] + xs[n // 2]) / 2

    for frac in depths:
        dif = [s_ for r, v in z_sn if r["comparison"] == "true" and r["depth"] == frac
               for _, s_, k in v if k == "different"]
        unc = [s_ for r, v in z_sn if r["comparison"] == "true" and r["depth"] == frac
               for _, s_, k in v if k == "unchanged"]
        nul = [s_ for r, v in z_sn if r["comparison"] == "null" and r["depth"] == frac
               for _, s_, _ in v]
        md.append(f"| {frac:g} | {fmt(median(dif))} | {fmt(median(unc))} | {fmt(median(nul))} |")
    md += ["", "One row per comparison and method: `chess.tsv`; windows and their truth: "
           "`windows.tsv`; commands: `commands.log`.", ""]
    with open(os.path.join(out, "chess_summary.md"), "w") as f:
        f.write("\n".join(md))
    log(f"# wrote {os.path.join(out, 'chess.tsv')} ({len(rows)} rows) and chess_summary.md "
        f"in {elapsed:.0f} s")
    print("\n".join(md))


if __name__ == "__main__":
    main()
