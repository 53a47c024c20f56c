"""woven.Surface: the library's woven surface from Python — a point is its cell's yarn, draws
have the densities `pdf` reports in both transport modes, and bad parameters are refused by
name."""

import numpy as np
import pytest

import woven
from conftest import SMALL, random_dirs


@pytest.fixture(scope="module")
def yarn():
    return woven.Table.build(
        woven.Material.preset("polyester-sateen").yarn_family(), colour=True, progress=False, **SMALL
    )


def test_a_point_is_its_cells_yarn(yarn):
    weft, warp = [0.7, 0.2, 0.1], [0.1, 0.3, 0.6]
    s = woven.Surface(table=yarn, pattern="twill-2/1", yarns_per_unit=(6, 4),
                      weft_color=weft, warp_color=warp, detail="yarns")
    rng = np.random.default_rng(2)
    n = 500
    uv = rng.uniform(-2, 2, (n, 2))
    wi, wo = random_dirs(rng, n), random_dirs(rng, n)
    f = s.eval(uv, wi, wo)
    cells = np.asarray(s.layout()["cells"])
    row = np.floor(uv[:, 1] * 4).astype(int) % 3
    col = np.floor(uv[:, 0] * 6).astype(int) % 3
    is_weft = cells[row, col] == 1

    def turn(d):
        return np.stack([d[:, 1], -d[:, 0], d[:, 2]], axis=1)

    own = yarn.raw()["own"]

    def dye(c):
        return [(x, min(own[1] * x / own[0], 1.0)) for x in c]

    for k in range(n):
        if is_weft[k]:
            want = yarn.eval_dyed(wi[k], wo[k], dye(weft))
        else:
            want = yarn.eval_dyed(turn(wi[k : k + 1])[0], turn(wo[k : k + 1])[0], dye(warp))
        np.testing.assert_allclose(f[k], np.ravel(want), rtol=1e-12, atol=1e-15)
    warp_lobe, along, weight, across = s.lobes(uv)
    assert np.all(weight[:, 0] == 1.0) and np.all(weight[:, 1:] == 0.0) and np.all(across[:, 0] == -1)
    # No u_max_deg: every yarn flat (−1 in the float column).
    assert np.array_equal(warp_lobe[:, 0] == 1.0, ~is_weft) and np.all(along[:, 0] == -1.0)


def test_tilted_floats_report_where_the_viewer_enters_them(yarn):
    # u_max_deg > 0 without gaps: every point lies on a tilted float, at the fraction along it
    # at which the viewer's ray enters; far away (cloth) each family is one whole float (2).
    kw = dict(table=yarn, pattern="twill-2/1", yarns_per_unit=(6, 4), u_max_deg=30)
    s = woven.Surface(**kw, detail="yarns")
    uv = np.random.default_rng(3).uniform(-2, 2, (300, 2))
    _, along, weight, _ = s.lobes(uv)
    assert np.all(weight[:, 0] == 1.0) and np.all((along[:, 0] >= 0) & (along[:, 0] <= 1))
    assert [f for _, f, _ in s.layout()["macro"]] == [True, True]
    _, along, weight, _ = woven.Surface(**kw, detail="cloth").lobes(uv)
    assert np.all(along[weight > 0] == 2.0) and np.allclose(weight.sum(axis=1), 1.0)


def test_a_whole_float_is_one_look_up_in_its_own_table(yarn):
    """Surface.float_table: None without a tilt; with one, the table a whole float reads (the
    yarn's averaged over the float, dyeable: its raw arrays carry the interreflection factor), so
    a weft-only macro surface is that table's look-up, dyed."""
    assert woven.Surface(table=yarn, weft_fraction=1.0).float_table is None
    weft = [0.7, 0.2, 0.1]
    s = woven.Surface(table=yarn, weft_fraction=1.0, u_max_deg=30, weft_color=weft)
    table = s.float_table
    raw = table.raw()
    assert raw["crown"] is not None and raw["crown"].shape == raw["values"].shape
    rng = np.random.default_rng(8)
    n = 300
    wi, wo = random_dirs(rng, n), random_dirs(rng, n)
    own = raw["own"]
    dye = [(x, min(own[1] * x / own[0], 1.0)) for x in weft]
    f = s.eval(rng.uniform(0, 1, (n, 2)), wi, wo)
    for k in range(n):
        np.testing.assert_allclose(f[k], np.ravel(table.eval_dyed(wi[k], wo[k], dye)), rtol=1e-12)
    # Not the flat yarn's: the float's tilt moves its sheen.
    assert np.abs(f - s.table.eval_dyed(wi, wo, dye)).max() > 0.01 * f.max()


