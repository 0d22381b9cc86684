#!/usr/bin/env python3
"""Simulated Hi-C reads aligned by bwa: the fixture of `contactmap pairs` (data/pairs/).

    python3 scripts/pairs_fixture.py --out-dir DIR [--n-pairs 5000] [--seed 2] [--genome-seed 1]
    python3 scripts/pairs_fixture.py --out-dir DIR --n-pairs 500000 --genome-scale 10 \\
        --no-truth --replicate 20 --replicate-out /tmp/bench10M.bam   # 10 M pairs (see below)

Python 3 standard library only; needs `bwa` and `samtools` on PATH (Debian: apt-get install bwa
samtools).  Everything is drawn from `random.Random`:

  * the genome from seed `--genome-seed` (default 1): chr1 300 kb, chr2 220 kb, chr3 160 kb,
    chrX 120 kb (times --genome-scale) of uniform random bases, with repeat families pasted over
    it (REPEATS below: exact and near-exact copies of 320-1000 bp elements on several
    chromosomes, so that bwa reports MAPQ 0 / low MAPQ and XA tags);
  * the read pairs from seed `--seed` (default 2): molecules of the kinds in KINDS below
    (ligations with P(s) ~ 1/s in cis and 15% trans; junctions inside reads; three- and
    four-fragment walks; two junctions in one read; repeats; random unmappable mates; unligated
    and self-circle fragments; chromosome ends), read length `--read-len` (100), substitution
    errors in 25% of the reads and a 1-3 bp indel in 4%, then PCR duplicates: exact copies
    (same molecule, fresh sequencing errors), copies whose two 5' ends moved by 1-3 bp ("shift",
    found by `pairtools dedup --max-mismatch 3`; both ends moved in half of them, which
    separates `--method max` from `--method sum`) and copies with one end moved by 4-6 bp
    ("far", a negative control).  The pairs are shuffled.  Read names are
    `p<5 digits>:<kind>[:dx|:ds|:df]` (dx/ds/df: exact / shifted / far duplicate).

Outputs in DIR: genome.fa (+ bwa index), sim.chrom.sizes, repeats.bed, R1.fq, R2.fq,
truth.tsv (one line per pair: readid, kind, dup, dup_of, molecule segments chrom:start-end:strand
0-based half-open in molecule order, read-1 and read-2 errors) and the alignment
`bwa mem -SP5M -K 10000000 -t T genome.fa R1.fq R2.fq | samtools view --no-PG -b
--output-fmt-option level=9 -o sim.bam`
(name-grouped as bwa writes it; -K makes the output independent of -t).  `--also-nom` also
writes sim.noM.bam aligned with `-SP5` (split alignments flagged supplementary, 0x800, instead
of secondary).

--replicate K (benchmark input, not a fixture): on this project's 2-core machine bwa aligns
100,000 pairs in 6.3 s (800 kb genome, idle machine) to 40 s (80 Mb genome, --genome-scale 100,
machine busy), and this script simulates them in 8-20 s: 10 M pairs would take 30-100 min.  So
the base set of --n-pairs pairs is aligned once and written K times to --replicate-out: copy k
gets ":k" appended to its read names and every coordinate on a chromosome of length L moved by
k*L (POS, PNEXT, the SA and XA tags; TLEN is unchanged), and the header declares each chromosome
K times as long (the genome tiled K times; also written as REPLICATE_OUT.chrom.sizes).  Copies
are thus disjoint, each keeps the base set's duplicates, P(s), walks and multimappers, and the
file stays name-grouped.  pairtools parse gives on copy k exactly copy 0's pairs, moved.
10 M pairs:  --n-pairs 500000 --genome-scale 10 --no-truth --replicate 20 --replicate-out BAM
"""
import argparse
import os
import random
import subprocess
import sys

CHROMS = [("chr1", 300_000), ("chr2", 220_000), ("chr3", 160_000), ("chrX", 120_000)]

# name, length, copies: list of (chrom, divergence); divergence = fraction of substituted bases
REPEATS = [
    ("repA", 320, [("chr1", 0), ("chr1", 0), ("chr2", 0), ("chr2", 0), ("chr3", 0), ("chrX", 0)]),
    ("repB", 650, [("chr1", 0.003), ("chr2", 0.003), ("chr3", 0.003), ("chrX", 0.003)]),
    ("repC", 1000, [("chr1", 0), ("chr2", 0), ("chrX", 0), ("chr3", 0.02)]),
    ("repD", 480, [("chr2", 0), ("chr2", 0)]),
]

