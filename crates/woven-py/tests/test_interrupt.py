"""Long calls stop for Ctrl-C: a call in a child process gets SIGINT half a second in and raises
KeyboardInterrupt promptly, on all cores (the GIL released) and on the calling thread alike."""

import signal
import subprocess
import sys
import time

import pytest

CHILD = r"""
import sys
import numpy as np
import woven

slow = woven.Material.preset("belt-cloth").build()    # about a millisecond a pair
sateen = woven.Material.preset("polyester-sateen").build()
up = np.array([0.0, 0.6, 0.8])
calls = {
    "parallel": lambda: slow.eval(np.broadcast_to(up, (10**6, 3)), up),
    "serial": lambda: slow.eval(np.broadcast_to(up, (woven.PARALLEL_MIN - 1, 3)), up),
    "albedo": lambda: sateen.albedo(np.full(10**4, 0.5)),
}
print("ready", flush=True)
try:
    calls[sys.argv[1]]()
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""


@pytest.mark.parametrize("call", ["parallel", "serial", "albedo"])
def test_ctrl_c_interrupts_a_long_call(call):
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, call],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout.readline().strip() == "ready", child.stderr.read()
        time.sleep(0.5)
        child.send_signal(signal.SIGINT)
        sent = time.monotonic()
        out, err = child.communicate(timeout=5)
        waited = time.monotonic() - sent
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    assert out.strip() == "interrupted", f"stdout {out!r}, stderr {err!r}"
    assert waited < 2.0, f"KeyboardInterrupt came {waited:.2f} s after SIGINT"
