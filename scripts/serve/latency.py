"""The explorer's view-update latency over HTTP, as the page sees it (docs/serve.md).

    target/release/woven serve --port 8321 &
    python3 scripts/serve/latency.py http://127.0.0.1:8321/ [repeats] [server-pid]

For each preset and each kind of change, POSTs /api/views (all views, light at θi = 45°)
`repeats` times (default 7) after one warm-up and prints the median and largest times to the
first view (the in-plane curve) and to the last (the 64² hemisphere map), measured from the
request to the line that carries it. The changes: "click", the same material again (a new
incidence: the server keeps the built model); "yarn slider", yarn.slope_std different each time
(the server keeps the fiber and its β table); "fiber slider", fiber.roughness different each
time (everything is built anew). Given the server's process id (Linux), also the median CPU time the server spent
per update (all threads): on a machine shared with other work, CPU time / cores is what the
wall time would be with the cores to itself. Standard library only.
"""

import json
import os
import statistics
import sys
import time
import urllib.request


def views(url, material):
    body = json.dumps({"material": material, "theta_i_deg": 45, "phi_i_deg": 0}).encode()
    req = urllib.request.Request(url + "api/views", data=body, headers={"content-type": "application/json"})
    start = time.perf_counter()
    first = None
    with urllib.request.urlopen(req) as r:
        for line in r:
            kind = json.loads(line)["kind"]
            if kind != "progress" and first is None:
                first = time.perf_counter() - start
            if kind == "done":
                return first, time.perf_counter() - start
    raise RuntimeError("no done line")


def cpu_seconds(pid):
    """User + system CPU time of process `pid`, seconds (Linux /proc)."""
    if pid is None:
        return 0.0
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def main():
    url = sys.argv[1] if len(sys.argv) > 1 else "http://127.0.0.1:8321/"
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    pid = int(sys.argv[3]) if len(sys.argv) > 3 else None
    with urllib.request.urlopen(url + "api/presets") as r:
        presets = json.load(r)["presets"]
    print(f"{'preset':<18} {'change':<13} {'first view, median / max':>26} {'all views, median / max':>26}"
          f" {'server CPU per update':>22}")
    for p in presets:
        for change in ["click", "yarn slider", "fiber slider"]:
            def material(k):
                m = json.loads(json.dumps(p["material"]))
                if change == "yarn slider":
                    m["yarn"]["slope_std"] = round(0.3 + 0.01 * k, 4)
                elif change == "fiber slider":
                    m["fiber"]["roughness"] = round(0.05 + 0.005 * k, 4)
                return m
            views(url, material(0))
            runs, cpus = [], []
            for k in range(1, repeats + 1):
                c0 = cpu_seconds(pid)
                runs.append(views(url, material(k)))
                cpus.append(1e3 * (cpu_seconds(pid) - c0))
            firsts = [1e3 * a for a, _ in runs]
            alls = [1e3 * b for _, b in runs]
            cpu = f"{statistics.median(cpus):>19.0f} ms" if pid else f"{'-':>22}"
            print(f"{p['name']:<18} {change:<13} {statistics.median(firsts):>13.0f} / {max(firsts):>6.0f} ms"
                  f" {statistics.median(alls):>15.0f} / {max(alls):>6.0f} ms {cpu}", flush=True)


if __name__ == "__main__":
    main()
