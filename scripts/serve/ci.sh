#!/usr/bin/env bash
# CI step: the explorer (`woven serve`, docs/serve.md) end to end in a real browser.
#
#   WOVEN_BIN=target/release/woven bash scripts/serve/ci.sh   # exit 0 = passed (or skipped, not in CI)
#
# Uses Debian's Chromium (installs the `chromium` package when run as root and it is missing;
# Playwright's own browser downloads are never used), a virtual environment with Playwright and
# pytest from PyPI (scripts/serve/requirements.txt; WOVEN_SERVE_VENV, default
# target/serve-venv), starts `woven serve --port 0` (a free port), runs
# scripts/serve/test_explorer.py against it and stops the server. SCREENSHOT=path.png keeps a
# picture of the page (docs/img/serve.png is made so). Outside CI it skips, with a message and
# exit 0, when Chromium, python3's venv or PyPI is not to be had; with the environment variable
# CI set (to anything but "", 0 or false) each of these fails the step (exit 1) with a message
# naming what is missing and how to get it, and so does a test that skips
# (scripts/serve/conftest.py, scripts/ci_no_skips.py). Fails (exit 1) when a test fails.
set -euo pipefail
cd "$(dirname "$0")/../.."

VENV=${WOVEN_SERVE_VENV:-target/serve-venv}
WOVEN=${WOVEN_BIN:-${CARGO_TARGET_DIR:-target}/release/woven}

in_ci() { case ${CI:-} in '' | 0 | [Ff]alse | FALSE) return 1 ;; *) return 0 ;; esac; }
# Under CI nothing may be left out: what would be skipped fails the step.
skip() {
  if in_ci; then
    printf 'FAIL (explorer in a browser): %s\nCI is set (CI=%s), so this step may not skip: install the above, or run without CI to skip it.\n' "$*" "$CI" >&2
    exit 1
  fi
  printf 'SKIP (explorer in a browser): %s\n' "$*"
  exit 0
}

# Chromium: Debian's, found or installed.
CHROMIUM=${CHROMIUM:-}
if [ -z "$CHROMIUM" ]; then
  if ! command -v chromium >/dev/null 2>&1 && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "installing Debian's chromium"
    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; } \
      || skip "apt-get could not install Debian's chromium (apt-get install chromium as root, with Debian's archive reachable, or set CHROMIUM to a Chromium binary)"
  fi
  # The binary itself rather than Debian's wrapper script, when it is there.
  if [ -x /usr/lib/chromium/chromium ]; then CHROMIUM=/usr/lib/chromium/chromium
  else CHROMIUM=$(command -v chromium || true); fi
fi
[ -n "$CHROMIUM" ] && [ -x "$CHROMIUM" ] \
  || skip "no chromium${CHROMIUM:+ at $CHROMIUM} (Debian: apt-get install chromium as root, or set CHROMIUM to a Chromium binary)"

command -v python3 >/dev/null 2>&1 || skip "no python3 on this machine"
if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV" 2>/dev/null || { rm -rf "$VENV"; skip "python3 -m venv failed (Debian: apt-get install python3-venv)"; }
fi
"$VENV/bin/python" -c "import playwright, pytest" 2>/dev/null \
  || "$VENV/bin/pip" install -q --disable-pip-version-check --timeout 30 --retries 2 -r scripts/serve/requirements.txt \
  || skip "pip could not install playwright and pytest (scripts/serve/requirements.txt) into $VENV (no PyPI: give pip a reachable index, PIP_INDEX_URL, or install them into $VENV by hand)"

[ -x "$WOVEN" ] || { echo "error: no woven binary at $WOVEN (cargo build --release -p woven-cli, or set WOVEN_BIN)" >&2; exit 1; }
WOVEN=$(cd "$(dirname "$WOVEN")" && pwd)/$(basename "$WOVEN")

LOG=$(mktemp)
"$WOVEN" serve --port 0 >"$LOG" 2>&1 &
SERVER=$!
trap 'kill "$SERVER" 2>/dev/null || true; wait "$SERVER" 2>/dev/null || true; rm -f "$LOG"' EXIT
URL=
for _ in $(seq 1 100); do
  URL=$(grep -o 'http://[^ ]*/' "$LOG" || true)
  [ -n "$URL" ] && break
  kill -0 "$SERVER" 2>/dev/null || { cat "$LOG" >&2; echo "error: woven serve did not start" >&2; exit 1; }
  sleep 0.1
done
[ -n "$URL" ] || { cat "$LOG" >&2; echo "error: woven serve printed no address" >&2; exit 1; }
echo "woven serve at $URL; Chromium: $CHROMIUM"

WOVEN_SERVE_URL=$URL WOVEN_BIN=$WOVEN CHROMIUM=$CHROMIUM \
  "$VENV/bin/python" -m pytest -q -p no:cacheprovider scripts/serve/test_explorer.py
