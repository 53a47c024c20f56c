"""Under CI a skipped test is a failed one: the pytest hooks that make it so.

Imported by the conftest.py of crates/woven-py/tests and of scripts/serve, so they hold wherever
pytest runs those tests. With the environment variable CI set (to anything but "", "0" or
"false"), a session that skipped any test, at collection (`pytest.importorskip` at a module's
top) or while it ran (`pytest.skip`, `skipif`), ends with a non-zero status and a list of each
skipped test with its reason. Without CI, skips are reported as usual and pass.
"""

import os

import pytest


def in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false")


def _skipped(reporter):
    if reporter is None:
        return []
    # An expected failure (xfail) counts as skipped in pytest's tallies, but is not a skip.
    return [r for r in reporter.stats.get("skipped", []) if not hasattr(r, "wasxfail")]


def _reason(report) -> str:
    longrepr = report.longrepr
    if isinstance(longrepr, tuple) and len(longrepr) == 3:
        return str(longrepr[2]).removeprefix("Skipped: ")
    return str(longrepr)


@pytest.hookimpl(trylast=True)
def pytest_sessionfinish(session, exitstatus):
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    # OK, or nothing collected but skipped modules: either way, under CI, a failure.
    quiet = (pytest.ExitCode.OK, pytest.ExitCode.NO_TESTS_COLLECTED)
    if in_ci() and _skipped(reporter) and exitstatus in quiet:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_terminal_summary(terminalreporter):
    skipped = _skipped(terminalreporter)
    if not (in_ci() and skipped):
        return
    terminalreporter.section("skipped tests fail under CI", red=True, bold=True)
    for report in skipped:
        terminalreporter.line(f"FAILED (skipped under CI) {report.nodeid}: {_reason(report)}")
    terminalreporter.line(
        f"CI is set ({os.environ['CI']!r}): {len(skipped)} skipped test(s) fail this run. Install "
        "what each reason names (the ci.sh that runs these tests installs what it can and says "
        "how), or unset CI to let them skip."
    )
