#!/usr/bin/env bash
# CI step: woven against Mitsuba 3 on issue 9's comparison scenes (docs/mitsuba.md).
#
#   bash scripts/mitsuba/ci.sh            # from anywhere; exit 0 = passed (or skipped, not in CI)
#
# Installs Mitsuba 3 from PyPI into a virtual environment (MITSUBA_VENV, default
# target/mitsuba-venv), Debian's libllvm19 when it can (root and apt-get) so the fast LLVM
# variant runs (without it compare.py falls back to scalar_rgb), then runs compare.py:
# Mitsuba vs the analytic images always, and Mitsuba vs `woven render` when the woven binary
# has a `render` command (built here with cargo build --release).
# Outside CI it skips, with a message and exit 0, when python3, its venv module or the PyPI
# packages cannot be had, and runs Mitsuba's slower scalar_rgb variant when no libLLVM >= 16 can
# be had. With the environment variable CI set (to anything but "", 0 or false) each of these
# fails the step (exit 1) with a message naming what is missing and how to get it, and the
# comparison must run llvm_ad_rgb and `woven render`. Then scripts/mitsuba/rgl_check.py reads
# `woven export --format rgl` files with Mitsuba's own `measured` plugin. Fails (exit 1) when a
# comparison fails.
set -euo pipefail
cd "$(dirname "$0")/../.."

MITSUBA_VERSION=3.9.1
DRJIT_VERSION=1.5.0
VENV=${MITSUBA_VENV:-target/mitsuba-venv}

in_ci() { case ${CI:-} in '' | 0 | [Ff]alse | FALSE) return 1 ;; *) return 0 ;; esac; }
# Under CI nothing may be left out: what would be skipped or degraded fails the step.
fail_in_ci() {
  in_ci || return 0
  printf 'FAIL (Mitsuba comparison): %s\nCI is set (CI=%s), so this step may not skip any part of it: install the above, or run without CI to skip it.\n' "$*" "$CI" >&2
  exit 1
}
skip() { fail_in_ci "$@"; printf 'SKIP (Mitsuba comparison): %s\n' "$*"; exit 0; }

command -v python3 >/dev/null 2>&1 || skip "no python3 on this machine"
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV" 2>/dev/null || { rm -rf "$VENV"; skip "python3 -m venv failed (Debian: apt-get install python3-venv)"; }
fi
if ! "$VENV/bin/python" -c "import mitsuba, numpy; assert mitsuba.__version__ == '$MITSUBA_VERSION'" 2>/dev/null; then
  echo "installing mitsuba==$MITSUBA_VERSION drjit==$DRJIT_VERSION numpy into $VENV"
  "$VENV/bin/pip" install -q --disable-pip-version-check --timeout 30 --retries 2 \
      "mitsuba==$MITSUBA_VERSION" "drjit==$DRJIT_VERSION" numpy \
    || skip "pip could not install mitsuba==$MITSUBA_VERSION drjit==$DRJIT_VERSION numpy into $VENV (no PyPI, or no wheel for this platform: give pip a reachable index, PIP_INDEX_URL, or install them into $VENV by hand)"
fi

args=()
# Dr.Jit's LLVM backend loads a system libLLVM >= 16 at run time (Debian 12: libllvm19).
if ! ldconfig -p 2>/dev/null | grep -Eq 'libLLVM(-1[6-9]|-[2-9][0-9]|\.so\.(1[6-9]|[2-9][0-9]))'; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "installing libllvm19 (for Mitsuba's llvm_ad_rgb variant)"
    if ! { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19; } >/dev/null 2>&1; then
      fail_in_ci "apt-get could not install libllvm19 (libLLVM >= 16, for Mitsuba's llvm_ad_rgb variant): apt-get install libllvm19 as root, with Debian's archive reachable"
      echo "note: libllvm19 could not be installed; Mitsuba runs its scalar_rgb variant (slower)"
    fi
  else
    fail_in_ci "no libLLVM >= 16 (for Mitsuba's llvm_ad_rgb variant) and no root and apt-get to install one: apt-get install libllvm19 (Debian 12) as root"
    echo "note: no libLLVM >= 16 found and no root to install one; Mitsuba runs scalar_rgb (slower)"
  fi
fi
# Under CI the LLVM variant must run: compare.py may not fall back to scalar_rgb.
if in_ci; then args=(--variant llvm_ad_rgb); fi

WOVEN_BIN=${WOVEN_BIN:-}
if [ -z "$WOVEN_BIN" ]; then
  cargo build --release --locked -q -p woven-cli
  WOVEN_BIN="${CARGO_TARGET_DIR:-target}/release/woven"
fi
if "$WOVEN_BIN" render --help >/dev/null 2>&1; then
  args+=(--woven "$WOVEN_BIN")
else
  fail_in_ci "$WOVEN_BIN has no \`render\` command (or does not run): build it with cargo build --release -p woven-cli, or set WOVEN_BIN"
  echo "note: $WOVEN_BIN has no \`render\` command yet: comparing Mitsuba with the analytic images only"
fi

"$VENV/bin/python" scripts/mitsuba/compare.py --out target/mitsuba-compare "${args[@]}" "$@"

# `woven export --format rgl` read by Mitsuba's own `measured` plugin (docs/export.md): two
# microcylinder fabrics (exact models, no table to build), in the RGB and spectral variants, and a
# plane of one rendered in both renderers (means within 1 %); about a minute and a half. Their
# sharp lobes miss the 10 % target at the 99th percentile (docs/export.md: 12 % and 24 %), so the
# limit here is 30 %: it catches a wrong convention or layout (errors of 100 % and more), and the
# median's 2 % holds.
if in_ci; then rgl_variants=(llvm_ad_rgb scalar_spectral); else rgl_variants=(scalar_rgb scalar_spectral); fi
"$VENV/bin/python" scripts/mitsuba/rgl_check.py --woven "$WOVEN_BIN" --pairs 2000 \
  --presets microcylinder-silk-shot microcylinder-velvet --variants "${rgl_variants[@]}" \
  --p99-limit 0.3 --render microcylinder-silk-shot --keep target/mitsuba-rgl
