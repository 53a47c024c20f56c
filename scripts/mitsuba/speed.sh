#!/usr/bin/env bash
# woven's renderer against Mitsuba 3 in speed, every speed scene in one run (docs/render.md,
# "Speed"): the peer-comparison scenes (scenes/compare: the woven plane, the diffuse plane, the
# furnace sphere) and the woven plane grown to fill the frame (scenes/speed/filled-plane.toml:
# every ray shades) at 512 × 512 and 64 spp in Mitsuba's llvm_ad_rgb and scalar_rgb and in
# `woven render`; then, woven alone, the built-in showcase at real thread counts and the tilted
# sateen plane at cloth level beside its yarn-level twin (scenes/speed). Mitsuba's time is its
# warm `mi.render`, woven's its whole command (scripts/mitsuba/bench.py). Ends with a Markdown
# table of samples per second and the ratios.
#
#   bash scripts/mitsuba/speed.sh          # WOVEN_BIN (default target/release/woven, built if
#                                          # missing); PYTHON (default target/mitsuba-venv's)
set -euo pipefail
cd "$(dirname "$0")/../.."
woven=${WOVEN_BIN:-target/release/woven}
python=${PYTHON:-target/mitsuba-venv/bin/python}
if [ ! -x "$woven" ]; then
  cargo build --release --locked -p woven-cli -q
fi
if ! "$python" -c "import mitsuba" 2>/dev/null; then
  echo "speed.sh: $python cannot import mitsuba (bash scripts/mitsuba/ci.sh makes the venv)" >&2
  exit 2
fi
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
exec "$python" scripts/mitsuba/bench.py --woven "$woven" --variant llvm_ad_rgb,scalar_rgb \
  --scene scenes/compare/roughplastic-plane.toml \
  --scene scenes/compare/diffuse-plane.toml \
  --scene scenes/compare/furnace-sphere.toml \
  --scene scenes/speed/filled-plane.toml \
  --woven-only showcase \
  --woven-only scenes/speed/tilted-sateen.toml \
  --woven-only scenes/speed/tilted-sateen-yarns.toml
