"""woven.Table: build, files, eval, sampling, dyes, raw arrays; against the CLI and invariants."""

import math
import threading
import time

import numpy as np
import pytest

import woven
from conftest import SMALL, random_dirs


def test_build_equals_the_clis_tabulate_byte_for_byte(cli, tmp_path, sateen):
    flags = ["--n-theta", 8, "--n-phi", 4, "--n-h", 21, "--n-h-isotropic", 31]
    cli("tabulate", "-m", "polyester-sateen", "-o", tmp_path / "cli.wtab", *flags)
    table = woven.Table.build(sateen, n_theta=8, n_phi=4, n_h=21, n_h_isotropic=31, progress=False)
    table.save(tmp_path / "py.wtab")
    assert (tmp_path / "py.wtab").read_bytes() == (tmp_path / "cli.wtab").read_bytes()


def test_eval_is_the_clis_and_survives_a_file_round_trip(cli, tmp_path, sateen_table):
    path = tmp_path / "t.wtab"
    sateen_table.save(path)
    back = woven.Table.load(path)
    rng = np.random.default_rng(5)
    n = 500
    angles = np.column_stack(
        [
            rng.uniform(0, 1.55, n),
            rng.uniform(-4, 4, n),
            rng.uniform(0, 1.55, n),
            rng.uniform(-4, 4, n),
        ]
    )
    csv = tmp_path / "dirs.csv"
    csv.write_text(
        "theta_i,phi_i,theta_r,phi_r\n"
        + "".join(",".join(map(repr, map(float, r))) + "\n" for r in angles)
    )
    want = np.array(
        [
            float(line.split(",")[4])
            for line in cli("eval", "--table", path, "--input", csv).splitlines()[1:]
        ]
    )
    wi = woven.from_spherical(angles[:, 0], angles[:, 1])
    wo = woven.from_spherical(angles[:, 2], angles[:, 3])
    np.testing.assert_array_equal(back.eval(wi, wo), want)
    np.testing.assert_array_equal(sateen_table.eval(wi, wo), want)
    assert back.dims == sateen_table.dims == (8, 4, 21)
    assert back.material == sateen_table.material
    assert back.symmetry == "mirror" and back.is_dyeable
    assert back.values.shape == (2, 8, 4, 21, 21) and back.values.dtype == np.float32


def test_table_is_close_to_the_exact_model(sateen, sateen_table):
    rng = np.random.default_rng(6)
    wi = woven.from_spherical(rng.uniform(0, 1.2, 400), rng.uniform(0, 6.3, 400))
    wo = woven.from_spherical(rng.uniform(0, 1.2, 400), rng.uniform(0, 6.3, 400))
    exact = sateen.build().eval(wi, wo)
    table = sateen_table.eval(wi, wo)
    # A coarse grid: compare f cos cos against its peak (the table's error budget's measure).
    w = wi[:, 2] * wo[:, 2]
    assert np.sqrt(np.mean(((table - exact) * w) ** 2)) < 0.05 * np.max(exact * w)


def test_interpolated_eval_differs_only_near_forward(sateen_table):
    rng = np.random.default_rng(7)
    wi, wo = random_dirs(rng, 20000), random_dirs(rng, 20000)
    a, b = sateen_table.eval(wi, wo), sateen_table.eval_interpolated(wi, wo)
    # The exact regions of woven::table: |wi + wo| < FORWARD_EXACT (0.5), or the half vector
    # within 5° of the horizon (h_z < GRAZING_HALF_EXACT |h|, sin 5°).
    h = wi + wo
    norm = np.linalg.norm(h, axis=1)
    forward = (norm < 0.5) | (h[:, 2] < math.sin(math.radians(5.0)) * norm)
    assert forward.any() and sateen_table.raw()["forward_exact"]
    np.testing.assert_array_equal(a[~forward], b[~forward])


