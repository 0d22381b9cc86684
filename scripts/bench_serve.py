#!/usr/bin/env python3
"""`contactmap serve` against clodius 0.22.2 (what higlass-server runs) on a zoom walk (issue 54).

    /tmp/clodius_venv/bin/python scripts/bench_serve.py BIN MAP.mcool [--clients 32] [--rounds 3]

The walk: a viewer's path from the whole genome down to the finest resolution around one point
of the diagonal, a 5 x 5 block of tiles at each zoom level, then panning along the diagonal at
the six finest levels (at least 500 distinct tiles). Each tile is asked for once, in order:
- clodius: `clodius.tiles.cooler.tiles(path, [id])` in this Python process, after a
  `tileset_info` call that opened the file (what higlass-server does per request, without the
  HTTP around it);
- contactmap: `BIN serve MAP --tile-cache 0` (every tile computed), one keep-alive HTTP
  connection, one request per tile: the latency is from the request to the answer's last byte
  (HTTP and the JSON text included; the client's parsing of it is not, as clodius' answer is a
  Python dict that no one parses).
Both answers are compared tile by tile (dtype, the base64 bytes, min / max). Then 32 clients at
once walk the same tiles in their own orders (a bounded load: each asks each tile once), with the
cache on (its default 256 MB), counting errors and the slowest answer.
"""

import argparse
import http.client
import json
import random
import statistics
import subprocess
import sys
import threading
import time

import clodius
import clodius.tiles.cooler as hgc


def walk(info):
    """The tile ids (without UID) of the zoom walk."""
    resolutions = sorted(info["resolutions"], reverse=True)
    length = info["max_pos"][0]
    focus = int(length * 0.37)
    ids = []
    for z, r in enumerate(resolutions):
        span = 256 * r
        n = -(-length // span)
        centres = [focus // span]
        if z >= len(resolutions) - 6:
            centres += [focus // span + 5, focus // span + 10, focus // span + 15]
        for c in centres:
            for x in range(c - 2, c + 3):
                for y in range(c - 2, c + 3):
                    if 0 <= x < n and 0 <= y < n and (z, x, y) not in ids:
                        ids.append((z, x, y))
    return [f"{z}.{x}.{y}" for z, x, y in ids]


def percentile(values, q):
    values = sorted(values)
    return values[min(len(values) - 1, int(round(q / 100 * (len(values) - 1))))]


def start_server(binary, path, cache):
    proc = subprocess.Popen(
        [binary, "serve", path, "--port", "0", "--tile-cache", cache],
        stderr=subprocess.PIPE,
        text=True,
    )
    uid = None
    for line in proc.stderr:
        if " <- " in line:
            uid = line.split(": ", 1)[1].split(" <- ")[0]
        if "http://" in line:
            port = int(line.strip().rstrip("/").rsplit(":", 1)[1])
            threading.Thread(target=lambda: proc.stderr.read(), daemon=True).start()
            return proc, port, uid
    raise SystemExit("serve did not start")


def fetch_raw(conn, uid, tile):
    """The answer's bytes (the latency measured: the request until its last byte)."""
    conn.request("GET", f"/api/v1/tiles/?d={uid}.{tile}")
    response = conn.getresponse()
    body = response.read()
    if response.status != 200:
        raise RuntimeError(f"{tile}: HTTP {response.status}: {body[:200]}")
    return body


def fetch(conn, uid, tile):
    return json.loads(fetch_raw(conn, uid, tile))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("binary")
    parser.add_argument("map")
    parser.add_argument("--clients", type=int, default=32)
    args = parser.parse_args()
    assert clodius.__version__ == "0.22.2", clodius.__version__

    info = hgc.tileset_info(args.map)
    tiles = walk(info)
    print(f"{args.map}: {len(info['resolutions'])} resolutions, walk of {len(tiles)} tiles")

    # clodius, one process, file already open
    theirs, their_t = {}, []
    for tile in tiles:
        t = time.perf_counter()
        answer = hgc.tiles(args.map, [f"a.{tile}"])
        their_t.append(time.perf_counter() - t)
        theirs[tile] = answer[0][1] if answer else None

    # contactmap serve, no cache: every tile computed
    proc, port, uid = start_server(args.binary, args.map, "0")
    conn = http.client.HTTPConnection("127.0.0.1", port)
    fetch(conn, uid, tiles[0])  # the connection's first request
    ours, our_t = {}, []
    for tile in tiles:
        t = time.perf_counter()
        body = fetch_raw(conn, uid, tile)
        our_t.append(time.perf_counter() - t)
        ours[tile] = json.loads(body).get(f"{uid}.{tile}")
    proc.terminate()
    proc.wait()

    same = 0
    for tile in tiles:
        a, b = ours[tile], theirs[tile]
        if a is None or b is None:
            same += a is None and b is None
        elif a["dtype"] == b["dtype"] and a["dense"] == b["dense"] and (
            str(a["min_value"]), str(a["max_value"])
        ) == (str(b["min_value"]), str(b["max_value"])):
            same += 1
        else:
            print(f"  differs: {tile}")
    print(f"identical tiles: {same} of {len(tiles)}")

    for name, times in (("clodius tiles()", their_t), ("contactmap serve", our_t)):
        print(
            f"{name}: p50 {percentile(times, 50) * 1e3:.2f} ms, p95 {percentile(times, 95) * 1e3:.2f} ms, "
            f"mean {statistics.mean(times) * 1e3:.2f} ms, total {sum(times):.2f} s"
        )
    slowest = sorted(zip(our_t, tiles), reverse=True)[:8]
    print("contactmap's slowest:", ", ".join(f"{t}: {dt * 1e3:.1f} ms" for dt, t in slowest))
    print(
        f"ratio: p50 {percentile(their_t, 50) / percentile(our_t, 50):.1f}x, "
        f"p95 {percentile(their_t, 95) / percentile(our_t, 95):.1f}x"
    )

    # a bounded load: clients walking the tiles at once, cache on
    proc, port, uid = start_server(args.binary, args.map, "256M")
    errors, slowest, done = [], [0.0], [0]
    lock = threading.Lock()

    def client(seed):
        order = tiles[:]
        random.Random(seed).shuffle(order)
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
        for tile in order:
            t = time.perf_counter()
            try:
                answer = fetch(conn, uid, tile)
                if f"{uid}.{tile}" not in answer:
                    raise RuntimeError(f"{tile}: missing")
            except Exception as e:  # noqa: BLE001
                with lock:
                    errors.append(str(e))
                conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
                continue
            dt = time.perf_counter() - t
            with lock:
                slowest[0] = max(slowest[0], dt)
                done[0] += 1

    t = time.perf_counter()
    threads = [threading.Thread(target=client, args=(s,)) for s in range(args.clients)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    elapsed = time.perf_counter() - t
    proc.terminate()
    proc.wait()
    print(
        f"{args.clients} clients x {len(tiles)} tiles: {done[0]} answered in {elapsed:.1f} s "
        f"({done[0] / elapsed:.0f} tiles/s), {len(errors)} errors, slowest {slowest[0] * 1e3:.0f} ms"
    )
    if errors:
        print("  first errors:", errors[:3])
    sys.exit(1 if errors or same != len(tiles) else 0)


main()