# kind: weight (fraction of the original molecules)
KINDS = [
    ("cis", 0.36),  # two fragments, cis, P(s) ~ 1/s, no junction inside the reads
    ("trans", 0.08),  # two fragments on two chromosomes
    ("unlig", 0.05),  # one fragment 120-700 bp (dangling end): inward pair at short distance
    ("circ", 0.02),  # self-circle: outward pair at short distance
    ("chim1", 0.08),  # junction inside read 1 (30-70 bp of A), read 2 on B: rescued
    ("chim2", 0.06),  # junction inside read 2
    ("walk3", 0.05),  # A|B in read 1, read 2 on a third fragment C
    ("walk3b", 0.04),  # A|B in read 1, C|B in read 2 (both reads chimeric, B short)
    ("twojunc", 0.03),  # A|B|C inside read 1 (two junctions), read 2 on C
    ("walk4", 0.02),  # A|B in read 1, D|C in read 2: four fragments
    ("rep1", 0.05),  # read 1 inside a repeat copy
    ("rep2", 0.02),  # both reads inside repeat copies
    ("chimrep", 0.02),  # read 1 = repeat part | unique part
    ("unmapR2", 0.02),  # read 2 random sequence
    ("unmapR1", 0.01),  # read 1 random sequence
    ("unmap2", 0.01),  # both random
    ("edge", 0.02),  # a fragment touching a chromosome end
]

COMP = str.maketrans("ACGTN", "TGCAN")


def rc(s):
    return s.translate(COMP)[::-1]


# ----------------------------------------------------------------------------- genome
def make_genome(seed, scale=1):
    rng = random.Random(seed)
    sizes = {c: n * scale for c, n in CHROMS}
    seqs = {}
    for c, n in sizes.items():
        seqs[c] = bytearray()
        for i in range(0, n, 1 << 20):
            seqs[c] += "".join(rng.choices("ACGT", k=min(1 << 20, n - i))).encode()
    placed = []  # (chrom, start, end, name, copy)
    for name, length, copies in REPEATS:
        element = "".join(rng.choices("ACGT", k=length))
        for k, (chrom, div) in enumerate(copies):
            while True:
                start = rng.randrange(5000, sizes[chrom] - 5000 - length)
                if all(
                    c != chrom or start + length + 2000 <= s or e + 2000 <= start
                    for c, s, e, _, _ in placed
                ):
                    break
            copy = list(element)
            for i in range(length):
                if div and rng.random() < div:
                    copy[i] = rng.choice([b for b in "ACGT" if b != copy[i]])
            if rng.random() < 0.5:  # copies in both orientations
                copy = list(rc("".join(copy)))
                strand = "-"
            else:
                strand = "+"
            seqs[chrom][start:start + length] = "".join(copy).encode()
            placed.append((chrom, start, start + length, f"{name}_{k}", strand))
    placed.sort(key=lambda r: ([c for c, _ in CHROMS].index(r[0]), r[1]))
    return {c: s.decode() for c, s in seqs.items()}, placed


