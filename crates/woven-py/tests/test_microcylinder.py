"""woven.Microcylinder (the microcylinder fabrics), the baselines woven.Sheen and
woven.RoughPlastic, and woven.open_material: the CLI on the same inputs, the direction
conventions, sampling against the density and the albedo, and errors."""

import numpy as np
import pytest

import woven
from conftest import random_dirs

# Velvet is the one preset that is not symmetric under x → −x (its pile leans): a swapped sign
# or a swapped direction would show.
VELVET = "microcylinder-velvet"
CHARMEUSE = "microcylinder-satin-charmeuse"


def angles_csv(path, angles):
    with open(path, "w") as f:
        f.write("theta_i,phi_i,theta_r,phi_r\n")
        for row in angles:
            f.write(",".join(repr(float(x)) for x in row) + "\n")


def test_eval_is_woven_eval_rgb_bit_for_bit(cli, tmp_path):
    rng = np.random.default_rng(11)
    n = 40
    angles = np.column_stack(
        [rng.uniform(0, 1.5, n), rng.uniform(-4, 4, n), rng.uniform(0, 1.5, n), rng.uniform(-4, 4, n)]
    )
    path = tmp_path / "dirs.csv"
    angles_csv(path, angles)
    wi = woven.from_spherical(angles[:, 0], angles[:, 1])  # toward the light
    wo = woven.from_spherical(angles[:, 2], angles[:, 3])  # toward the viewer
    for name in [VELVET, CHARMEUSE]:
        out = cli("eval", "--material", name, "--rgb", "--input", path)
        want = np.array([[float(x) for x in line.split(",")[4:]] for line in out.splitlines()[1:]])
        fabric = woven.Microcylinder(name)
        got = fabric.eval(wi, wo)
        assert got.shape == (n, 3)
        np.testing.assert_array_equal(got, want)
        # One pair gives (3,); one direction broadcasts against many.
        np.testing.assert_array_equal(fabric.eval(wi[0], wo[0]), want[0])
        np.testing.assert_array_equal(fabric.eval(wi[:5], wo[0]), fabric.eval(wi[:5], wo[[0] * 5]))
        # Without --rgb the CLI writes the luminance (Rec. 709) of the same values.
        out = cli("eval", "--material", name, "--input", path)
        lum = np.array([float(line.split(",")[4]) for line in out.splitlines()[1:]])
        np.testing.assert_allclose(got @ [0.2126, 0.7152, 0.0722], lum, rtol=1e-12)


def test_directions_follow_the_convention(cli, tmp_path):
    """wi toward the light (the CLI's θi, φi), wo toward the viewer, f without the cosine, 0
    below the surface; velvet tells x from −x."""
    fabric = woven.Microcylinder(VELVET)
    light = woven.from_spherical(0.6, 0.4)
    view = woven.from_spherical(0.9, 2.6)
    path = tmp_path / "one.csv"
    angles_csv(path, [[0.6, 0.4, 0.9, 2.6], [0.9, 2.6, 0.6, 0.4]])
    out = cli("eval", "--material", VELVET, "--rgb", "--input", path)
    rows = [[float(x) for x in line.split(",")[4:]] for line in out.splitlines()[1:]]
    np.testing.assert_array_equal(fabric.eval(light, view), rows[0])
    np.testing.assert_array_equal(fabric.eval(view, light), rows[1])
    mirrored = lambda d: d * [-1, 1, 1]  # noqa: E731
    assert not np.allclose(fabric.eval(mirrored(light), mirrored(view)), rows[0], rtol=1e-3)
    below = light * [1, 1, -1]
    np.testing.assert_array_equal(fabric.eval(below, view), [0, 0, 0])
    np.testing.assert_array_equal(fabric.eval(light, view * [1, 1, -1]), [0, 0, 0])
    # The energy guard only lowers the printed model.
    assert (fabric.eval(light, view) <= fabric.eval_unguarded(light, view) + 1e-15).all()


