#!/usr/bin/env python3
"""Peer run of the differential known-truth study (scripts/diff_study.py): Mustache's differential
loop caller (diff_mustache, PyPI mustache-hic, through scripts/run_diff_mustache.sh) on exactly
the comparisons of the study's `loops_called` kind, scored with the study's own functions against
the study's own truth, next to contactmap's numbers read from the study's study.tsv.

usage: scripts/diff_study_mustache.py [--study DIR] [--scale full] [--seed 1] [--tolerance 2]
                                      [--binary /tmp/ds/cm_rel] [--timing-binary BIN]
                                      [--processes 1] [--retime]

Python 3 standard library only. Needs a finished `scripts/diff_study.py --out DIR` (its maps,
simulations and study.tsv; run with the same --scale and --seed given here) and diff_mustache
installed as scripts/run_diff_mustache.sh says (MUSTACHE_VENV, default /tmp/mustache_venv).

Per comparison (every row of DIR/study.tsv with kind loops_called: null and true, 2 and 3
replicates, every depth):
- each condition's replicate maps (DIR/maps/sSEED.dDEPTH.cool, balanced) are summed with
  `BINARY merge` and the sum balanced with `BINARY balance --store --force --store-unconverged`
  (ICE, cooler's defaults): diff_mustache takes one map per condition;
- `scripts/run_diff_mustache.sh A.cool B.cool 5000 PREFIX -p N` with the tool's defaults
  (-pt 0.2 detection FDR, -pt2 0.1 difference p, -st 0.88, distance 2 Mb at 5 kb); its wall time
  is measured around the whole script (Python start-up and imports included);
- PREFIX.diffloop2 (loops of B weaker in A) become calls with direction `up` (stronger in B),
  PREFIX.diffloop1 (loops of A weaker in B) `down`; a failed run, or one that wrote no file
  (diff_mustache returns nothing when a map has fewer than 10,000 nonzero pixels within 2 Mb, or
  when no loop of one of the two maps passes its sparsity filters), counts as 0 calls;
- the calls are scored with diff_study.score_loops(matched_nearest=True, --tolerance) and
  diff_study.prf against the truth built as diff_study.main() builds it (the truth-loop fractions
  of all A ensembles against all B ensembles, diff_study.loop_truth); in a null comparison every
  call is false, as in the study. n_tested is the number of loops diff_mustache detected in A
  plus in B (PREFIX.loop1 + .loop2, not deduplicated): the analogue of the pooled dots that
  `diff loops` tests.
- timing of contactmap: `TIMING_BINARY diff loops --a A1 A2 [A3] --b B1 B2 [B3] -o X` (no
  --loops: it calls dots itself, as the loops_called kind; replicates given directly, nothing
  merged), wall time of the best of 3 runs, on every comparison; its calls are compared with the
  study's (DIR/diff/NAME.loops_called.loops.bedpe, made by --diff-binary) and disagreements noted.

As a check that the truth is the study's, the study's own loops_called outputs are rescored here
and must reproduce study.tsv's counts (the script stops otherwise).

Outputs: DIR/mustache.tsv (study.tsv's columns, kind diff_mustache, plus wall_seconds,
merge_balance_seconds, contactmap_seconds), DIR/mustache_summary.md, DIR/mustache/NAME/ (merged
maps, diff_mustache outputs and logs, result.json: the cache; a rerun reuses every comparison whose
inputs and commands are unchanged; --retime times contactmap again).
"""
import argparse
import importlib.util
import json
import os
import shlex
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location("diff_study", os.path.join(HERE, "diff_study.py"))
ds = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ds)

RES = 5000
log = ds.log


def run(cmd, **kw):
    log("$ " + " ".join(shlex.quote(str(c)) for c in cmd))
    t0 = time.time()
    p = subprocess.run([str(c) for c in cmd], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True, **kw)
    return p, time.time() - t0


def check(p, cmd):
    if p.returncode != 0:
        sys.stderr.write(p.stderr)
        raise SystemExit(f"command failed (exit {p.returncode}): {' '.join(map(str, cmd))}")


def read_rows(path):
    if not os.path.exists(path):
        return None
    with open(path) as f:
        lines = [ln.rstrip("\n").split("\t") for ln in f if ln.strip()]
    return lines[1:]


