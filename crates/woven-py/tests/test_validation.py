"""Every entry point validates its arrays alike (crates/woven-py/src/arrays.rs): directions finite
and unit length within woven.UNIT_TOLERANCE, uv and footprints finite, colours, albedos and
uniforms in [0, 1], complex arrays refused; an empty batch gives empty results everywhere."""

import numpy as np
import pytest

import woven

UP = np.array([0.0, 0.0, 1.0])
UV = [0.1, 0.2]


@pytest.fixture(scope="module")
def objs(sateen, sateen_table):
    return {
        "model": sateen.build(),
        "table": sateen_table,
        "surface": woven.Surface(table=sateen_table),
        "sheen": woven.Sheen(),
    }


# Each call that takes directions, with `d` in place of the argument named last.
DIRECTION_CALLS = {
    "Model.eval": (lambda o, d: o["model"].eval(d, UP), "wi"),
    "Model.eval/wo": (lambda o, d: o["model"].eval(UP, d), "wo"),
    "Table.eval": (lambda o, d: o["table"].eval(d, UP), "wi"),
    "Table.eval_interpolated": (lambda o, d: o["table"].eval_interpolated(UP, d), "wo"),
    "Table.eval_dyed": (lambda o, d: o["table"].eval_dyed(d, UP, [[0.5, 0.5]]), "wi"),
    "Table.pdf": (lambda o, d: o["table"].pdf(UP, d), "wo"),
    "Table.sample": (lambda o, d: o["table"].sample(d, [0.5, 0.5]), "known"),
    "Table.sample_direction": (lambda o, d: o["table"].sample_direction(d, [0.5, 0.5]), "wi"),
    "Surface.eval": (lambda o, d: o["surface"].eval(UV, d, UP), "wi"),
    "Surface.pdf": (lambda o, d: o["surface"].pdf(UV, UP, d), "wo"),
    "Surface.sample": (lambda o, d: o["surface"].sample(UV, d, 0.5, [0.5, 0.5]), "known"),
    "Bsdf.eval": (lambda o, d: o["sheen"].eval(d, UP), "wi"),
    "Bsdf.pdf": (lambda o, d: o["sheen"].pdf(UP, d), "wo"),
    "Bsdf.sample": (lambda o, d: o["sheen"].sample(d, 0.5, [0.5, 0.5]), "known"),
}


@pytest.mark.parametrize("call", sorted(DIRECTION_CALLS))
def test_directions_must_be_unit_length(objs, call):
    f, name = DIRECTION_CALLS[call]
    with pytest.raises(ValueError, match=rf"`{name}`\[1\] = \[0\.0, 0\.0, 2\.0\]: expected a unit "
                       r"vector, its length within 1e-6 of 1 \(this one's is 2\)"):
        f(objs, np.array([UP, [0.0, 0.0, 2.0]]))
    with pytest.raises(ValueError, match=rf"`{name}` = \[0\.6, 0\.0, 0\.6\]: .*is 0\.84"):
        f(objs, [0.6, 0.0, 0.6])
    # Within the tolerance (float32 rounding and better) is a unit vector.
    f(objs, UP * (1 + 0.5e-6))
    f(objs, np.array([[0.6, 0.0, 0.8]], dtype=np.float32))


@pytest.mark.parametrize("call", sorted(DIRECTION_CALLS))
def test_non_finite_directions_are_refused(objs, call):
    f, name = DIRECTION_CALLS[call]
    for bad, shown in [(np.nan, "NaN"), (np.inf, "inf"), (-np.inf, "-inf")]:
        with pytest.raises(ValueError, match=rf"`{name}`\[0\] = \[{shown}, 0\.0, 1\.0\]: "
                           "expected finite numbers"):
            f(objs, np.array([[bad, 0.0, 1.0], UP]))


@pytest.mark.parametrize("call", sorted(DIRECTION_CALLS))
def test_complex_arrays_are_type_errors_naming_the_argument(objs, call):
    f, name = DIRECTION_CALLS[call]
    with pytest.raises(TypeError, match=rf"`{name}` is a complex array \(complex128\)"):
        f(objs, UP + 0j)
    with pytest.raises(TypeError, match=rf"`{name}` is a complex array \(complex64\)"):
        f(objs, np.array([UP], dtype=np.complex64))


def test_table_and_model_agree_on_what_they_accept(objs):
    long = np.array([0.0, 0.0, 1.5])
    for f in (objs["model"].eval, objs["table"].eval):
        with pytest.raises(ValueError, match=r"`wi` = \[0\.0, 0\.0, 1\.5\]"):
            f(long, UP)