# ----------------------------------------------------------------------------- molecules
class Sim:
    def __init__(self, genome, repeats, rng, read_len):
        self.g = genome
        self.sizes = {c: len(s) for c, s in genome.items()}
        self.names = [c for c, _ in CHROMS]
        self.weights = [self.sizes[c] for c in self.names]
        self.repeats = repeats
        self.rng = rng
        self.L = read_len

    def in_repeat(self, chrom, start, end):
        return any(c == chrom and start < e + 50 and s - 50 < end for c, s, e, _, _ in self.repeats)

    def locus(self, length, chrom=None):
        """A unique locus [start, start+length) away from repeats."""
        r = self.rng
        while True:
            c = chrom or r.choices(self.names, self.weights)[0]
            if self.sizes[c] <= length + 2:
                continue
            s = r.randrange(0, self.sizes[c] - length)
            if not self.in_repeat(c, s, s + length):
                return c, s

    def seg(self, chrom, start, length, strand=None):
        return [chrom, start, start + length, strand or self.rng.choice("+-")]

    def partner(self, chrom, pos, length, trans):
        """Second fragment: cis at separation s ~ 1/s (150 bp .. chromosome), or trans."""
        r = self.rng
        if trans:
            others = [c for c in self.names if c != chrom]
            c, s = self.locus(length, r.choices(others, [self.sizes[o] for o in others])[0])
            return self.seg(c, s, length)
        n = self.sizes[chrom]
        for _ in range(1000):
            sep = int(150 * (n / 150) ** r.random())
            s = pos + sep if r.random() < 0.5 else pos - sep - length
            if 0 <= s <= n - length and not self.in_repeat(chrom, s, s + length):
                return self.seg(chrom, s, length)
        c, s = self.locus(length, chrom)
        return self.seg(c, s, length)

    def unique(self, length):
        c, s = self.locus(length)
        return self.seg(c, s, length)

    def repeat_seg(self, length):
        """A segment fully inside a repeat copy (length <= element length)."""
        c, s, e, _, _ = self.rng.choice(self.repeats)
        length = min(length, e - s)
        st = self.rng.randrange(s, e - length + 1)
        return self.seg(c, st, length)

    def molecule(self, kind):
        """Segments [chrom, start, end, strand] in molecule order, or None for random reads."""
        r, L = self.rng, self.L
        short = lambda: r.randint(30, 70)  # a junction inside the read
        long_ = lambda lo=L + 5, hi=450: r.randint(lo, hi)
        trans = r.random() < 0.15
        if kind in ("cis", "trans"):
            a = self.unique(long_())
            b = self.partner(a[0], a[1], long_(), kind == "trans")
            return [a, b]
        if kind == "unlig":
            return [self.unique(r.randint(120, 700))]
        if kind == "circ":
            c, f0 = self.locus(700)
            lf = r.randint(300, 700)
            la = r.randint(L + 5, lf - L - 5)
            a = [c, f0 + lf - la, f0 + lf, "+"]
            b = [c, f0, f0 + lf - la, "+"]
            mol = [a, b]
            if r.random() < 0.5:  # the same circle read from the other strand
                mol = [[c, b[1], b[2], "-"], [c, a[1], a[2], "-"]]
            return mol
        if kind == "chim1":
            a = self.unique(short())
            return [a, self.partner(a[0], a[1], long_(150, 600), trans)]
        if kind == "chim2":
            a = self.unique(long_(150, 600))
            return [a, self.partner(a[0], a[1], short(), trans)]
        if kind == "walk3":
            a = self.unique(short())
            b = self.partner(a[0], a[1], r.randint(100, 300), trans)
            c = self.partner(b[0], b[1], long_(), r.random() < 0.15)
            return [a, b, c]
        if kind == "walk3b":
            a = self.unique(short())
            b = self.partner(a[0], a[1], r.randint(60, 140), trans)
            c = self.partner(b[0], b[1], short(), r.random() < 0.15)
            return [a, b, c]
        if kind == "twojunc":
            a = self.unique(r.randint(30, 40))
            b = self.partner(a[0], a[1], r.randint(35, 45), trans)
            c = self.partner(b[0], b[1], r.randint(150, 400), r.random() < 0.15)
            return [a, b, c]
        if kind == "walk4":
            a = self.unique(short())
            b = self.partner(a[0], a[1], r.randint(100, 250), trans)
            c = self.partner(b[0], b[1], r.randint(100, 250), r.random() < 0.15)
            d = self.partner(c[0], c[1], short(), r.random() < 0.15)
            return [a, b, c, d]
        if kind == "rep1":
            a = self.repeat_seg(long_(L + 5, 300))
            return [a, self.partner(a[0], a[1], long_(), trans)]
        if kind == "rep2":
            return [self.repeat_seg(long_(L + 5, 300)), self.repeat_seg(long_(L + 5, 300))]
        if kind == "chimrep":
            a = self.repeat_seg(short())
            return [a, self.partner(a[0], a[1], long_(150, 600), trans)]
        if kind == "edge":
            c = r.choice(self.names)
            n = self.sizes[c]
            la = long_()
            if r.random() < 0.5:
                a = [c, r.randint(0, 3), 0, "-"]  # read 1 ends at the chromosome start
                a[2] = a[1] + la
            else:
                a = [c, n - la - r.randint(0, 3), 0, "+"]  # read 1 ends at the chromosome end
                a[2] = a[1] + la
            if r.random() < 0.5:
                return [a]
            return [a, self.partner(c, a[1], long_(), trans)]
        return None  # unmapped kinds

    def seq(self, mol):
        return "".join(
            self.g[c][s:e] if st == "+" else rc(self.g[c][s:e]) for c, s, e, st in mol
        )

    def read(self, template):
        """Read L bases from the 5' end of template, with sequencing errors; returns (seq, note)."""
        r, L = self.rng, self.L
        notes = []
        if r.random() < 0.04 and len(template) >= L + 3:
            d = r.randint(1, 3)
            p = r.randint(25, L - 25)
            if r.random() < 0.5:
                s = template[:p] + template[p + d:L + d]
                notes.append(f"del{d}@{p}")
            else:
                s = template[:p] + "".join(r.choices("ACGT", k=d)) + template[p:L - d]
                notes.append(f"ins{d}@{p}")
        else:
            s = template[:L]
        s = list(s)
        if r.random() < 0.25:
            for _ in range(r.randint(1, 3)):
                p = r.randrange(L)
                s[p] = r.choice([b for b in "ACGT" if b != s[p]])
                notes.append(f"sub@{p}")
        return "".join(s), ",".join(notes) or "."