@pytest.mark.parametrize("detail", ["auto", "fibers", "yarns"])
@pytest.mark.parametrize("mode", ["radiance", "importance"])
def test_draws_have_the_density_pdf_reports(yarn, mode, detail):
    s = woven.Surface(table=yarn, pattern="satin-5", yarns_per_unit=5, u_max_deg=30, gap=0.3,
                      detail=detail)
    rng = np.random.default_rng(5)
    n = 2000
    uv = rng.uniform(0, 1, (n, 2))
    fp = rng.uniform(0, 0.2, (n, 4))
    known = random_dirs(rng, n)
    drawn, f, pdf = s.sample(uv, known, rng.random(n), rng.random((n, 2)), fp, mode=mode)
    ok = pdf > 0
    # Holes (gap²) draw nothing; a facet's lobe reflects part of its draws below the horizon.
    assert ok.mean() > (0.5 if detail == "fibers" else 0.8)
    # A failed draw's zero vector is no direction (pdf and eval refuse it): only the draws.
    uv, fp, known, drawn, f, pdf = (a[ok] for a in (uv, fp, known, drawn, f, pdf))
    wi, wo = (drawn, known) if mode == "radiance" else (known, drawn)
    np.testing.assert_allclose(s.pdf(uv, wi, wo, fp, mode=mode), pdf, rtol=1e-5)
    np.testing.assert_allclose(s.eval(uv, wi, wo, fp), f, rtol=1e-12)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"gap": 0.99}, "gap"),
        ({"u_max_deg": 95.0}, "u_max"),
        ({"yarns_per_unit": 0.0}, "yarns_per_unit"),
        ({"weft_color": [1.5, 0.0, 0.0]}, "weft_color"),
        ({"pattern": "twill-0/1"}, "twill"),
        ({"detail": "threads"}, "detail"),
        ({"irregularity": 1.5}, "irregularity"),
        ({"irregularity": (0.2, 0.3, 0.4)}, "irregularity"),
        ({"irregularity": 0.2, "irregularity_length": 0.0}, "irregularity_length"),
    ],
)
def test_bad_parameters_are_refused_by_name(yarn, kwargs, name):
    args = {"pattern": "plain", **kwargs}
    with pytest.raises(ValueError, match=name):
        woven.Surface(table=yarn, **args)


def test_irregular_yarns_vary_but_average_to_the_uniform_cloth(yarn):
    """Each yarn's dye varies along it (the library's `Irregularity`): points differ from the
    uniform cloth's, their mean does not (dyes dark enough that no factor meets a cap)."""
    args = dict(table=yarn, pattern="twill-2/1", yarns_per_unit=(6, 4), detail="yarns",
                weft_color=[0.05, 0.025, 0.01], warp_color=[0.01, 0.025, 0.05])
    plain = woven.Surface(**args)
    uneven = woven.Surface(**args, irregularity=(0.3, 0.3), irregularity_length=8.0)
    rng = np.random.default_rng(5)
    n = 20000
    uv = rng.uniform(-40, 40, (n, 2))
    wi = np.tile([0.3, 0.1, 0.95], (n, 1)) / np.linalg.norm([0.3, 0.1, 0.95])
    wo = np.tile([-0.5, 0.4, 0.77], (n, 1)) / np.linalg.norm([-0.5, 0.4, 0.77])
    a, b = plain.eval(uv, wi, wo), uneven.eval(uv, wi, wo)
    d = b - a
    assert np.mean(np.abs(d) > 1e-6 * a) > 0.9
    se = d.std(axis=0) / np.sqrt(n)
    assert np.all(np.abs(d.mean(axis=0)) < 4 * se), (d.mean(axis=0), se)


def test_a_table_alone_takes_no_weave_options(yarn):
    with pytest.raises(ValueError, match="need a weave"):
        woven.Surface(table=yarn, gap=0.2)
    with pytest.raises(ValueError, match="exactly one"):
        woven.Surface()
    whole = woven.Surface(table=yarn)
    assert whole.layout()["kind"] in ("whole", "flat")


def test_fibre_level_points_lie_across_their_yarn(yarn):
    s = woven.Surface(table=yarn, pattern="plain", yarns_per_unit=4, detail="fibers")
    uv = np.array([[0.01, 0.0625], [0.2, 0.125 - 0.001]])
    warp, along, weight, across = s.lobes(uv)
    assert np.all(weight[:, 0] == 1.0) and np.all(across[:, 0] >= 0)
    assert s.layout()["detail"] == "fibers"