def test_sample_weight_pdf_and_eval_agree(sateen_table):
    rng = np.random.default_rng(8)
    n = 20000
    wi = woven.from_spherical(0.7, 0.4)
    u = rng.random((n, 2))
    wo, weight, pdf = sateen_table.sample(wi, u, mode="importance")
    assert wo.shape == (n, 3) and weight.shape == (n,) and pdf.shape == (n,)
    ok = pdf > 0
    assert ok.mean() > 0.95
    np.testing.assert_allclose(np.linalg.norm(wo[ok], axis=1), 1, atol=1e-12)
    f = sateen_table.eval(wi, wo[ok])
    np.testing.assert_allclose(weight[ok], f * wo[ok, 2] / pdf[ok], rtol=1e-12)
    np.testing.assert_allclose(sateen_table.pdf(wi, wo[ok], mode="importance"), pdf[ok], rtol=1e-6)
    # sample_direction is the same draw without f.
    wo2, pdf2 = sateen_table.sample_direction(wi, u)
    np.testing.assert_array_equal(wo2, wo)
    np.testing.assert_array_equal(pdf2, pdf)
    # Importance-sampled and uniform estimates of the albedo agree.
    is_est = weight.sum() / n
    wu = random_dirs(rng, 400_000)
    uni = 2 * math.pi * np.mean(sateen_table.eval(wi, wu) * wu[:, 2])
    assert abs(is_est - uni) < 0.02 * uni, (is_est, uni)
    # The density integrates to at most 1 over the hemisphere.
    total = 2 * math.pi * np.mean(sateen_table.pdf(wi, wu, mode="importance"))
    assert 0.9 < total <= 1.01, total
    # Failed draws: wi below the surface.
    wo3, w3, p3 = sateen_table.sample([0.0, 0.6, -0.8], [0.5, 0.5], mode="importance")
    assert (wo3 == 0).all() and (w3 == 0).all() and (p3 == 0).all()
    # Mode "radiance" (the default, as woven.Surface): the known direction is wo and wi is
    # drawn; its density is pdf(wi, wo) in that mode.
    drawn, w4, p4 = sateen_table.sample(wi, u)
    ok = p4 > 0
    assert ok.mean() > 0.95 and (drawn[ok, 2] > 0).all()
    np.testing.assert_allclose(sateen_table.pdf(drawn[ok], wi), p4[ok], rtol=1e-6)
    with pytest.raises(ValueError, match="mode"):
        sateen_table.pdf(wi, wi, mode="both")
    wo3, w3, p3 = sateen_table.sample([0.0, 0.6, -0.8], [0.5, 0.5])
    assert (wo3 == 0).all() and (w3 == 0).all() and (p3 == 0).all()


def test_eval_dyed_with_own_albedos_is_eval(sateen, sateen_table):
    rng = np.random.default_rng(9)
    wi, wo = random_dirs(rng, 3000), random_dirs(rng, 3000)
    own = (sateen.fiber.diffuse, sateen.yarn.interreflection_albedo)
    dyed = sateen_table.eval_dyed(wi, wo, [own, (0.5, 0.9), (0.0, 0.0)])
    assert dyed.shape == (3000, 3)
    np.testing.assert_allclose(dyed[:, 0], sateen_table.eval(wi, wo), rtol=1e-12, atol=1e-15)
    assert (dyed >= 0).all()
    # Dyed tables follow the dyed material (docs/model.md §7): within the tables' budget.
    red = sateen.replace({"fiber.diffuse": 0.5, "yarn.interreflection_albedo": 0.9})
    red_table = woven.Table.build(red, progress=False, **SMALL)
    far = np.linalg.norm(wi + wo, axis=1) >= 0.5
    np.testing.assert_allclose(dyed[far, 1], red_table.eval(wi[far], wo[far]), rtol=2e-3, atol=1e-6)