@pytest.mark.parametrize("mode", ["radiance", "importance"])
def test_sampling_agrees_with_pdf_and_albedo(mode):
    fabric = woven.Microcylinder(CHARMEUSE)
    rng = np.random.default_rng(5)
    n = 3000
    known = woven.from_spherical(0.7, 0.3)
    drawn, f, pdf = fabric.sample(known, rng.random(n), rng.random((n, 2)), mode=mode)
    ok = pdf > 0
    assert ok.mean() > 0.5  # the rest: tangent cones below the horizon, rejected
    wi, wo = (drawn, known) if mode == "radiance" else (known, drawn)
    wi = np.broadcast_to(wi, drawn.shape)[ok]
    wo = np.broadcast_to(wo, drawn.shape)[ok]
    np.testing.assert_allclose(f[ok], fabric.eval(wi, wo), rtol=1e-12)
    np.testing.assert_allclose(pdf[ok], fabric.pdf(wi, wo, mode=mode), rtol=1e-9)
    assert (drawn[~ok] == 0).all()
    if mode == "importance":
        # ∫ f cos θo dωo for light from `known`: the mean weight is the directional albedo.
        weight = np.zeros((n, 3))
        weight[ok] = f[ok] * (drawn[ok, 2] / pdf[ok])[:, None]
        a = fabric.albedo(0.7, 0.3)
        assert a.shape == (3,)
        mean, se = weight.mean(axis=0), weight.std(axis=0) / np.sqrt(n)
        assert (np.abs(mean - a) <= 5 * se + 0.01 * a).all(), (mean, se, a)
        assert (a > 0).all() and (a <= 1).all()
        assert fabric.albedo(np.array([0.2, 0.7]), 0.3).shape == (2, 3)


def test_gonio_of_a_fabric_is_woven_gonio(cli):
    out = cli("gonio", "-m", VELVET, "--azimuth-deg", "0,90", "--tilt-deg=-30,0,30")
    rows = np.array([[float(x) for x in line.split(",")] for line in out.splitlines()[1:]])
    g = woven.gonio(woven.Microcylinder(VELVET), [0, 90], [-30, 0, 30])
    got = np.column_stack([g[k] for k in ["azimuth_deg", "tilt_deg", "theta_i", "theta_r", "radiance"]])
    np.testing.assert_array_equal(got, rows)


def test_names_files_and_errors(tmp_path):
    assert set(woven.Microcylinder.preset_names()) == {
        "microcylinder-linen-plain",
        "microcylinder-silk-crepe-de-chine",
        "microcylinder-satin-charmeuse",
        "microcylinder-satin-charmeuse-back",
        "microcylinder-silk-shot",
        "microcylinder-velvet",
    }
    fabric = woven.Microcylinder(CHARMEUSE)
    assert fabric.name == CHARMEUSE and isinstance(fabric, woven.Bsdf)
    assert "glossy" in fabric.lobes and CHARMEUSE in repr(fabric)
    assert isinstance(woven.open_material(VELVET), woven.Microcylinder)
    assert isinstance(woven.open_material("silk"), woven.Material)
    with pytest.raises(ValueError, match=r"satin-nope.*microcylinder-velvet"):
        woven.Microcylinder("satin-nope")
    with pytest.raises(ValueError, match=r"woven material.*woven\.Material"):
        woven.Microcylinder("silk")
    with pytest.raises(OSError):
        woven.Microcylinder(tmp_path / "missing.toml")
    with pytest.raises(ValueError, match="mode"):
        fabric.pdf([0, 0, 1], [0, 0, 1], mode="both")
    with pytest.raises(ValueError, match=r"`wo` must have shape"):
        fabric.eval([0, 0, 1], [[0, 1]])
    with pytest.raises(ValueError, match="theta_i"):
        fabric.albedo(2.0)
    with pytest.raises(TypeError):
        woven.Bsdf()


def test_baselines():
    sheen = woven.Sheen(sheen_color=0.0)
    wi, wo = woven.from_spherical(0.3, 0.0), woven.from_spherical(1.2, 2.0)
    # No sheen: the Lambertian base, 0.5/π.
    np.testing.assert_allclose(sheen.eval(wi, wo), [0.5 / np.pi] * 3, rtol=1e-15)
    plastic = woven.RoughPlastic(distribution="ggx", alpha=0.2, diffuse_reflectance=[0.6, 0.3, 0.1])
    rng = np.random.default_rng(2)
    a, b = random_dirs(rng, 50), random_dirs(rng, 50)
    f = plastic.eval(a, b)
    assert f.shape == (50, 3) and (f > 0).all()
    # Mitsuba's rough plastic is reciprocal.
    np.testing.assert_allclose(plastic.eval(b, a), f, rtol=1e-12)
    with pytest.raises(ValueError, match="roughness"):
        woven.Sheen(roughness=0.01)
    with pytest.raises(ValueError, match="distribution"):
        woven.RoughPlastic(distribution="phong")
    with pytest.raises(ValueError, match="diffuse_reflectance"):
        woven.RoughPlastic(diffuse_reflectance=[0.5, 2.0, 0.5])