def shift_ends(mol, d1, d2, sizes):
    """Move the molecule's 5' end (read 1's start) by d1 and its 3' end (read 2's start) by d2
    (positive = longer); None if out of the chromosome or too short."""
    mol = [list(s) for s in mol]
    first, last = mol[0], mol[-1]
    if first[3] == "+":
        first[1] -= d1
    else:
        first[2] += d1
    if last[3] == "+":
        last[2] += d2
    else:
        last[1] -= d2
    for c, s, e, _ in mol:
        if s < 0 or e > sizes[c] or e - s < 25:
            return None
    return mol


def simulate(genome, repeats, n_pairs, seed, read_len, chunk=200_000):
    """Yield lists of read pairs, `chunk` pairs at a time (duplicates and the shuffle stay
    within a chunk; the fixture is one chunk)."""
    rng = random.Random(seed)
    sim = Sim(genome, repeats, rng, read_len)
    kinds, weights = zip(*KINDS)
    width = max(5, len(str(n_pairs - 1)))
    done = 0
    while done < n_pairs:
        want = min(chunk, n_pairs - done)
        pairs = []  # dict(kind, dup, of (index), mol)
        while len(pairs) < want:
            kind = rng.choices(kinds, weights)[0]
            mol = sim.molecule(kind)
            if mol is not None and len(sim.seq(mol)) < read_len + 3:
                continue
            pairs.append(dict(kind=kind, dup="", of=None, mol=mol))
            orig = len(pairs) - 1
            if mol is None:
                continue
            u = rng.random()
            if u < 0.07:  # exact PCR duplicates (1 or 2 extra copies)
                for _ in range(1 if rng.random() < 0.8 else 2):
                    pairs.append(dict(kind=kind, dup="dx", of=orig, mol=mol))
            elif u < 0.11:  # shifted by 1-3 bp: one end, or both ends (max <= 3 < sum)
                d1 = rng.choice([-3, -2, -1, 1, 2, 3])
                d2 = rng.choice([-3, -2, -1, 1, 2, 3]) if rng.random() < 0.5 else 0
                if rng.random() < 0.5:
                    d1, d2 = d2, d1
                m2 = shift_ends(mol, d1, d2, sim.sizes)
                if m2 is not None:
                    pairs.append(dict(kind=kind, dup="ds", of=orig, mol=m2, d=(d1, d2)))
            elif u < 0.12:  # one end moved by 4-6 bp: not a duplicate at --max-mismatch 3
                d = rng.choice([-6, -5, -4, 4, 5, 6])
                d1, d2 = (d, 0) if rng.random() < 0.5 else (0, d)
                m2 = shift_ends(mol, d1, d2, sim.sizes)
                if m2 is not None:
                    pairs.append(dict(kind=kind, dup="df", of=orig, mol=m2, d=(d1, d2)))
        pairs = pairs[:want]
        order = list(range(len(pairs)))
        rng.shuffle(order)
        name_of = {}
        for new, old in enumerate(order):
            p = pairs[old]
            name_of[old] = f"p{done + new:0{width}d}:{p['kind']}" + (f":{p['dup']}" if p["dup"] else "")
        out = []
        L = read_len
        for old in order:
            p = pairs[old]
            mol_seq = None if p["mol"] is None else sim.seq(p["mol"])
            if p["kind"] in ("unmapR1", "unmap2"):
                r1, n1 = "".join(rng.choices("ACGT", k=L)), "random"
            if p["kind"] in ("unmapR2", "unmap2"):
                r2, n2 = "".join(rng.choices("ACGT", k=L)), "random"
            if p["kind"] in ("unmapR1", "unmapR2"):
                a = sim.unique(rng.randint(L + 5, 450))
                p["mol"] = [a]
                mol_seq = sim.seq([a])
            if p["kind"] not in ("unmapR1", "unmap2"):
                r1, n1 = sim.read(mol_seq)
            if p["kind"] not in ("unmapR2", "unmap2"):
                r2, n2 = sim.read(rc(mol_seq))
            out.append(dict(
                name=name_of[old], kind=p["kind"], dup=p["dup"] or ".",
                of=name_of[p["of"]] if p["of"] is not None else ".",
                d=p.get("d"), mol=p["mol"], r1=r1, r2=r2, n1=n1, n2=n2,
            ))
        done += want
        yield out


