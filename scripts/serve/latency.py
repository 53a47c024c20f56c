"""The explorer's view-update latency over HTTP, as the page sees it (docs/serve.md).

    target/release/woven serve --port 8321 &
    python3 scripts/serve/latency.py http://127.0.0.1:8321/ [repeats]

For each preset, POSTs /api/views (all views, light at θi = 45°) `repeats` times (default 7)
after one warm-up and prints the median and largest times to the first view (the in-plane
curve) and to the last (the 64² hemisphere map), measured from the request to the line that
carries it. Standard library only.
"""

import json
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


def main():
    url = sys.argv[1] if len(sys.argv) > 1 else "http://127.0.0.1:8321/"
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    with urllib.request.urlopen(url + "api/presets") as r:
        presets = json.load(r)["presets"]
    print(f"{'preset':<18} {'first view, median / max':>26} {'all views, median / max':>26}")
    for p in presets:
        views(url, p["material"])
        runs = [views(url, p["material"]) for _ in range(repeats)]
        firsts = [1e3 * a for a, _ in runs]
        alls = [1e3 * b for _, b in runs]
        print(f"{p['name']:<18} {statistics.median(firsts):>13.0f} / {max(firsts):>6.0f} ms"
              f" {statistics.median(alls):>15.0f} / {max(alls):>6.0f} ms")


if __name__ == "__main__":
    main()
