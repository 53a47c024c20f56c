#!/usr/bin/env python3
"""docs/python.md's Mitsuba example: `woven render`'s built-in showcase, as it is, rendered by
Mitsuba 3 with the woven plugin. It is `python -m woven.mitsuba showcase`, unchanged:

    python scripts/python/example_mitsuba.py -o docs/img/python-mitsuba.png [--spp N]
        [--width W --height H] [--variant V]

The library reads and checks the showcase (its camera and inset, its draped meshes with their
uv in metres along weft and warp, its materials and every key, its Preetham sun and sky baked
as `woven render` bakes them), and woven.mitsuba translates it: `woven_path` carries the camera
ray's footprint, so `detail = "auto"` and the footprint filter work as in `woven render`.
"""

import sys

from woven.mitsuba.__main__ import main

if __name__ == "__main__":
    sys.exit(main(["showcase", *sys.argv[1:]]))