# ----------------------------------------------------------------------------- output
def write_fasta(path, genome):
    with open(path, "w") as f:
        for c, s in genome.items():
            f.write(f">{c}\n")
            for i in range(0, len(s), 60):
                f.write(s[i:i + 60] + "\n")


def write_outputs(out_dir, genome, repeats, chunks, truth=True):
    write_fasta(os.path.join(out_dir, "genome.fa"), genome)
    with open(os.path.join(out_dir, "sim.chrom.sizes"), "w") as f:
        for c, s in genome.items():
            f.write(f"{c}\t{len(s)}\n")
    with open(os.path.join(out_dir, "repeats.bed"), "w") as f:
        for c, s, e, name, strand in repeats:
            f.write(f"{c}\t{s}\t{e}\t{name}\t0\t{strand}\n")
    with open(os.path.join(out_dir, "R1.fq"), "w") as f1, \
            open(os.path.join(out_dir, "R2.fq"), "w") as f2, \
            open(os.path.join(out_dir, "truth.tsv") if truth else os.devnull, "w") as ft:
        ft.write("readid\tkind\tdup\tdup_of\tshift\tsegments\terrors1\terrors2\n")
        for reads in chunks:
            qual = "I" * len(reads[0]["r1"])
            b1, b2, bt = [], [], []
            for p in reads:
                b1.append(f"@{p['name']}\n{p['r1']}\n+\n{qual}\n")
                b2.append(f"@{p['name']}\n{p['r2']}\n+\n{qual}\n")
                if truth:
                    segs = ",".join(f"{c}:{s}-{e}:{st}" for c, s, e, st in p["mol"]) if p["mol"] else "."
                    d = f"{p['d'][0]},{p['d'][1]}" if p["d"] else "."
                    bt.append(f"{p['name']}\t{p['kind']}\t{p['dup']}\t{p['of']}\t{d}\t{segs}\t{p['n1']}\t{p['n2']}\n")
            f1.writelines(b1)
            f2.writelines(b2)
            ft.writelines(bt)


def run(cmd, cwd):
    print("+ (cd %s && %s)" % (cwd, cmd), file=sys.stderr)
    subprocess.run(["bash", "-o", "pipefail", "-c", cmd], cwd=cwd, check=True)


def align(out_dir, threads, bam, flags):
    run(
        f"bwa mem {flags} -K 10000000 -t {threads} genome.fa R1.fq R2.fq 2> {bam}.bwa.log"
        f" | samtools view --no-PG -b --output-fmt-option level=9 -o {bam}",
        out_dir,
    )


