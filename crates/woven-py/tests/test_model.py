"""woven.Model and woven.gonio: golden vectors, the CLI on the same inputs, shapes and errors."""

import csv
import math

import numpy as np
import pytest

import woven
from conftest import VECTORS, random_dirs


def tolerance(name, material):
    """The vector README's tolerances (as crates/woven/tests/integration/golden.rs)."""
    if name.startswith("fiber-rough"):
        return 1e-9 if material.fiber.normalization == "none" else 2e-4
    if name.startswith("fiber-htsg"):
        return 1e-4
    if name.startswith("profile-"):
        return 1e-6
    return 1e-3


def read_cases(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    cols = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    return cols


@pytest.mark.parametrize("name", sorted(p.name for p in VECTORS.iterdir() if p.is_dir()))
def test_golden_vectors(name):
    material = woven.Material.load(VECTORS / name / "material.toml")
    c = read_cases(VECTORS / name / "cases.csv")
    wi = woven.from_spherical(c["theta_i"], c["phi_i"])
    wo = woven.from_spherical(c["theta_r"], c["phi_r"])
    got = material.build(550.0).eval(wi, wo)
    want = c["brdf"]
    rel = tolerance(name, material)
    err = np.abs(got - want)
    ok = (err <= rel * np.abs(want)) | (err <= 1e-9)
    assert ok.all(), f"{name}: got {got[~ok]}, want {want[~ok]}, rel tolerance {rel}"
    assert len(want) == 12


def test_eval_is_the_clis_bit_for_bit(cli, tmp_path):
    rng = np.random.default_rng(3)
    n = 300
    angles = np.column_stack(
        [
            rng.uniform(0, 1.5, n),
            rng.uniform(-4, 4, n),
            rng.uniform(0, 1.5, n),
            rng.uniform(-4, 4, n),
        ]
    )
    path = tmp_path / "dirs.csv"
    with open(path, "w") as f:
        f.write("theta_i,phi_i,theta_r,phi_r\n")
        for row in angles:
            f.write(",".join(repr(float(x)) for x in row) + "\n")
    for preset in ["polyester-sateen", "flat"]:
        if preset == "flat":
            material = woven.Material.from_toml(
                "[fiber]\neta = 1.5\nroughness = 0.3\ndiffuse = 0.1\n"
            )
            mpath = tmp_path / "flat.toml"
            mpath.write_text(material.to_toml())
            arg = mpath
        else:
            material, arg = woven.Material.preset(preset), preset
        out = cli("eval", "--material", arg, "--input", path, "--wavelength-nm", 600)
        want = np.array([float(line.split(",")[4]) for line in out.splitlines()[1:]])
        wi = woven.from_spherical(angles[:, 0], angles[:, 1])
        wo = woven.from_spherical(angles[:, 2], angles[:, 3])
        got = material.build(wavelength_nm=600.0).eval(wi, wo)
        np.testing.assert_array_equal(got, want)


def test_from_spherical_is_the_formula_and_round_trips():
    theta = np.linspace(0, math.pi / 2, 7)
    phi = np.linspace(-3, 3, 7)
    d = woven.from_spherical(theta, phi)
    want = np.column_stack(
        [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)]
    )
    np.testing.assert_allclose(d, want, atol=1e-15)
    t, p = woven.to_spherical(d)
    np.testing.assert_allclose(t, theta, atol=1e-12)
    np.testing.assert_allclose(p[1:], phi[1:], atol=1e-12)  # φ is undefined at the pole
    assert woven.from_spherical(0.5, 0.25).shape == (3,)
    assert isinstance(woven.to_spherical([0, 0, 1])[0], float)