def mustache_calls(prefix):
    """diffloop2 -> up (stronger in B), diffloop1 -> down; None when diff_mustache wrote nothing."""
    d1, d2 = read_rows(prefix + ".diffloop1"), read_rows(prefix + ".diffloop2")
    if d1 is None or d2 is None:
        return None
    rows = []
    for direction, table in (("down", d1), ("up", d2)):
        for c in table:
            rows.append(dict(chrom1=c[0], start1=c[1], end1=c[2], chrom2=c[3], start2=c[4],
                             end2=c[5], fdr=c[6], scale=c[7], direction=direction))
    return rows




def score(rows, truth, tolerance, ctype):
    n_calls, n_t, n_f, n_x, found, n_truth = ds.score_loops(rows, truth, tolerance, True)
    if ctype == "null":
        n_f, n_t, n_x, found, n_truth = n_calls, 0, 0, 0, 0
    return n_calls, n_t, n_f, n_x, found, n_truth


def calls_set(path):
    out = set()
    for r in ds.read_table(path):
        if r["direction"] in ("up", "down"):
            out.add((r["chrom1"], r["start1"], r["start2"], r["direction"]))
    return out


agg = ds.pooled


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ds.study_arguments(ap)
    ap.add_argument("--tolerance", type=int, default=2, help="bins for matching calls to truth")
    ap.add_argument("--binary", default="/tmp/ds/cm_rel", help="contactmap for merge / balance")
    ap.add_argument("--timing-binary",
                    default=os.path.join(os.path.dirname(HERE), "target/release/contactmap"),
                    help="contactmap (release) timed on `diff loops` without --loops")
    ap.add_argument("--processes", type=int, default=1, help="diff_mustache -p")
    ap.add_argument("--nice", type=int, default=15, help="niceness of every command run")
    ap.add_argument("--retime", action="store_true", help="time contactmap again")
    args = ap.parse_args()
    out = os.path.abspath(args.study)
    cm = os.path.abspath(args.binary)
    cm_t = os.path.abspath(args.timing_binary)
    wrapper = os.path.join(HERE, "run_diff_mustache.sh")
    nice = ["nice", "-n", str(args.nice)]
    os.makedirs(os.path.join(out, "mustache"), exist_ok=True)
    ds.LOG = open(os.path.join(out, "mustache", "commands.log"), "a")
    log(f"# diff_study_mustache.py --study {out} --scale {args.scale} --seed {args.seed} "
        f"({time.strftime('%Y-%m-%d %H:%M:%S')})")
    t_start = time.time()

    # truth, exactly as diff_study.main() builds it
    sc = ds.SCALES[args.scale]
    base = 10000 * args.seed
    seeds_a = [base + 1001 + i for i in range(sc["n_a"])]
    seeds_b = [base + 2001 + i for i in range(sc["n_b"])]
    tpath = lambda s: os.path.join(out, "sims", f"s{s}.truth_loops.bedpe")  # noqa: E731
    fa = ds.read_truth_loops([tpath(s) for s in seeds_a])
    fb = ds.read_truth_loops([tpath(s) for s in seeds_b])
    truth = ds.loop_truth(fa, fb)
    n_changed = sum(1 for v in truth.values() if v[0] == "changed")
    log(f"# truth: {len(truth)} pairs, {n_changed} changed")

    study = ds.study_rows(os.path.join(out, "study.tsv"))
    cm_rows = [r for r in study if r["kind"] == "loops_called"]
    if not cm_rows:
        raise SystemExit("no loops_called rows in study.tsv (was it run with --no-called?)")

    # the study's own calls rescored here must give study.tsv's numbers
    for r in cm_rows:
        path = os.path.join(out, "diff", ds.study_row_name(r) + ".loops_called.loops.bedpe")
        got = score(ds.read_table(path), truth, args.tolerance, r["comparison"])
        want = (r["n_calls"], r["true_calls"], r["false_calls"], r["excluded_calls"], r["found"],
                r["n_truth"])
        if got != want:
            raise SystemExit(f"truth differs from the study's: {ds.study_row_name(r)} rescored {got}, "
                             f"study.tsv {want}")
    log(f"# truth check: the study's {len(cm_rows)} loops_called outputs rescore to study.tsv")

    version = subprocess.run([os.environ.get("MUSTACHE_VENV", "/tmp/mustache_venv") +
                              "/bin/python", "-c",
                              "import importlib.metadata as m; print(m.version('mustache-hic'))"],
                             stdout=subprocess.PIPE, text=True).stdout.strip()
    rows = []
    n_run = 0
    for ci, r in enumerate(cm_rows):
        name = ds.study_row_name(r)
        d = os.path.join(out, "mustache", name)
        os.makedirs(d, exist_ok=True)
        frac = r["depth"]
        a = r["a"].split(",")
        b = r["b"].split(",")
        amaps = [os.path.join(out, "maps", f"s{s}.d{frac:g}.cool") for s in a]
        bmaps = [os.path.join(out, "maps", f"s{s}.d{frac:g}.cool") for s in b]
        prefix = os.path.join(d, "dm")
        res_path = os.path.join(d, "result.json")
        params = dict(maps=amaps + bmaps, mtimes=[os.path.getmtime(p) for p in amaps + bmaps],
                      binary_mtime=os.path.getmtime(cm), wrapper_mtime=os.path.getmtime(wrapper),
                      processes=args.processes, version=version)
        result = None
        if os.path.exists(res_path):
            with open(res_path) as f:
                result = json.load(f)
            if result.get("params") != params:
                result = None
        if result is None:
            n_run += 1
            log(f"# [{ci + 1}/{len(cm_rows)}] {name}")
            t_mb = 0.0
            merged = {}
            for cond, maps in (("A", amaps), ("B", bmaps)):
                dst = os.path.join(d, f"{cond}.cool")
                if os.path.exists(dst):
                    os.remove(dst)
                cmd = [*nice, cm, "merge", *maps, "-o", dst]
                p, dt = run(cmd)
                check(p, cmd)
                t_mb += dt
                cmd = [*nice, cm, "balance", dst, "--store", "--force", "--store-unconverged"]
                p, dt = run(cmd)
                check(p, cmd)
                t_mb += dt
                merged[cond] = dict(path=dst, converged="converged=false" not in p.stderr,
                                    balance=p.stderr.strip().splitlines()[-1:])
            for k in ("loop1", "loop2", "diffloop1", "diffloop2", "log", "time"):
                if os.path.exists(f"{prefix}.{k}"):
                    os.remove(f"{prefix}.{k}")
            cmd = [*nice, wrapper, merged["A"]["path"], merged["B"]["path"], RES, prefix,
                   "-p", args.processes]
            p, wall = run(cmd)
            with open(prefix + ".stderr", "w") as f:
                f.write(p.stderr)
            if p.returncode != 0:
                log(f"  diff_mustache failed (exit {p.returncode}): 0 calls recorded")
            result = dict(params=params, rc=p.returncode, wall_seconds=wall,
                          merge_balance_seconds=t_mb, merged=merged)
            with open(res_path, "w") as f:
                json.dump(result, f, indent=1, sort_keys=True)
        calls = mustache_calls(prefix) if result["rc"] == 0 else None
        written = calls is not None
        calls = calls or []
        detected = sum(len(read_rows(f"{prefix}.{k}") or []) for k in ("loop1", "loop2"))
        n_calls, n_t, n_f, n_x, found, n_truth = score(calls, truth, args.tolerance,
                                                       r["comparison"])
        p_, rc_, f1, fdp = ds.prf(n_calls, n_t, n_f, found, n_truth)

        # contactmap (release) timing on the same comparison, replicates given directly
        tres = os.path.join(d, "contactmap_timing.json")
        tparams = dict(maps=amaps + bmaps, mtimes=params["mtimes"],
                       binary=cm_t, binary_mtime=os.path.getmtime(cm_t))
        timing = None
        if os.path.exists(tres) and not args.retime:
            with open(tres) as f:
                timing = json.load(f)
            if timing.get("params") != tparams:
                timing = None
        if timing is None:
            xp = os.path.join(d, "cm")
            cmd = [*nice, cm_t, "diff", "loops", "--a", *amaps, "--b", *bmaps, "-o", xp]
            walls, rc = [], 0
            for _ in range(3):
                p, dt = run(cmd)
                rc = p.returncode
                walls.append(dt)
            agree = None
            study_out = os.path.join(out, "diff", name + ".loops_called.loops.bedpe")
            if rc == 0 and os.path.exists(xp + ".loops.bedpe"):
                mine, theirs = calls_set(xp + ".loops.bedpe"), calls_set(study_out)
                agree = dict(same=mine == theirs, release_calls=len(mine), study_calls=len(theirs),
                             shared=len(mine & theirs))
            elif rc != 0:
                # as the study: too sparse for dots to score any pixel, no loop called
                agree = dict(same=calls_set(study_out) == set(), release_calls=0,
                             study_calls=len(calls_set(study_out)), shared=0)
            timing = dict(params=tparams, rc=rc, walls=walls, agree=agree)
            with open(tres, "w") as f:
                json.dump(timing, f, indent=1, sort_keys=True)

        rows.append(dict(kind="diff_mustache", comparison=r["comparison"],
                         replicates=r["replicates"], depth=frac, contacts=r["contacts"],
                         a=r["a"], b=r["b"], n_tested=detected, n_calls=n_calls, true_calls=n_t,
                         false_calls=n_f, excluded_calls=n_x, n_truth=n_truth, found=found,
                         precision=p_, recall=rc_, F1=f1, FDP=fdp,
                         wall_seconds=result["wall_seconds"],
                         merge_balance_seconds=result["merge_balance_seconds"],
                         contactmap_seconds=min(timing["walls"]), cm_rc=timing["rc"], written=written,
                         rc=result["rc"], cm_agree=timing["agree"], name=name,
                         unconverged=[c for c, m in result["merged"].items()
                                      if not m["converged"]]))
        log(f"  {name}: diff_mustache {n_calls} calls ({n_t} true, {n_f} false, {n_x} excluded), "
            f"{result['wall_seconds']:.1f} s; contactmap {r['n_calls']} calls "
            f"({r['true_calls']} true, {r['false_calls']} false), {min(timing['walls']):.2f} s")

    cols = ["kind", "comparison", "replicates", "depth", "contacts", "a", "b", "n_tested",
            "n_calls", "true_calls", "false_calls", "excluded_calls", "n_truth", "found",
            "precision", "recall", "F1", "FDP", "wall_seconds", "merge_balance_seconds",
            "contactmap_seconds"]
    ds.write_tsv(os.path.join(out, "mustache.tsv"), rows, cols)

    # ------------------------------------------------------------ summary
    depths = sorted({r["depth"] for r in rows})
    contacts = {r["depth"]: r["contacts"] for r in rows}
    tools = [("diff_mustache", rows), ("contactmap diff loops (loops_called)", cm_rows)]
    elapsed = time.time() - t_start
    fmt = ds.fmt
    md = [f"# diff_mustache on the differential known-truth study (`scripts/diff_study_mustache.py "
          f"--study {args.study} --scale {args.scale} --seed {args.seed}`)", "",
          f"Generated {time.strftime('%Y-%m-%d %H:%M')}; diff_mustache (mustache-hic {version}) "
          f"through `scripts/run_diff_mustache.sh ... {RES} PREFIX -p {args.processes}` with its "
          f"defaults (-pt 0.2, -pt2 0.1, -st 0.88, 2 Mb), on each condition's replicates summed by "
          f"`{args.binary} merge` and balanced by `balance --store` (ICE); contactmap's rows are "
          f"the study's `loops_called` (its study.tsv, `diff loops` without `--loops`, q < 0.05). "
          f"Wall time of this run {elapsed:.0f} s ({n_run} comparisons run, the rest cached).", "",
          f"Same {len(rows)} comparisons, same truth (rescoring the study's own outputs here "
          f"reproduces study.tsv), same scoring: a call is placed on the nearest truth pair with "
          f"both anchors within {args.tolerance} bins; diffloop2 (B's loops weaker in A) = up, "
          f"diffloop1 = down. Calls on an ambiguous pair are left out of precision; in null "
          f"comparisons every call is false.", ""]
    bad = [r for r in rows if r["unconverged"]]
    if bad:
        md += [f"ICE did not converge on the merged map(s) of {len(bad)} comparisons "
               f"(weights stored anyway): " + ", ".join(r["name"] for r in bad) + ".", ""]

    md += ["## Comparisons with true differences (A against B)", "",
           "Pooled over the comparisons of each cell: precision = true / (true + false) calls, "
           "recall = truth differences found / truth differences, F1 of the two; FDR = mean over "
           "comparisons of false / scored calls.", ""]
    for tool, sel_rows in tools:
        md += [f"### {tool}", "",
               "| replicates | depth | contacts / replicate | comparisons | calls | true | false "
               "| found / truth | precision | recall | F1 | observed FDR |",
               "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        md += ds.true_table_rows([r for r in sel_rows if r["comparison"] == "true"], depths,
                                 contacts)

    md += ["### Side by side (precision / recall / F1)", "",
           "| replicates | depth | contactmap | diff_mustache |", "|---|---|---|---|"]
    for reps in (2, 3, "all"):
        for frac in (depths if reps != "all" else ["all"]):
            cells = []
            for _, sel_rows in reversed(tools):
                sel = [r for r in sel_rows if r["comparison"] == "true"
                       and (reps == "all" or (r["replicates"] == reps and r["depth"] == frac))]
                _, _, _, _, _, p, rc, f1, _ = agg(sel)
                cells.append(f"{fmt(p)} / {fmt(rc)} / **{fmt(f1)}**")
            md.append(f"| {reps} | {frac if frac == 'all' else format(frac, 'g')} | {cells[0]} "
                      f"| {cells[1]} |")
    md.append("")
    md += ["F1 by depth, 2 and 3 replicates pooled:", "",
           "| depth | contactmap | diff_mustache |", "|---|---|---|"]
    for frac in depths:
        cells = []
        for _, sel_rows in reversed(tools):
            sel = [r for r in sel_rows if r["comparison"] == "true" and r["depth"] == frac]
            cells.append(fmt(agg(sel)[7]))
        md.append(f"| {frac:g} | {cells[0]} | {cells[1]} |")
    md.append("")

    md += ["## Null comparisons (A against A' with other seeds)", "",
           "Every call is false; the observed FDR (mean false-discovery proportion) is the "
           "fraction of comparisons with any call, given with its Clopper-Pearson 95% interval "
           "(which treats the comparisons as independent: they are not, they share ensembles). "
           "Tested per comparison: contactmap's pooled dots; diff_mustache's loops detected in A "
           "plus in B.", "",
           "| tool | replicates | comparisons | with a call | calls | tested per comparison "
           "| observed FDR | 95% interval |", "|---|---|---|---|---|---|---|---|"]
    for tool, sel_rows in reversed(tools):
        for reps in (2, 3, "all"):
            sel = [r for r in sel_rows if r["comparison"] == "null"
                   and (reps == "all" or r["replicates"] == reps)]
            if not sel:
                continue
            k = sum(1 for r in sel if r["n_calls"] > 0)
            lo, hi = ds.clopper_pearson(k, len(sel))
            tested = sum(r["n_tested"] for r in sel) / len(sel)
            b_ = "**" if reps == "all" else ""
            md.append(f"| {tool} | {reps} | {len(sel)} | {k} | {sum(r['n_calls'] for r in sel)} "
                      f"| {tested:.1f} | {b_}{k / len(sel):.3f}{b_} | [{lo:.3f}, {hi:.3f}] |")
    md += ["", "Null comparisons with a call, by depth (with a call / comparisons):", "",
           "| tool | " + " | ".join(f"{d:g}" for d in depths) + " |",
           "|---|" + "---|" * len(depths)]
    for tool, sel_rows in reversed(tools):
        cells = []
        for frac in depths:
            sel = [r for r in sel_rows if r["comparison"] == "null" and r["depth"] == frac]
            cells.append(f"{sum(1 for r in sel if r['n_calls'] > 0)} / {len(sel)} "
                         f"({sum(r['n_calls'] for r in sel)} calls)")
        md.append(f"| {tool} | " + " | ".join(cells) + " |")

    md += ["", "## Observed FDR over all comparisons", "",
           "| tool | comparisons (null + true) | calls | false calls | pooled false / calls "
           "| mean FDP |", "|---|---|---|---|---|---|"]
    for tool, sel_rows in reversed(tools):
        sel = sel_rows
        calls = sum(r["n_calls"] - r["excluded_calls"] for r in sel)
        fl = sum(r["false_calls"] for r in sel)
        nn = sum(1 for r in sel if r["comparison"] == "null")
        md.append(f"| {tool} | {len(sel)} ({nn} + {len(sel) - nn}) | {calls} | {fl} | "
                  f"{fmt(fl / calls if calls else float('nan'))} | "
                  f"{fmt(sum(r['FDP'] for r in sel) / len(sel))} |")

    mean = lambda xs: sum(xs) / len(xs) if xs else float("nan")  # noqa: E731
    agree = [r["cm_agree"] for r in rows if r["cm_agree"] is not None]
    n_same = sum(1 for x in agree if x["same"])
    md += ["", "## Wall time per comparison", "",
           f"Seconds, mean over comparisons (niceness {args.nice}, 1 block: the 4.5 Mb chromosome "
           f"fits one 2,000-bin chunk). diff_mustache: `run_diff_mustache.sh` as a whole, -p "
           f"{args.processes} (Python start-up and imports included); merge + balance: the two "
           f"`merge` and `balance --store` runs it needs first; contactmap: `{args.timing_binary} "
           f"diff loops` without --loops on the replicates themselves, best of 3 runs.", "",
           "| replicates | depth | comparisons | diff_mustache | merge + balance | contactmap "
           "diff loops | ratio |", "|---|---|---|---|---|---|---|"]
    for reps in (2, 3, "all"):
        for frac in (depths if reps != "all" else ["all"]):
            sel = [r for r in rows if reps == "all"
                   or (r["replicates"] == reps and r["depth"] == frac)]
            w, mb, c = (mean([r[k] for r in sel]) for k in
                        ("wall_seconds", "merge_balance_seconds", "contactmap_seconds"))
            md.append(f"| {reps} | {frac if frac == 'all' else format(frac, 'g')} | {len(sel)} | "
                      f"{w:.2f} | {mb:.2f} | {c:.3f} | {w / c:.0f}x |")
    md += ["", f"The timed contactmap ({args.timing_binary}) gave the same up/down calls as the "
           f"study's `--diff-binary` on {n_same} of {len(agree)} comparisons."]
    cm_failed = [r for r in rows if r["cm_rc"] != 0]
    if cm_failed:
        md += ["", f"contactmap `diff loops` stopped with an error (no dot could be scored: too "
               f"sparse; 0 calls, as in the study) on {len(cm_failed)} comparisons (depths "
               + ", ".join(sorted({f"{r['depth']:g}" for r in cm_failed}))
               + "): its time there is that of the failed run."]
    diff_ = [r for r in rows if r["cm_agree"] is not None and not r["cm_agree"]["same"]]
    for r in diff_:
        a_ = r["cm_agree"]
        md.append(f"- {r['name']}: {a_['release_calls']} calls here, {a_['study_calls']} in the "
                  f"study, {a_['shared']} shared")
    failed = [r for r in rows if r["rc"] != 0]
    unwritten = [r for r in rows if r["rc"] == 0 and not r["written"]]
    empty = [r for r in rows if r["written"] and r["n_tested"] == 0]
    md += ["", "## diff_mustache runs without output", "",
           f"- failed (non-zero exit): {len(failed)}"
           + (": " + ", ".join(r["name"] for r in failed) if failed else ""),
           f"- exit 0 but no diffloop files: {len(unwritten)}",
           f"- no loop detected in either map (0 calls): {len(empty)} "
           "(by depth: " + ", ".join(
               f"{d:g}: {sum(1 for r in empty if r['depth'] == d)}/"
               f"{sum(1 for r in rows if r['depth'] == d)}" for d in depths) + ")",
           "", "diff_mustache returns nothing for a chromosome when either map has fewer than "
           "10,000 nonzero pixels within the distance limit, or when either map keeps no "
           "significant pixel after its sparsity filters (local nonzero fraction >= -st 0.88 "
           "around the pixel and a hard-coded >= 0.6 in twice the window): then neither map's "
           "loops nor differential loops are written. -st does not relax the second filter.",
           "", "One row per comparison: `mustache.tsv`; outputs and logs: `mustache/`.", ""]
    with open(os.path.join(out, "mustache_summary.md"), "w") as f:
        f.write("\n".join(md))
    log(f"# wrote {os.path.join(out, 'mustache.tsv')} ({len(rows)} rows) and mustache_summary.md "
        f"in {elapsed:.0f} s")
    print("\n".join(md))


if __name__ == "__main__":
    main()
