"""A million-element call neither leaks memory nor references."""

import gc
import sys

import numpy as np

from conftest import random_dirs


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096


def test_a_million_pairs_do_not_leak(flat_table):
    rng = np.random.default_rng(11)
    n = 1_000_000
    wi, wo = random_dirs(rng, n), random_dirs(rng, n)
    u = rng.random((n, 2))
    refs = (sys.getrefcount(wi), sys.getrefcount(wo), sys.getrefcount(u))

    def calls():
        f = flat_table.eval(wi, wo)
        p = flat_table.pdf(wi, wo, mode="importance")
        s = flat_table.sample(wi, u, mode="importance")
        assert f.shape == p.shape == (n,) and s[0].shape == (n, 3)
        assert sys.getrefcount(f) == 2  # the local name and getrefcount's argument
        return f

    calls()
    gc.collect()
    before = rss_bytes()
    for _ in range(5):
        calls()
    gc.collect()
    grown = rss_bytes() - before
    # Five rounds allocate ~320 MB in results; a leak of one (N,) result a round would keep 40 MB.
    assert grown < 16 << 20, f"RSS grew by {grown / 2**20:.1f} MiB over 5 million-pair rounds"
    assert (sys.getrefcount(wi), sys.getrefcount(wo), sys.getrefcount(u)) == refs


def peak_rss_bytes():
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def test_a_batch_over_the_budget_is_a_memory_error_before_allocating(sateen_table):
    import pytest

    import woven

    assert woven.BATCH_BUDGET_BYTES == 2 << 30
    up = np.array([0.0, 0.0, 1.0])
    surface = woven.Surface(table=sateen_table)
    peak = peak_rss_bytes()
    # 10^8 directions (2.4 GB as float64) and 10^9 angles, as views that take no memory.
    many = np.broadcast_to(up, (10**8, 3))
    over = r"over the batch budget of 2 GiB an array \(woven.BATCH_BUDGET_BYTES\): split the batch"
    with pytest.raises(MemoryError, match=rf"`known`: 100000000 rows × 3 float64s take 2\.24 GiB, "
                       rf"0\.24 GiB {over}"):
        surface.sample([0.1, 0.2], many, 0.5, [0.5, 0.5])
    with pytest.raises(MemoryError, match=rf"`wi`: .*{over}"):
        sateen_table.eval(many, up)
    with pytest.raises(MemoryError, match=rf"`theta`: 1000000000 rows × 1 float64s .*{over}"):
        woven.from_spherical(np.broadcast_to(0.5, (10**9,)), 0.0)
    # The result's size is checked too: 10^6 pairs × 300 channels (2.4 GB) from small arguments.
    with pytest.raises(MemoryError, match=rf"the result: 1000000 rows × 300 float64s .*{over}"):
        sateen_table.eval_dyed(np.broadcast_to(up, (10**6, 3)), up, np.full((300, 2), 0.5))
    assert peak_rss_bytes() - peak < 64 << 20, "a refused batch was allocated"
