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
