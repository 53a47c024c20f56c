#!/usr/bin/env bash
# CI step: the Python package (crates/woven-py) and its Mitsuba 3 plugin (docs/python.md).
#
#   bash scripts/python/ci.sh            # from anywhere; exit 0 = passed (or skipped, not in CI)
#
# Builds the `woven` command line (the tests compare with it) and the wheel (maturin, abi3),
# installs the wheel into a virtual environment with numpy, pytest and dask, and runs
# crates/woven-py/tests. The environment is WOVEN_PY_VENV, default MITSUBA_VENV (default
# target/mitsuba-venv): the one scripts/mitsuba/ci.sh sets up, so Mitsuba is installed once for
# both steps; when Mitsuba 3.9.1 is not there this script tries to install it. Outside CI the
# Mitsuba tests skip when it cannot be had (or when Dr.Jit's LLVM backend finds no libLLVM >= 16:
# scripts/mitsuba/ci.sh installs Debian's libllvm19 as root), and the step skips, with a message
# and exit 0, when python3 or its venv module is missing, or PyPI cannot provide maturin, numpy,
# pytest and dask[distributed]. With the environment variable CI set (to anything but "", 0 or
# false) each of these fails the step (exit 1) with a message naming what is missing and how to
# get it; a test that skips fails too (crates/woven-py/tests/conftest.py,
# scripts/ci_no_skips.py). Fails (exit 1) when the wheel does not build or a test fails.
set -euo pipefail
cd "$(dirname "$0")/../.."

MITSUBA_VERSION=3.9.1
DRJIT_VERSION=1.5.0
VENV=${WOVEN_PY_VENV:-${MITSUBA_VENV:-target/mitsuba-venv}}
TARGET=${CARGO_TARGET_DIR:-target}

in_ci() { case ${CI:-} in '' | 0 | [Ff]alse | FALSE) return 1 ;; *) return 0 ;; esac; }
# Under CI nothing may be left out: what would be skipped fails the step.
fail_in_ci() {
  in_ci || return 0
  printf 'FAIL (Python package): %s\nCI is set (CI=%s), so this step may not skip any part of it: install the above, or run without CI to skip it.\n' "$*" "$CI" >&2
  exit 1
}
skip() { fail_in_ci "$@"; printf 'SKIP (Python package): %s\n' "$*"; exit 0; }
pip_install() {
  "$VENV/bin/pip" install -q --disable-pip-version-check --timeout 30 --retries 2 "$@"
}

command -v python3 >/dev/null 2>&1 || skip "no python3 on this machine"
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV" 2>/dev/null || { rm -rf "$VENV"; skip "python3 -m venv failed (Debian: apt-get install python3-venv)"; }
fi
"$VENV/bin/python" -c "import numpy, pytest" 2>/dev/null \
  || pip_install numpy pytest \
  || skip "pip could not install numpy and pytest into $VENV (no PyPI: give pip a reachable index, PIP_INDEX_URL, or install them into $VENV by hand)"
# dask's distributed scheduler: woven.batch's cluster test (a LocalCluster of two processes).
"$VENV/bin/python" -c "import dask.distributed" 2>/dev/null \
  || pip_install "dask[distributed]>=2024" \
  || skip "pip could not install dask[distributed]>=2024 into $VENV, which woven.batch's cluster test needs (no PyPI: give pip a reachable index, PIP_INDEX_URL, or install it into $VENV by hand)"
[ -x "$VENV/bin/maturin" ] || pip_install "maturin>=1.7,<2" \
  || skip "pip could not install maturin>=1.7,<2 into $VENV (no PyPI: give pip a reachable index, PIP_INDEX_URL, or install it into $VENV by hand)"
if ! "$VENV/bin/python" -c "import mitsuba; assert mitsuba.__version__ == '$MITSUBA_VERSION'" 2>/dev/null; then
  echo "installing mitsuba==$MITSUBA_VERSION into $VENV (the plugin's tests skip without it)"
  if ! pip_install "mitsuba==$MITSUBA_VERSION" "drjit==$DRJIT_VERSION"; then
    fail_in_ci "pip could not install mitsuba==$MITSUBA_VERSION drjit==$DRJIT_VERSION into $VENV, which the plugin's tests need (no PyPI, or no wheel for this platform: give pip a reachable index, PIP_INDEX_URL, or install them into $VENV by hand)"
    echo "note: mitsuba==$MITSUBA_VERSION could not be installed: the Mitsuba tests skip"
  fi
fi

WOVEN_BIN=${WOVEN_BIN:-}
if [ -z "$WOVEN_BIN" ]; then
  cargo build --release --locked -q -p woven-cli
  WOVEN_BIN="$TARGET/release/woven"
fi
# Absolute paths: the tests run from crates/woven-py.
WOVEN_BIN=$(realpath -m "$WOVEN_BIN")
VENV=$(realpath -m "$VENV")
export WOVEN_BIN

wheels="$TARGET/wheels"
rm -rf "$wheels"
"$VENV/bin/maturin" build --release --locked -q -m crates/woven-py/Cargo.toml -o "$wheels" \
  --interpreter "$VENV/bin/python"
"$VENV/bin/pip" install -q --disable-pip-version-check --force-reinstall --no-deps "$wheels"/woven-*.whl

# Tables the Mitsuba tests build go into a fresh cache folder, never the user's.
XDG_CACHE_HOME=$(mktemp -d)
export XDG_CACHE_HOME
trap 'rm -rf "$XDG_CACHE_HOME"' EXIT
cd crates/woven-py
"$VENV/bin/python" -m pytest -q -p no:cacheprovider -W ignore::DeprecationWarning tests
