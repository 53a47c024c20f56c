#!/usr/bin/env bash
# The README's speed and table figures, from one run on the machine at hand (about 17 minutes on
# two idle cores). Prints each figure with the command behind it; nothing is written outside
# target/ and $OUT (default: a temporary folder). ONLY="showcase python" runs just those
# sections (bench, tables, load, showcase, fit, mitsuba, python), for re-measuring what changed.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-$(mktemp -d)}
export CARGO_TERM_COLOR=never

echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo), load $(cut -d' ' -f1-3 /proc/loadavg)"
cargo build --release --locked -p woven-cli -q
woven=$(cd "${CARGO_TARGET_DIR:-target}/release" && pwd)/woven
venv=${MITSUBA_VENV:-target/mitsuba-venv}
want() { [ -z "${ONLY:-}" ] || [[ " $ONLY " == *" $1 "* ]]; }

if want bench; then
echo
echo "== criterion: cargo bench -p woven (fiber, cloth, table), -p woven-cli (eval), -p woven-render (render)"
cargo bench --locked -p woven -p woven-cli -p woven-render 2>&1 | grep -E "^[a-z_0-9]+/|time:|thrpt:" | tee "$OUT/bench.txt"

echo
fi

if want tables; then
echo "== tables: woven tabulate -m M -o M.wtab --report (wall time, file size, accuracy by band)"
smooth="$OUT/smooth-sateen.toml"
$woven materials --show polyester-sateen | sed 's/^roughness = 0.05/roughness = 0.02/' > "$smooth"
grep -q '^roughness = 0.02' "$smooth"
for m in polyester-sateen belt-cloth silk "$smooth"; do
  name=$(basename "$m" .toml)
  TIMEFORMAT="   build+report: %R s wall, %U s user"
  time $woven tabulate -m "$m" -o "$OUT/$name.wtab" --report
  echo
done
fi

if want load; then
echo "== load: woven eval --table on 10^6 rows, and the exact belt cloth on 10^3 rows"
python3 - "$OUT/dirs.csv" <<'PY'
import math, random, sys
random.seed(1)
with open(sys.argv[1], "w") as f:
    f.write("theta_i,phi_i,theta_r,phi_r\n")
    for _ in range(10**6):
        f.write("%.6f,%.6f,%.6f,%.6f\n" % (math.acos(random.random()), 2 * math.pi * random.random(),
                                          math.acos(random.random()), 2 * math.pi * random.random()))
PY
TIMEFORMAT="   eval --table sateen, 10^6 rows: %R s wall"
time $woven eval --table "$OUT/polyester-sateen.wtab" --input "$OUT/dirs.csv" -o "$OUT/t.csv"
head -1001 "$OUT/dirs.csv" > "$OUT/dirs1k.csv"
TIMEFORMAT="   eval exact belt-cloth, 10^3 rows: %R s wall, %U s user"
time $woven eval -m belt-cloth --input "$OUT/dirs1k.csv" -o "$OUT/b.csv"
TIMEFORMAT="   eval exact silk, 10^3 rows: %R s wall, %U s user"
time $woven eval -m silk --input "$OUT/dirs1k.csv" -o "$OUT/s.csv"
TIMEFORMAT="   woven gonio (the goniometer job): %R s wall"
(cd "$OUT" && time "$woven" gonio > /dev/null)
fi

if want showcase; then
echo
echo "== bare woven: the showcase render, with a cold table cache (tables built) and a warm one"
TIMEFORMAT="   bare woven, cold cache: %R s wall"
(cd "$OUT" && time XDG_CACHE_HOME="$OUT/cache" "$woven")
TIMEFORMAT="   bare woven, warm cache: %R s wall"
(cd "$OUT" && time XDG_CACHE_HOME="$OUT/cache" "$woven")
cp "$OUT/woven-out/showcase.png" "$OUT/showcase.png"
fi

if want fit; then
echo
echo "== woven fit --model cloth: the issue's speed cases (wall and user time, both cores)"
fit() {
  local label=$1; shift
  TIMEFORMAT="   $label: %R s wall, %U s user"
  time $woven fit --model cloth "$@" -o "$OUT/fit.toml" > "$OUT/fit.log" 2>&1
}
fit "CUReT linen (205 points), one orientation (--init polyester-sateen)" \
  --data 'data/curet/abrdf.dat#linen' --init polyester-sateen
fit "CUReT linen (205 points), twisted (--init belt-cloth)" \
  --data 'data/curet/abrdf.dat#linen' --init belt-cloth
fit "CUReT linen (205 points), isotropic (--init silk)" \
  --data 'data/curet/abrdf.dat#linen' --init silk
fit "MERL white-fabric grid (3757 points x RGB), twisted (--init belt-cloth)" \
  --data data/merl/white-fabric.grid.csv --init belt-cloth
fi

if want mitsuba; then
echo
echo "== woven render against Mitsuba 3 (scripts/mitsuba/speed.sh: the comparison scenes at 512x512, 64 spp, and the speed scenes; needs scripts/mitsuba/ci.sh's venv)"
if [ -x "$venv/bin/python" ]; then
  WOVEN_BIN="$woven" PYTHON="$venv/bin/python" bash scripts/mitsuba/speed.sh
else
  echo "   (skipped: no Mitsuba venv at $venv; run bash scripts/mitsuba/ci.sh first)"
fi
fi

if want python; then
echo
echo "== Python package and Mitsuba plugin (scripts/python/bench.py; needs scripts/python/ci.sh's venv)"
if [ -x "$venv/bin/python" ] && "$venv/bin/python" -c "import woven, mitsuba" 2>/dev/null; then
  "$venv/bin/python" scripts/python/bench.py --rust
  "$venv/bin/python" scripts/python/bench.py --mitsuba
else
  echo "   (skipped: no venv with woven and mitsuba at $venv; run bash scripts/python/ci.sh first)"
fi
fi

echo "results in $OUT"