def test_shapes_broadcast_and_scalars():
    model = woven.Material.preset("polyester-sateen").build()
    rng = np.random.default_rng(1)
    wi, wo = random_dirs(rng, 5), random_dirs(rng, 5)
    f = model.eval(wi, wo)
    assert f.shape == (5,) and f.dtype == np.float64
    one = model.eval(wi[0], wo)
    assert one.shape == (5,)
    np.testing.assert_array_equal(one, model.eval(np.repeat(wi[:1], 5, axis=0), wo))
    assert isinstance(model.eval(wi[0], wo[0]), float)
    assert model.eval(wi[0], wo[0]) == f[0]
    # Lists and float32 arrays are accepted (converted to float64).
    assert model.eval(wi[0].tolist(), [wo[0].tolist()])[0] == f[0]
    f32 = model.eval(wi.astype(np.float32), wo.astype(np.float32))
    np.testing.assert_allclose(f32, f, rtol=1e-5)
    # Non-contiguous views are read correctly.
    big = np.repeat(wi, 2, axis=0)[::2]
    np.testing.assert_array_equal(model.eval(big, wo), f)
    # Below the surface: 0.
    below = wi * np.array([1, 1, -1])
    assert (model.eval(below, wo) == 0).all()
    # Empty batches.
    assert model.eval(np.zeros((0, 3)), np.zeros((0, 3))).shape == (0,)


def test_bad_shapes_are_value_errors_naming_the_shape():
    model = woven.Material.preset("polyester-sateen").build()
    good = np.array([[0.0, 0.0, 1.0]])
    for bad, name in [
        (np.zeros((4, 2)), "wi"),
        (np.zeros((2, 3, 3)), "wi"),
        (np.zeros(4), "wi"),
        (5.0, "wi"),
        ("up", "wi"),
        ([[0, 0], [1]], "wi"),
    ]:
        with pytest.raises(ValueError, match=rf"`{name}`.*\(N, 3\) or \(3,\)"):
            model.eval(bad, good)
    with pytest.raises(ValueError, match=r"`wi` has 4 rows and `wo` has 2"):
        model.eval(np.tile(good, (4, 1)), np.tile(good, (2, 1)))
    with pytest.raises(ValueError, match=r"theta_i"):
        model.albedo(2.0)
    with pytest.raises(ValueError, match=r"shape \(N,\)"):
        model.albedo(np.zeros((2, 2)))


def test_nan_huge_and_zero_directions_are_refused_naming_the_row():
    model = woven.Material.preset("polyester-sateen").build()
    up = np.array([0.0, 0.0, 1.0])
    for k, bad in enumerate([[np.nan, 0, 1], [np.inf, 0, 1], [1e300, 1e300, 1e300], [0, 0, 0]]):
        rows = np.array([up, up, bad])
        with pytest.raises(ValueError, match=r"`wo`\[2\] = \["):
            model.eval(up, rows)


def test_albedo_is_the_librarys_and_at_most_one(flat):
    model = flat.build()
    a = model.albedo(np.array([0.0, 0.5, 1.2]))
    assert a.shape == (3,) and ((a > 0) & (a <= 1)).all()
    assert model.albedo(0.5) == a[1]
    # The hemisphere integral of f cos θo by Monte Carlo agrees.
    rng = np.random.default_rng(2)
    wo = random_dirs(rng, 200_000)
    wi = woven.from_spherical(0.5, 0.0)
    mc = 2 * math.pi * np.mean(model.eval(wi, wo) * wo[:, 2])
    assert abs(mc - a[1]) < 0.01, (mc, a[1])


def test_gonio_is_the_clis(cli):
    out = cli("gonio", "-m", "polyester-sateen", "--azimuth-deg", "0,90", "--tilt-deg=-30,0,30")
    rows = np.array([[float(x) for x in line.split(",")] for line in out.splitlines()[1:]])
    g = woven.gonio(woven.Material.preset("polyester-sateen"), [0, 90], [-30, 0, 30])
    got = np.column_stack(
        [g[k] for k in ["azimuth_deg", "tilt_deg", "theta_i", "theta_r", "radiance"]]
    )
    np.testing.assert_array_equal(got, rows)
    # A Model gives the same; the default tilts are the paper's 29.
    model = woven.Material.preset("polyester-sateen").build()
    np.testing.assert_array_equal(
        woven.gonio(model, [0, 90], [-30, 0, 30])["radiance"], g["radiance"]
    )
    assert len(woven.gonio(model, [0])["tilt_deg"]) == 29
    with pytest.raises(ValueError, match="tilt"):
        woven.gonio(model, [0], [45])
    with pytest.raises(TypeError):
        woven.gonio("polyester-sateen")