# ----------------------------------------------------------------------------- replicate
def replicate(bam, k_copies, out, threads):
    """Write k_copies tiled copies of a name-grouped BAM (see the module docstring)."""
    view = subprocess.Popen(["samtools", "view", "--no-PG", "-h", bam], stdout=subprocess.PIPE, text=True)
    wr = subprocess.Popen(
        ["samtools", "view", "--no-PG", "-b", "-@", str(threads), "-o", out, "-"],
        stdin=subprocess.PIPE, text=True,
    )
    sizes, header, records = {}, [], []
    for line in view.stdout:
        if line.startswith("@"):
            if line.startswith("@SQ"):
                f = dict(x.split(":", 1) for x in line.rstrip("\n").split("\t")[1:])
                sizes[f["SN"]] = int(f["LN"])
                line = f"@SQ\tSN:{f['SN']}\tLN:{int(f['LN']) * k_copies}\n"
            header.append(line)
        else:
            records.append(line.rstrip("\n").split("\t"))
    view.wait()
    w = wr.stdin
    w.writelines(header)
    w.write(f"@CO\tpairs_fixture.py --replicate {k_copies} of {os.path.basename(bam)}\n")
    with open(out + ".chrom.sizes", "w") as f:
        for c, n in sizes.items():
            f.write(f"{c}\t{n * k_copies}\n")

    def shift_tag(tag, k):
        # SA:Z:chr,pos,strand,CIGAR,mapq,NM;...  XA:Z:chr,+pos,CIGAR,NM;...
        head, body = tag[:5], tag[5:]
        items = []
        for it in body.split(";"):
            if not it:
                continue
            f = it.split(",")
            off = k * sizes[f[0]]
            if head == "XA:Z:":
                f[1] = f[1][0] + str(int(f[1][1:]) + off)
            else:
                f[1] = str(int(f[1]) + off)
            items.append(",".join(f))
        return head + ";".join(items) + ";"

    for k in range(k_copies):
        buf = []
        for rec in records:
            r = list(rec)
            r[0] = f"{r[0]}:{k}"
            if k:
                if r[2] != "*":
                    r[3] = str(int(r[3]) + k * sizes[r[2]])
                mate = r[2] if r[6] == "=" else r[6]
                if mate != "*":
                    r[7] = str(int(r[7]) + k * sizes[mate])
                for i in range(11, len(r)):
                    if r[i].startswith(("SA:Z:", "XA:Z:")):
                        r[i] = shift_tag(r[i], k)
            buf.append("\t".join(r) + "\n")
        w.writelines(buf)
    w.close()
    if wr.wait() != 0:
        sys.exit("samtools view failed")


def main():
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out-dir", required=True)
    ap.add_argument("--n-pairs", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=2, help="reads (default 2)")
    ap.add_argument("--genome-seed", type=int, default=1, help="genome (default 1)")
    ap.add_argument("--genome-scale", type=int, default=1,
                    help="multiply the chromosome lengths (benchmarks; default 1)")
    ap.add_argument("--read-len", type=int, default=100)
    ap.add_argument("--no-truth", action="store_true", help="do not write truth.tsv")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--bam", default="sim.bam", help="name of the BAM in --out-dir")
    ap.add_argument("--no-align", action="store_true", help="only FASTA/FASTQ/truth")
    ap.add_argument("--also-nom", action="store_true", help="also sim.noM.bam by bwa mem -SP5")
    ap.add_argument("--replicate", type=int, default=0, metavar="K")
    ap.add_argument("--replicate-out", metavar="BAM")
    a = ap.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)
    genome, repeats = make_genome(a.genome_seed, a.genome_scale)
    chunks = simulate(genome, repeats, a.n_pairs, a.seed, a.read_len)
    write_outputs(a.out_dir, genome, repeats, chunks, truth=not a.no_truth)
    if a.no_align:
        return
    run("bwa index genome.fa 2> bwa_index.log", a.out_dir)
    align(a.out_dir, a.threads, a.bam, "-SP5M")
    if a.also_nom:
        align(a.out_dir, a.threads, a.bam.replace(".bam", ".noM.bam"), "-SP5")
    if a.replicate:
        if not a.replicate_out:
            sys.exit("--replicate needs --replicate-out")
        replicate(os.path.join(a.out_dir, a.bam), a.replicate, a.replicate_out, a.threads)


if __name__ == "__main__":
    main()