def test_surface_keys_are_the_librarys_table_and_name_surfaces_keywords(yarn):
    """`woven.SURFACE_KEYS` is the library's table of a woven surface's keys; `woven.Surface`
    takes them as keywords (beside its material, table and progress), and a key left out takes
    the library's default: 40 cells per unit, as in `woven render` scenes and the plugin."""
    import inspect

    keys = woven.SURFACE_KEYS
    assert isinstance(keys, tuple) and keys
    for k in keys:
        assert set(k) == {"name", "default", "valid", "meaning"}
        assert all(isinstance(v, str) and v for v in k.values()), k
    names = [k["name"] for k in keys]
    assert len(set(names)) == len(names)
    by_name = {k["name"]: k for k in keys}
    # The keywords: the material (the key `material`, also a woven.Material), the table in its
    # place, the progress of the table's build, and every other key through **keys, which the
    # library reads (an unknown one is refused by name: test_keys_are_read_by_the_library_...).
    params = inspect.signature(woven.Surface).parameters
    assert {n for n, p in params.items() if p.kind != p.VAR_KEYWORD} == {
        "material", "table", "progress"}
    assert [p.kind for p in params.values()].count(inspect.Parameter.VAR_KEYWORD) == 1
    assert by_name["yarns_per_unit"]["default"] == "40"
    assert by_name["detail"]["default"] == '"auto"'
    assert "0.95" in by_name["gap"]["valid"] and "80" in by_name["u_max_deg"]["valid"]
    for name in ("auto", "fibers", "yarns", "cloth"):
        assert f'"{name}"' in by_name["detail"]["valid"]

    s = woven.Surface(table=yarn, pattern="plain")
    lay = s.layout()
    assert list(lay["yarns_per_unit"]) == [40.0, 40.0]
    assert lay["yarns_per_unit"][0] == float(by_name["yarns_per_unit"]["default"])
    assert lay["detail"] == "auto" and lay["gap"] == 0.0


def test_keys_are_read_by_the_library_in_every_form_it_takes(yarn):
    """woven.Surface hands its keyword arguments to the library's one reader of a surface's keys
    (SurfaceSpec::from_keys): a pattern as a name or as its 0/1 matrix is the same surface; a pair
    as a tuple, a NumPy array or a string "a, b"; NumPy scalars as numbers; an unknown key is
    refused by name with the list of keys; a value of a type no key takes raises TypeError."""
    uv = np.array([[0.01, 0.02], [0.3, 0.7], [0.55, 0.15]])
    rng = np.random.default_rng(7)
    wi, wo = random_dirs(rng, 3), random_dirs(rng, 3)
    named = woven.Surface(table=yarn, pattern="twill-2/1", yarns_per_unit=(6, 4), detail="yarns")
    cells = np.asarray(named.layout()["cells"]).tolist()
    for pattern, ypu in [(cells, np.array([6.0, 4.0])), ("twill-2/1", "6, 4")]:
        other = woven.Surface(table=yarn, pattern=pattern, yarns_per_unit=ypu,
                              detail="yarns", gap=np.float32(0.0))
        np.testing.assert_array_equal(other.eval(uv, wi, wo), named.eval(uv, wi, wo))
    with pytest.raises(ValueError, match="colour.*`footprint_filter`"):
        woven.Surface(table=yarn, pattern="plain", colour=[1, 0, 0])
    with pytest.raises(ValueError, match=r"pattern\[0\]\[1\]"):
        woven.Surface(table=yarn, pattern=[[1, 2], [0, 1]])
    with pytest.raises(TypeError, match="gap"):
        woven.Surface(table=yarn, pattern="plain", gap=object())


def test_footprint_filter_off_ignores_the_calls_footprints(yarn):
    """`footprint_filter = False`: the footprints a call passes are ignored, as `woven render`
    with its integrator's filter off; on (the default), a footprint of many cells blends to the
    macro BRDF."""
    kw = dict(table=yarn, pattern="satin-5", yarns_per_unit=40, detail="yarns")
    on, off = woven.Surface(**kw), woven.Surface(**kw, footprint_filter=False)
    assert on.footprint_filter and not off.footprint_filter
    rng = np.random.default_rng(3)
    n = 200
    uv = rng.uniform(0, 1, (n, 2))
    wi, wo = random_dirs(rng, n), random_dirs(rng, n)
    wide = np.tile([1.0, 0.0, 0.0, 1.0], (n, 1))  # 40 cells a pixel
    np.testing.assert_array_equal(off.eval(uv, wi, wo, wide), on.eval(uv, wi, wo))
    assert not np.allclose(on.eval(uv, wi, wo, wide), on.eval(uv, wi, wo))


