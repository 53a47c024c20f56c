#!/usr/bin/env bash
# CI step: every woven preset exported as OpenPBR (MaterialX) and as glTF (docs/export.md), each
# read by its ecosystem's own validator.
#
#   WOVEN_BIN=target/release/woven bash scripts/exports/ci.sh   # exit 0 = passed (or skipped, not in CI)
#
# Installs MaterialX 1.39 from PyPI into a virtual environment (WOVEN_EXPORTS_VENV, default
# target/exports-venv) and the Khronos glTF validator from npm (`gltf-validator`, into
# target/exports-node; Debian's nodejs and npm are installed when run as root and node or npm is
# missing). Then `woven export --format openpbr` and `--format gltf` write every preset `woven
# materials` lists into target/exports, both formats from one projection (--also-output; each
# preset's yarn tabulated on the draft grid, --draft-tables, in a table cache of its own,
# target/exports/cache, and its textures at 8 texels a cell: the documents' structure is the same
# as at the default grid, in less time; two presets at once), and:
# - scripts/exports/validate_mtlx.py reads each .mtlx with MaterialX's standard libraries
#   loaded: doc.validate(), every node defined by them, every texture present, the GLSL shader
#   generated;
# - scripts/exports/validate_gltf.mjs runs the validator over each .gltf with its .bin and
#   textures: any error fails.
# Outside CI it skips, with a message and exit 0, when python3's venv, PyPI, node, npm or the npm
# registry cannot be had; with the environment variable CI set (to anything but "", 0 or false)
# each of these fails the step (exit 1) with a message naming what is missing. Fails (exit 1)
# when an export fails or a validator reports an error.
set -euo pipefail
cd "$(dirname "$0")/../.."

MATERIALX_VERSION='1.39.*'
GLTF_VALIDATOR_VERSION=2.0.0-dev.3.10
VENV=${WOVEN_EXPORTS_VENV:-target/exports-venv}
NODE_PREFIX=${WOVEN_EXPORTS_NODE:-target/exports-node}
OUT=${WOVEN_EXPORTS_OUT:-target/exports}
WOVEN=${WOVEN_BIN:-${CARGO_TARGET_DIR:-target}/release/woven}

in_ci() { case ${CI:-} in '' | 0 | [Ff]alse | FALSE) return 1 ;; *) return 0 ;; esac; }
# Under CI nothing may be left out: what would be skipped fails the step.
skip() {
  if in_ci; then
    printf 'FAIL (exports and their validators): %s\nCI is set (CI=%s), so this step may not skip: install the above, or run without CI to skip it.\n' "$*" "$CI" >&2
    exit 1
  fi
  printf 'SKIP (exports and their validators): %s\n' "$*"
  exit 0
}

[ -x "$WOVEN" ] || { echo "error: no woven binary at $WOVEN (cargo build --release -p woven-cli, or set WOVEN_BIN)" >&2; exit 1; }
start=$SECONDS

# MaterialX from PyPI.
command -v python3 >/dev/null 2>&1 || skip "no python3 on this machine"
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV" 2>/dev/null || { rm -rf "$VENV"; skip "python3 -m venv failed (Debian: apt-get install python3-venv)"; }
fi
if ! "$VENV/bin/python" -c "import MaterialX as mx; assert mx.getVersionString().startswith('1.39.')" 2>/dev/null; then
  echo "installing MaterialX==$MATERIALX_VERSION into $VENV"
  "$VENV/bin/pip" install -q --disable-pip-version-check --timeout 30 --retries 2 "MaterialX==$MATERIALX_VERSION" \
    || skip "pip could not install MaterialX==$MATERIALX_VERSION into $VENV (no PyPI, or no wheel for this platform: give pip a reachable index, PIP_INDEX_URL)"
fi

# Node and the glTF validator from npm.
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "installing Debian's nodejs and npm"
    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nodejs npm >/dev/null; } \
      || skip "apt-get could not install Debian's nodejs and npm (apt-get install nodejs npm as root, with Debian's archive reachable)"
  else
    skip "no node and npm (Debian: apt-get install nodejs npm as root)"
  fi
fi
if [ ! -f "$NODE_PREFIX/node_modules/gltf-validator/package.json" ] \
   || ! grep -q "\"version\": \"$GLTF_VALIDATOR_VERSION\"" "$NODE_PREFIX/node_modules/gltf-validator/package.json"; then
  echo "installing gltf-validator@$GLTF_VALIDATOR_VERSION into $NODE_PREFIX"
  mkdir -p "$NODE_PREFIX"
  npm install --prefix "$NODE_PREFIX" --no-audit --no-fund --silent "gltf-validator@$GLTF_VALIDATOR_VERSION" \
    || skip "npm could not install gltf-validator@$GLTF_VALIDATOR_VERSION (no npm registry: set npm's registry, or install it into $NODE_PREFIX by hand)"
fi
echo "tools ready in $((SECONDS - start)) s (MaterialX $("$VENV/bin/python" -c 'import MaterialX as mx; print(mx.getVersionString())'), node $(node --version), gltf-validator $GLTF_VALIDATOR_VERSION)"

# Every woven preset: the first column of `woven materials`' first table.
mapfile -t presets < <("$WOVEN" materials | awk 'NR > 1 && NF == 0 { exit } NR > 1 { print $1 }')
[ "${#presets[@]}" -gt 0 ] || { echo "error: \`woven materials\` listed no presets" >&2; exit 1; }
rm -rf "$OUT/openpbr" "$OUT/gltf"
mkdir -p "$OUT/openpbr" "$OUT/gltf" "$OUT/logs"
export WOVEN OUT
export XDG_CACHE_HOME=$PWD/$OUT/cache
export_preset() {
  local p=$1
  # Both formats from one projection (--also-output): the projection is most of the time. A
  # sheer is exported with --transmission false (these formats carry no transmission yet, and
  # refuse it otherwise): its reflection, its holes black.
  "$WOVEN" export --format openpbr -m "$p" --draft-tables --texels-per-cell 8 --transmission false \
      -o "$OUT/openpbr/$p.mtlx" --also-output "$OUT/gltf/$p.gltf" >"$OUT/logs/$p.log" 2>&1 \
    || { cat "$OUT/logs/$p.log" >&2; echo "error: exporting $p failed" >&2; return 1; }
  echo "exported $p: $(grep -o 'the projection took .*' "$OUT/logs/$p.log")"
}
export -f export_preset
exports_start=$SECONDS
printf '%s\n' "${presets[@]}" | xargs -P 2 -I{} bash -c 'export_preset "$1"' _ {}
echo "${#presets[@]} presets exported as OpenPBR and glTF in $((SECONDS - exports_start)) s"

"$VENV/bin/python" scripts/exports/validate_mtlx.py "$OUT"/openpbr/*.mtlx
node scripts/exports/validate_gltf.mjs "$NODE_PREFIX" "$OUT"/gltf/*.gltf
echo "exports step: $((SECONDS - start)) s"
