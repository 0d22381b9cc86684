"""Print the layout of a Juicer .hic file (v8 / v9): header, master index, matrix metadata (block
size, columns, blocks per resolution), expected-value vectors and the normalisation-vector index.
Independent of contactmap (plain Python, struct + zlib), to check what another writer chose and
what ours wrote.  Usage: python scripts/hic_inspect.py FILE.hic [--json]"""
import json
import struct
import sys


class R:
    def __init__(self, data, pos=0):
        self.d, self.p = data, pos

    def take(self, fmt):
        v = struct.unpack_from("<" + fmt, self.d, self.p)
        self.p += struct.calcsize("<" + fmt)
        return v[0] if len(v) == 1 else v

    def s(self):
        end = self.d.index(b"\0", self.p)
        v = self.d[self.p:end].decode()
        self.p = end + 1
        return v


def inspect(path):
    data = open(path, "rb").read()
    r = R(data)
    assert r.d[:4] == b"HIC\0"
    r.p = 4
    version = r.take("i")
    long_ = "q" if version >= 9 else "i"
    value = "f" if version >= 9 else "d"
    out = {"version": version, "footer_position": r.take("q"), "genome": r.s()}
    if version >= 9:
        out["nvi_position"], out["nvi_length"] = r.take("q"), r.take("q")
    out["attributes"] = {r.s(): r.s() for _ in range(r.take("i"))}
    out["chroms"] = [(r.s(), r.take(long_)) for _ in range(r.take("i"))]
    out["resolutions"] = [r.take("i") for _ in range(r.take("i"))]
    out["frag_resolutions"] = [r.take("i") for _ in range(r.take("i"))]
    r.p = out["footer_position"]
    out["n_bytes_v5"] = r.take(long_)
    master = [(r.s(), r.take("q"), r.take("i")) for _ in range(r.take("i"))]
    out["master"] = master
    expected = []
    for _ in range(r.take("i")):
        unit, bin_size = r.s(), r.take("i")
        n = r.take(long_)
        values = [r.take(value) for _ in range(n)]
        factors = [(r.take("i"), r.take(value)) for _ in range(r.take("i"))]
        expected.append({"unit": unit, "bin_size": bin_size, "values": values, "factors": factors})
    out["expected"] = expected
    norm_expected = []
    for _ in range(r.take("i")):
        kind, unit, bin_size = r.s(), r.s(), r.take("i")
        n = r.take(long_)
        values = [r.take(value) for _ in range(n)]
        factors = [(r.take("i"), r.take(value)) for _ in range(r.take("i"))]
        norm_expected.append({"type": kind, "unit": unit, "bin_size": bin_size, "values": values,
                              "factors": factors})
    out["norm_expected"] = norm_expected
    index = []
    for _ in range(r.take("i")):
        index.append({"type": r.s(), "chrom": r.take("i"), "unit": r.s(), "bin_size": r.take("i"),
                      "position": r.take("q"), "n_bytes": r.take(long_)})
    out["norm_index"] = index
    matrices = []
    for key, pos, size in master:
        m = R(data, pos)
        c1, c2, n_res = m.take("i"), m.take("i"), m.take("i")
        levels = []
        for _ in range(n_res):
            unit, res_idx, total = m.s(), m.take("i"), m.take("f")
            m.take("i"), m.take("f"), m.take("f")
            bin_size, block_size, columns, n_blocks = m.take("i"), m.take("i"), m.take("i"), m.take("i")
            blocks = [(m.take("i"), m.take("q"), m.take("i")) for _ in range(n_blocks)]
            levels.append({"unit": unit, "res_idx": res_idx, "sum": total, "bin_size": bin_size,
                           "block_size": block_size, "columns": columns, "n_blocks": n_blocks,
                           "numbers": [b[0] for b in blocks][:8]})
        matrices.append({"key": key, "c1": c1, "c2": c2, "levels": levels})
    out["matrices"] = matrices
    return out


if __name__ == "__main__":
    info = inspect(sys.argv[1])
    if "--json" in sys.argv:
        json.dump(info, sys.stdout)
    else:
        for k, v in info.items():
            if k in ("matrices", "expected", "norm_expected"):
                for item in v:
                    text = json.dumps(item)
                    print(k, text[:400])
            else:
                print(k, json.dumps(v)[:600])