def test_progress_callback_and_bad_options(flat):
    seen = []
    woven.Table.build(flat, progress=lambda done, total: seen.append((done, total)), **SMALL)
    assert seen and seen[-1][0] == seen[-1][1] and all(0 <= d <= t for d, t in seen)

    def boom(done, total):
        raise RuntimeError("stop")

    with pytest.raises(RuntimeError, match="stop"):
        woven.Table.build(flat, progress=boom, **SMALL)

    # A callback that raises stops the build: a model-grid table of the belt cloth (a minute
    # on two cores) ends within a few rows of the first percent.
    calls = []

    def stop_early(done, total):
        calls.append(done)
        if done * 100 >= total:
            raise KeyboardInterrupt

    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        woven.Table.build("belt-cloth", progress=stop_early)
    assert time.monotonic() - start < 10, "the build ran on after its callback raised"
    assert len(calls) <= 3, calls
    with pytest.raises(ValueError, match="n_theta"):
        woven.Table.build(flat, n_theta=1, progress=False)
    with pytest.raises(ValueError, match="grid"):
        woven.Table.build(flat, grid="huge", progress=False)
    with pytest.raises(ValueError, match="table grid"):
        woven.Table.build("polyester-sateen", n_theta=1000, n_phi=1000, n_h=101, progress=False)
    with pytest.raises(TypeError):
        woven.Table.build(3.5)


def test_file_errors(tmp_path, flat_table):
    with pytest.raises(OSError, match="missing.wtab"):
        woven.Table.load(tmp_path / "missing.wtab")
    junk = tmp_path / "junk.wtab"
    junk.write_bytes(b"not a table at all" * 10)
    with pytest.raises(ValueError, match="junk.wtab"):
        woven.Table.load(junk)
    with pytest.raises(OSError):
        flat_table.save(tmp_path / "no-such-dir" / "t.wtab")
    assert not (tmp_path / "no-such-dir").exists()


def test_threads_share_a_table(flat_table):
    rng = np.random.default_rng(10)
    wi, wo = random_dirs(rng, 50_000), random_dirs(rng, 50_000)
    want = flat_table.eval(wi, wo)
    results = [None] * 4

    def work(k):
        results[k] = flat_table.eval(wi, wo)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results:
        np.testing.assert_array_equal(r, want)


def test_export_merl_is_the_clis(cli, tmp_path, flat):
    mpath = tmp_path / "flat.toml"
    mpath.write_text(flat.to_toml())
    cli("export", "--material", mpath, "-o", tmp_path / "cli.binary")
    woven.export_merl(flat.build(), tmp_path / "py.binary")
    assert (tmp_path / "py.binary").read_bytes() == (tmp_path / "cli.binary").read_bytes()
    with pytest.raises(ValueError, match="φ_h|isotropic"):
        woven.export_merl(woven.Material.preset("polyester-sateen").build(), tmp_path / "x.binary")
    assert not (tmp_path / "x.binary").exists()


def test_the_cache_notes_a_damaged_table_as_a_warning(tmp_path, monkeypatch):
    """`Table.cached` goes through the library's table cache: a second call loads the file the
    first stored; a damaged file is rebuilt, and the cache's note reaches Python as a
    UserWarning."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    yarn = woven.Material.preset("polyester-sateen").yarn_family()
    first = woven.Table.cached(yarn)
    files = list((tmp_path / "woven").glob("*.wtab"))
    assert len(files) == 1
    data = bytearray(files[0].read_bytes())
    data[len(data) // 2] ^= 0x40
    files[0].write_bytes(bytes(data))
    with pytest.warns(UserWarning, match="not using the cached table"):
        again = woven.Table.cached(yarn)
    wi = np.array([[0.3, 0.1, 0.95]]) / np.linalg.norm([0.3, 0.1, 0.95])
    wo = np.array([[-0.5, 0.4, 0.77]]) / np.linalg.norm([-0.5, 0.4, 0.77])
    np.testing.assert_array_equal(first.eval(wi, wo), again.eval(wi, wo))
