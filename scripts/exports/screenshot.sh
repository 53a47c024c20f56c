#!/usr/bin/env bash
# docs/img/gltf-swatch.png: a glTF swatch of `woven export --format gltf` in three.js, in headless
# Chromium (by hand; not in CI).
#
#   bash scripts/exports/screenshot.sh [PRESET] [YARNS_PER_UNIT]   # default: satin-charmeuse, 240
#
# Exports PRESET as a 5 cm swatch with the weave enlarged to YARNS_PER_UNIT cells per metre (so
# that a viewer at arm's length sees it; real cloth has thousands), at the default table grid and
# 32 texels a cell; installs three.js from npm (pinned, into target/exports-node, beside
# scripts/exports/ci.sh's gltf-validator) and Playwright from PyPI (scripts/serve/requirements.txt,
# into target/serve-venv, as scripts/serve/ci.sh does); then scripts/exports/screenshot.py
# photographs scripts/exports/swatch.html with Debian's Chromium (CHROMIUM to use another).
set -euo pipefail
cd "$(dirname "$0")/../.."

PRESET=${1:-satin-charmeuse}
YARNS=${2:-240}
THREE_VERSION=0.187.0
VENV=${WOVEN_SERVE_VENV:-target/serve-venv}
NODE_PREFIX=${WOVEN_EXPORTS_NODE:-target/exports-node}
WOVEN=${WOVEN_BIN:-${CARGO_TARGET_DIR:-target}/release/woven}
OUT=target/exports/screenshot

[ -x "$WOVEN" ] || { echo "error: no woven binary at $WOVEN (cargo build --release -p woven-cli)" >&2; exit 1; }
if [ ! -f "$NODE_PREFIX/node_modules/three/package.json" ] \
   || ! grep -q "\"version\": \"$THREE_VERSION\"" "$NODE_PREFIX/node_modules/three/package.json"; then
  mkdir -p "$NODE_PREFIX"
  npm install --prefix "$NODE_PREFIX" --no-audit --no-fund --silent "three@$THREE_VERSION"
fi
if [ ! -x "$VENV/bin/python" ]; then python3 -m venv "$VENV"; fi
"$VENV/bin/python" -c "import playwright" 2>/dev/null \
  || "$VENV/bin/pip" install -q --disable-pip-version-check -r scripts/serve/requirements.txt

rm -rf "$OUT" && mkdir -p "$OUT"
"$WOVEN" export --format gltf -m "$PRESET" --yarns-per-unit "$YARNS" --texels-per-cell 32 \
  -o "$OUT/swatch.gltf"
"$VENV/bin/python" scripts/exports/screenshot.py --three "$NODE_PREFIX/node_modules/three" \
  --swatch "$OUT/swatch.gltf" --out docs/img/gltf-swatch.png