def test_points_colours_albedos_and_uniforms_are_checked(objs):
    s, t = objs["surface"], objs["table"]
    with pytest.raises(ValueError, match=r"`uv`\[1\] = \[NaN, 0\.5\]: expected finite numbers"):
        s.eval([UV, [np.nan, 0.5]], UP, UP)
    with pytest.raises(ValueError, match=r"`footprint` = \[inf, 0\.0, 0\.0, 0\.1\]"):
        s.eval(UV, UP, UP, footprint=[np.inf, 0, 0, 0.1])
    with pytest.raises(ValueError, match=r"`weft_color` = \[1\.5, 0\.0, 0\.0\]: expected "
                       r"fractions in \[0, 1\]"):
        s.eval(UV, UP, UP, weft_color=[1.5, 0, 0])
    with pytest.raises(ValueError, match=r"`warp_color`\[0\] = \[NaN, 0\.5, 0\.5\]: expected "
                       r"finite fractions in \[0, 1\]"):
        s.sample(UV, UP, 0.5, [0.5, 0.5], warp_color=[[np.nan, 0.5, 0.5]])
    with pytest.raises(TypeError, match=r"`weft_color` is a complex array"):
        s.eval(UV, UP, UP, weft_color=np.array([0.5, 0.5, 0.5j]))
    with pytest.raises(ValueError, match=r"`uc` = 2: expected uniforms in \[0, 1\]"):
        s.sample(UV, UP, 2.0, [0.5, 0.5])
    with pytest.raises(ValueError, match=r"`u`\[0\] = \[0\.5, -0\.1\]: expected uniforms"):
        t.sample(UP, [[0.5, -0.1]])
    with pytest.raises(ValueError, match=r"`u` = \[NaN, 0\.5\]: expected finite uniforms"):
        objs["sheen"].sample(UP, 0.5, [np.nan, 0.5])
    with pytest.raises(ValueError, match=r"`albedos`\[0\] = \[2\.0, 0\.5\]: expected fractions"):
        t.eval_dyed(UP, UP, [[2.0, 0.5]])
    with pytest.raises(ValueError, match=r"`phi_i` = NaN: expected finite numbers"):
        objs["model"].albedo(0.5, np.nan)
    with pytest.raises(ValueError, match=r"`theta`\[1\] = inf"):
        woven.from_spherical([0.1, np.inf], 0.0)
    with pytest.raises(ValueError, match=r"`d` = \[NaN, 0\.0, 1\.0\]: expected finite numbers"):
        woven.to_spherical([np.nan, 0.0, 1.0])
    # to_spherical takes any finite vector.
    assert woven.to_spherical([0.0, 0.0, 2.0]) == (0.0, 0.0)


def test_a_nan_direction_no_longer_samples_nan_with_a_density(objs):
    with pytest.raises(ValueError, match=r"`known` = \[NaN, 0\.0, 1\.0\]"):
        objs["surface"].sample(UV, [np.nan, 0.0, 1.0], 0.5, [0.5, 0.5])


def test_empty_batches_give_empty_results_everywhere(objs):
    m, t, s, b = objs["model"], objs["table"], objs["surface"], objs["sheen"]
    none, none_uv, none_u = np.zeros((0, 3)), np.zeros((0, 2)), np.zeros((0, 2))

    def shapes(x):
        return tuple(a.shape for a in x) if isinstance(x, tuple) else x.shape

    assert shapes(m.eval(none, UP)) == (0,)
    assert shapes(m.eval(none, none)) == (0,)
    assert shapes(m.albedo(np.zeros(0))) == (0,)
    assert shapes(t.eval(UP, none)) == (0,)
    assert shapes(t.pdf(none, none)) == (0,)
    assert shapes(t.eval_dyed(none, UP, [[0.5, 0.5], [0.2, 0.1]])) == (0, 2)
    assert shapes(t.sample(none, [0.5, 0.5])) == ((0, 3), (0,), (0,))
    assert shapes(t.sample(UP, none_u)) == ((0, 3), (0,), (0,))
    assert shapes(t.sample_direction(none, none_u)) == ((0, 3), (0,))
    assert shapes(s.eval(none_uv, UP, UP)) == (0, 3)
    assert shapes(s.eval(UV, none, UP, weft_color=np.zeros((0, 3)))) == (0, 3)
    assert shapes(s.pdf(none_uv, none, none)) == (0,)
    assert shapes(s.sample(none_uv, UP, 0.5, [0.5, 0.5])) == ((0, 3), (0, 3), (0,))
    assert shapes(s.sample(UV, UP, np.zeros(0), [0.5, 0.5])) == ((0, 3), (0, 3), (0,))
    assert shapes(s.lobes(none_uv)) == ((0, 6),) * 4
    assert shapes(b.eval(none, UP)) == (0, 3)
    assert shapes(b.pdf(UP, none)) == (0,)
    assert shapes(b.sample(none, 0.5, [0.5, 0.5])) == ((0, 3), (0, 3), (0,))
    assert shapes(b.albedo(np.zeros(0))) == (0, 3)
    assert shapes(woven.from_spherical(np.zeros(0), 0.0)) == (0, 3)
    assert shapes(woven.to_spherical(none)) == ((0,), (0,))
    # An empty batch against a batch of several is still a mismatch.
    with pytest.raises(ValueError, match=r"`wi` has 0 rows and `wo` has 2"):
        m.eval(none, np.array([UP, UP]))
    with pytest.raises(ValueError, match=r"`wi` has 2 rows where others have 0"):
        s.eval(none_uv, np.array([UP, UP]), UP)
