#!/usr/bin/env bash
# CI step: woven in Blender's Cycles (woven.blender, docs/blender.md).
#
#   bash scripts/blender/ci.sh           # from anywhere; exit 0 = passed (or skipped, not in CI)
#
# Installs Blender's Python module (bpy 5.0.1 from PyPI: CPython 3.11, a 374 MB wheel, about
# 0.9 GB installed) with numpy and pytest into BLENDER_VENV (default target/blender-venv), and as
# root the Debian libraries bpy links (X11, Xrender, Xi, Xfixes, xkbcommon, SM/ICE, GL) when it
# does not import; installs the woven wheel scripts/python/ci.sh built (target/wheels), or builds
# it; then runs scripts/blender/test_blender.py: Cycles measured against the lobes it is given
# (a virtual goniometer), a gapped weave's layout and holes, `python -m woven.blender` on a small
# scene and its refusals, and the showcase's matte cloths against `woven render`. Needs python3.11
# (bpy 5.0 is built for it). Outside CI the step skips, with a message and exit 0, when
# python3.11, PyPI or the libraries cannot be had; with CI set (to anything but "", 0 or false)
# each of these fails it (exit 1), and so does a skipped test (scripts/ci_no_skips.py).
set -euo pipefail
cd "$(dirname "$0")/../.."

BPY_VERSION=5.0.1
VENV=${BLENDER_VENV:-target/blender-venv}
TARGET=${CARGO_TARGET_DIR:-target}

in_ci() { case ${CI:-} in '' | 0 | [Ff]alse | FALSE) return 1 ;; *) return 0 ;; esac; }
fail_in_ci() {
  in_ci || return 0
  printf 'FAIL (Blender): %s\nCI is set (CI=%s), so this step may not skip any part of it: install the above, or run without CI to skip it.\n' "$*" "$CI" >&2
  exit 1
}
skip() { fail_in_ci "$@"; printf 'SKIP (Blender): %s\n' "$*"; exit 0; }
pip_install() {
  "$VENV/bin/pip" install -q --disable-pip-version-check --timeout 60 --retries 2 "$@"
}

PYTHON=$(command -v python3.11 || true)
if [ -z "$PYTHON" ] && python3 -c 'import sys; assert sys.version_info[:2] == (3, 11)' 2>/dev/null; then
  PYTHON=$(command -v python3)
fi
[ -n "$PYTHON" ] || skip "bpy $BPY_VERSION needs CPython 3.11, and this machine has no python3.11"
t0=$(date +%s)
if [ ! -x "$VENV/bin/python" ]; then
  "$PYTHON" -m venv "$VENV" 2>/dev/null || { rm -rf "$VENV"; skip "$PYTHON -m venv failed (Debian: apt-get install python3-venv)"; }
fi
"$VENV/bin/python" -c "import numpy, pytest" 2>/dev/null || pip_install numpy pytest \
  || skip "pip could not install numpy and pytest into $VENV (no PyPI: give pip a reachable index, PIP_INDEX_URL)"
if ! "$VENV/bin/python" -c "import importlib.metadata as m; assert m.version('bpy') == '$BPY_VERSION'" 2>/dev/null; then
  echo "installing bpy==$BPY_VERSION into $VENV (a 374 MB wheel)"
  pip_install "bpy==$BPY_VERSION" \
    || skip "pip could not install bpy==$BPY_VERSION into $VENV (no PyPI, or no wheel for this platform)"
fi
if ! "$VENV/bin/python" -c "import bpy" >/dev/null 2>&1; then
  libs="libx11-6 libxrender1 libxi6 libxfixes3 libxkbcommon0 libsm6 libice6 libgl1 libxxf86vm1"
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "installing the libraries bpy links: $libs"
    # shellcheck disable=SC2086
    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $libs >/dev/null; } \
      || skip "apt-get could not install $libs, which bpy links"
  fi
  "$VENV/bin/python" -c "import bpy" >/dev/null 2>&1 \
    || skip "bpy does not import: $("$VENV/bin/python" -c 'import bpy' 2>&1 | tail -1) (Debian: apt-get install $libs)"
fi
echo "bpy $BPY_VERSION ready in $(( $(date +%s) - t0 )) s; $VENV holds $(du -sh "$VENV" | cut -f1)"

WOVEN_BIN=${WOVEN_BIN:-}
if [ -z "$WOVEN_BIN" ]; then
  cargo build --release --locked -q -p woven-cli
  WOVEN_BIN="$TARGET/release/woven"
fi
WOVEN_BIN=$(realpath -m "$WOVEN_BIN")
export WOVEN_BIN
if ! ls "$TARGET"/wheels/woven-*.whl >/dev/null 2>&1; then
  [ -x "$VENV/bin/maturin" ] || pip_install "maturin>=1.7,<2" || skip "pip could not install maturin into $VENV"
  "$VENV/bin/maturin" build --release --locked -q -m crates/woven-py/Cargo.toml -o "$TARGET/wheels" \
    --interpreter "$VENV/bin/python"
fi
"$VENV/bin/pip" install -q --disable-pip-version-check --force-reinstall --no-deps "$TARGET"/wheels/woven-*.whl

# Projections and tables go into a fresh cache folder, never the user's.
XDG_CACHE_HOME=$(mktemp -d)
export XDG_CACHE_HOME
trap 'rm -rf "$XDG_CACHE_HOME"' EXIT
"$VENV/bin/python" -m pytest -q -p no:cacheprovider -W ignore::DeprecationWarning scripts/blender/test_blender.py
echo "the Blender step took $(( $(date +%s) - t0 )) s"
