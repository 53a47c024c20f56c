"""A photograph of a glTF swatch in three.js, in headless Chromium (Playwright).

    python scripts/exports/screenshot.py --three NODE_PREFIX/node_modules/three \\
        --swatch target/exports/screenshot/swatch.gltf --out docs/img/gltf-swatch.png

Serves scripts/exports/swatch.html, three.js under /three/ and the swatch's folder under
/swatch/ on a free local port, opens the page in Chromium (CHROMIUM, default /usr/bin/chromium;
WebGL by SwiftShader, no GPU needed), waits for the swatch to load and render, prints what
three.js made of the material (its type and the extensions' maps) and saves the page. Exits 1
when the page reports an error or the material lacks what the file carries.
"""

import argparse
import functools
import http.server
import json
import os
import sys
import threading

from playwright.sync_api import sync_playwright

HERE = os.path.dirname(os.path.abspath(__file__))


class Handler(http.server.SimpleHTTPRequestHandler):
    """/ the page, /three/ three.js, /swatch/ the swatch's folder."""

    def __init__(self, *args, three, swatch, **kwargs):
        self.roots = {"/three/": three, "/swatch/": swatch}
        super().__init__(*args, directory=HERE, **kwargs)

    def translate_path(self, path):
        path = path.split("?", 1)[0]
        if path in ("/", "/index.html"):
            return os.path.join(HERE, "swatch.html")
        for prefix, root in self.roots.items():
            if path.startswith(prefix):
                rest = http.server.SimpleHTTPRequestHandler.translate_path(self, "/" + path[len(prefix):])
                return os.path.join(root, os.path.relpath(rest, HERE))
        return super().translate_path(path)

    def log_message(self, *args):
        pass


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--three", required=True, help="the `three` package's folder (node_modules/three)")
    ap.add_argument("--swatch", required=True, help="the .gltf file")
    ap.add_argument("--out", required=True, help="the PNG to write")
    ap.add_argument("--width", type=int, default=800)
    ap.add_argument("--height", type=int, default=500)
    args = ap.parse_args()

    handler = functools.partial(
        Handler, three=os.path.abspath(args.three), swatch=os.path.dirname(os.path.abspath(args.swatch))
    )
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    url = (
        f"http://127.0.0.1:{server.server_port}/?file={os.path.basename(args.swatch)}"
        f"&w={args.width}&h={args.height}"
    )
    chromium = os.environ.get("CHROMIUM", "/usr/bin/chromium")
    flags = ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"]
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, headless=True, args=flags)
        page = browser.new_page(viewport={"width": args.width, "height": args.height})
        messages = []
        page.on("console", lambda m: messages.append(f"{m.type}: {m.text}"))
        page.on("pageerror", lambda e: messages.append(f"page error: {e}"))
        page.goto(url)
        page.wait_for_function("window.wovenDone || window.wovenError", timeout=120_000)
        error = page.evaluate("window.wovenError")
        material = page.evaluate("window.wovenMaterial")
        if not error:
            page.screenshot(path=args.out)
        browser.close()
    server.shutdown()
    for m in messages:
        print(m)
    if error:
        print(f"error: the page could not show the swatch: {error}", file=sys.stderr)
        return 1
    print("three.js's material:", json.dumps(material))
    wanted = ["anisotropyMap", "sheenColorMap", "sheenRoughnessMap", "specularIntensityMap",
              "specularColorMap", "roughnessMap", "tangents"]
    missing = [k for k in wanted if not material.get(k)]
    if material.get("type") != "MeshPhysicalMaterial" or missing:
        print(f"error: three.js did not read {missing or material.get('type')}", file=sys.stderr)
        return 1
    print(f"wrote {args.out} ({args.width}×{args.height})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
