#!/usr/bin/env python3
"""Peak memory of `contactmap serve` under load, by --tile-cache (docs/serve.md, "Memory").

    python3 scripts/serve_memory.py BIN CACHE CLIENTS    # in a folder holding big.mcool

CLIENTS threads walk the zoom walk of scripts/bench_serve.py in their own orders; prints the time,
the errors and the server's VmHWM / VmRSS (Linux /proc).
"""
import http.client, json, sys, threading, subprocess, time, random
binary, cache, clients = sys.argv[1], sys.argv[2], int(sys.argv[3])
p = subprocess.Popen([binary, "serve", "big.mcool", "--port", "0", "--tile-cache", cache], stderr=subprocess.PIPE, text=True)
for line in p.stderr:
    if "http://" in line:
        port = int(line.strip().rstrip("/").rsplit(":", 1)[1]); break
threading.Thread(target=p.stderr.read, daemon=True).start()
c = http.client.HTTPConnection("127.0.0.1", port)
c.request("GET", "/api/v1/tileset_info/?d=big"); info = json.loads(c.getresponse().read())["big"]
res = sorted(info["resolutions"], reverse=True); L = info["max_pos"][0]; f = int(L * 0.37); ids = []
for z, r in enumerate(res):
    s = 256 * r; n = -(-L // s); cs = [f // s]
    if z >= len(res) - 6: cs += [f // s + 5, f // s + 10, f // s + 15]
    for cc in cs:
        for x in range(cc - 2, cc + 3):
            for y in range(cc - 2, cc + 3):
                if 0 <= x < n and 0 <= y < n and (z, x, y) not in ids: ids.append((z, x, y))
errors = []
def client(seed):
    order = ids[:]; random.Random(seed).shuffle(order)
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=300)
    for z, x, y in order:
        conn.request("GET", f"/api/v1/tiles/?d=big.{z}.{x}.{y}"); r = conn.getresponse(); r.read()
        if r.status != 200: errors.append(r.status)
t = time.time(); th = [threading.Thread(target=client, args=(s,)) for s in range(clients)]
[x.start() for x in th]; [x.join() for x in th]
hwm = [l for l in open(f"/proc/{p.pid}/status") if l.startswith(("VmHWM", "VmRSS"))]
print(f"--tile-cache {cache}: {clients} clients x {len(ids)} tiles in {time.time()-t:.1f} s, errors {len(errors)}; " + " ".join(h.split()[0] + h.split()[1] + "kB" for h in hwm))
p.terminate(); p.wait()