def test_the_jit_layout_is_the_librarys_typed_and_versioned(yarn):
    """Surface.layout() is the library's JitLayout: versioned (woven.JIT_LAYOUT_VERSION), with
    every rule evaluated in Rust: a pattern at "cloth" is traced as the macro BRDF, the macro
    lobes' weights are the γ-mix's, and the dye rule comes as constants that dye a colour as
    the surface dyes its own weft_color."""
    lay = woven.Surface(table=yarn, pattern="twill-2/1", detail="cloth").layout()
    assert lay["version"] == woven.JIT_LAYOUT_VERSION >= 1
    assert lay["kind"] == "macro" and lay["detail"] == "cloth"
    assert sum(w for _, _, w in lay["macro"]) == pytest.approx(1.0)
    assert woven.Surface(table=yarn, pattern="plain", detail="yarns").layout()["kind"] == "pattern"
    c = [0.7, 0.05, float("nan")]
    dyed = woven.Surface(table=yarn, pattern="plain", weft_color=[0.7, 0.05, 0.0]).layout()
    cap, slope, offset = dyed["dye_rule"]
    for x, (rho0, rho) in zip(c, dyed["albedos"]["weft"]):
        x = 0.0 if x != x else min(max(x, 0.0), 1.0)
        assert (min(x, cap), min(max(slope * x + offset, 0.0), 1.0)) == pytest.approx((rho0, rho))


def test_the_library_decides_which_surfaces_jit_variants_trace(yarn):
    """Surface.route: None where Mitsuba's JIT variants trace the surface in Dr.Jit, else the
    reason the library answers lane by lane: only the fibres ("auto", "fibers") and the relief.
    Irregular dyes and shaped floats are traced, on a weft fraction as on a pattern, and the
    layout carries what traces them."""
    assert woven.Surface(table=yarn, pattern="plain", detail="yarns").route is None
    assert woven.Surface(table=yarn, weft_fraction=0.4, u_max_deg=20).route is None
    assert "fibres" in woven.Surface(table=yarn, pattern="plain").route
    assert "relief" in woven.Surface(table=yarn, pattern="plain", detail="yarns", relief=True).route
    uneven = woven.Surface(table=yarn, pattern="plain", detail="cloth", irregularity=[0.2, 0.3],
                           irregularity_length=5.0)
    assert uneven.route is None
    assert uneven.layout()["irregularity"] == {"spread": [0.2, 0.3], "length": 5.0}
    assert woven.Surface(table=yarn, pattern="plain", detail="cloth").layout()["irregularity"] is None
    shaped = woven.Material.preset("satin-charmeuse").replace({"weave": None})
    table = woven.Table.build(shaped, progress=False, colour=True, n_theta=4, n_phi=3, n_h=11,
                              n_h_isotropic=11, azimuth_nodes=8)
    for weave in ({"pattern": "satin-5"}, {"weft_fraction": 0.2}):
        s = woven.Surface(table=table, detail="yarns", **weave)
        assert s.route is None, (weave, s.route)
        knots = s.layout()["float"]["knots"]
        # Flat over the crest (float_crest), at full tilt over each flank (float_flank).
        crest, flank = shaped.yarn["float_crest"], shaped.yarn["float_flank"]
        u = s.layout()["u_max"]
        assert len(knots) == 6 and knots[0] == (0.0, u) and knots[-1] == (1.0, -u), knots
        assert abs(knots[1][0] - flank) < 1e-12 and abs(knots[3][0] - knots[2][0] - crest) < 1e-12


def test_light_passes_through_the_holes_by_the_open_area(yarn):
    # A gapped plain weave with transmission: along the normal a hole passes everything and a
    # yarn nothing, so a cell's mean is gap²; tilted, the mean is the cloth level's value (a
    # footprint of many cells), which falls as the yarns close the gaps.
    gap = 0.3
    kw = dict(table=yarn, pattern="plain", yarns_per_unit=(10, 10), gap=gap)
    s = woven.Surface(**kw, transmission=True)
    assert s.transmits
    n = 200
    g = (np.arange(n) + 0.5) / (10 * n)
    uv = np.stack(np.meshgrid(g, g), axis=-1).reshape(-1, 2)
    normal = s.pass_through(uv, [0.0, 0.0, 1.0])
    assert set(np.unique(normal)) <= {0.0, 1.0}
    assert abs(normal.mean() - gap**2) < 1e-3
    d = np.array([np.sin(0.6) * np.cos(0.4), np.sin(0.6) * np.sin(0.4), np.cos(0.6)])
    far = s.pass_through([0.01, 0.02], d, footprint=[1.0, 0.0, 0.0, 1.0])
    assert 0.0 < far[0] < gap**2
    assert abs(s.pass_through(uv, d).mean() - far[0]) < 1e-3 * gap**2
    # Off (the paper's opaque cloth), nothing passes.
    off = woven.Surface(**kw)
    assert not off.transmits and np.all(off.pass_through(uv, d) == 0.0)
