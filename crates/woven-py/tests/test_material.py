"""woven.Material: presets, files, sections, replace, errors; against the CLI."""

import pickle

import numpy as np
import pytest

import woven
from conftest import REPO


def test_presets_are_the_clis(cli):
    # The woven presets' table comes first; the microcylinder fabrics' follows a blank line.
    woven_table = cli("materials").split("\n\n")[0]
    names = [line.split()[0] for line in woven_table.splitlines()[1:] if line.strip()]
    assert woven.presets() == names
    for name in names:
        # `woven materials --show` prints the preset's TOML exactly; the preset parses the same.
        text = cli("materials", "--show", name)
        assert woven.Material.from_toml(text) == woven.Material.preset(name)


def test_a_sheer_transmits_what_the_cli_says(cli):
    # The preset opens its weave in [weave]; its model transmits, an opaque one does not.
    voile = woven.Material.preset("cotton-voile")
    assert voile.weave["gap"] == 0.5 and voile.weave["transmission"] is True
    model = voile.build()
    assert model.transmits and not woven.Material.preset("silk").build().transmits
    rows = cli("albedo", "-m", "cotton-voile", "--theta-deg", "0,60").splitlines()
    assert rows[0] == "theta_i_deg,albedo,transmittance"
    want = np.array([[float(x) for x in r.split(",")[1:]] for r in rows[1:]])
    theta = np.radians([0.0, 60.0])
    assert np.allclose(model.albedo(theta), want[:, 0], rtol=1e-12)
    assert np.allclose(model.transmittance(theta), want[:, 1], rtol=1e-12)
    assert woven.Material.preset("silk").build().transmittance(0.3) == 0.0


def test_toml_round_trip_and_sections():
    for name in woven.presets():
        m = woven.Material.preset(name)
        assert woven.Material.from_toml(m.to_toml()) == m
        assert pickle.loads(pickle.dumps(m)) == m
        assert m.name == name
        assert m.fiber.model == "rough" and m.fiber["eta"] == m.to_dict()["fiber"]["eta"]
        assert set(m.fiber.keys()) >= {"eta", "roughness", "diffuse", "normalization"}
    sateen = woven.Material.preset("polyester-sateen")
    assert sateen.fiber.roughness == 0.05
    assert sateen.yarn.lateral_length == 20.0 and "slope_std" in sateen.yarn
    belt = woven.Material.preset("belt-cloth")
    assert belt.weave.pattern == "twill-2/1"
    assert abs(belt.weft_fraction - 1 / 3) < 1e-15
    flat = woven.Material.from_toml("[fiber]\neta = 1.5\nroughness = 0.3\n")
    assert flat.yarn is None and flat.weave is None and flat.weft_fraction == 1.0
    with pytest.raises(AttributeError, match="roughness"):
        sateen.fiber.roughnes  # a typo: the message lists the keys


def test_replace_validates_like_a_file():
    sateen = woven.Material.preset("polyester-sateen")
    rough = sateen.replace({"fiber.roughness": 0.1, "yarn.slope_std": 0.5})
    assert rough.fiber.roughness == 0.1 and rough.yarn.slope_std == 0.5
    assert sateen.fiber.roughness == 0.05  # immutable
    plain = sateen.replace({"weave.weft_fraction": None, "weave.pattern": "plain"})
    assert plain.weft_fraction == 0.5
    matrix = sateen.replace({"weave": {"pattern": [[1, 0], [0, 0]]}})
    assert matrix.weft_fraction == 0.25
    flat = sateen.replace({"yarn": None, "weave": None})
    assert flat.yarn is None
    with pytest.raises(ValueError, match=r"fiber\.roughness.*7"):
        sateen.replace({"fiber.roughness": 7.0})
    with pytest.raises(ValueError, match="unknown field"):
        sateen.replace({"fiber.roughnes": 0.1})


def test_material_errors():
    with pytest.raises(ValueError, match="polyester-sateen, belt-cloth, silk"):
        woven.Material.preset("denim")
    with pytest.raises(ValueError, match=r"fiber\.roughness"):
        woven.Material.from_toml("[fiber]\neta = 1.6\nroughness = 7.0\n")
    with pytest.raises(ValueError, match="cloth.toml"):
        woven.Material.from_toml("[fiber\n", origin="cloth.toml")
    with pytest.raises(OSError, match="no-such.toml"):
        woven.Material.load("/nonexistent/no-such.toml")
    with pytest.raises(ValueError, match="wavelength"):
        woven.Material.preset("silk").build(wavelength_nm=-5.0)
    with pytest.raises(TypeError):
        woven.Material.load(42)


def test_material_files_load_from_paths(tmp_path):
    path = tmp_path / "cloth.toml"
    path.write_text(woven.Material.preset("silk").to_toml())
    assert woven.Material.load(path) == woven.Material.preset("silk")
    assert woven.Material.open(str(path)) == woven.Material.open("silk")
    # The repository's vector materials load as the Rust tests load them.
    for toml in (REPO / "crates" / "woven" / "tests" / "data" / "vectors").glob("*/material.toml"):
        assert woven.Material.load(toml).fiber.eta is not None


def test_a_huge_key_is_not_echoed_whole():
    """A key of a megabyte in a material is shown cut in the exception, as the CLI shows it."""
    key = "k" * (1 << 20)
    with pytest.raises(ValueError) as raised:
        woven.Material.from_toml(f"[fiber]\n{key} = 1\n")
    text = str(raised.value)
    assert len(text) < 1000 and "characters left out" in text, len(text)


def test_a_named_pipe_is_refused_not_waited_on(tmp_path):
    """`Material.load` and `Table.load` on a FIFO with no writer refuse it as not a regular file
    at once (opening it would block until a writer came)."""
    import os
    import threading

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    for load in (woven.Material.load, woven.Table.load):
        outcome = []

        def attempt():
            try:
                load(str(fifo))
                outcome.append("read")
            except Exception as e:  # noqa: BLE001 - the message is what is checked
                outcome.append(str(e))

        t = threading.Thread(target=attempt, daemon=True)
        t.start()
        t.join(10)
        assert not t.is_alive(), f"{load.__qualname__} blocked on a named pipe"
        assert "a named pipe, not a regular file" in outcome[0], outcome
