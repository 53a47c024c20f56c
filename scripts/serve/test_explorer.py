"""The explorer in a real browser (Playwright driving Debian's Chromium, headless).

Run by scripts/serve/ci.sh, which starts `woven serve` and sets WOVEN_SERVE_URL, WOVEN_BIN and
CHROMIUM (and SCREENSHOT, a PNG path, to keep a picture of the page).
"""

import csv
import math
import os
import subprocess

import pytest
from playwright.sync_api import expect, sync_playwright

URL = os.environ["WOVEN_SERVE_URL"]
WOVEN = os.environ["WOVEN_BIN"]
CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")
# Views of twisted and isotropic yarns take seconds on two cores.
SLOW_MS = 120_000


@pytest.fixture(scope="module")
def page():
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=["--no-sandbox"])
        pg = browser.new_page(viewport={"width": 1400, "height": 1000})
        errors = []
        pg.on("pageerror", lambda e: errors.append(str(e)))
        pg.goto(URL)
        yield pg
        browser.close()
        assert not errors, f"errors on the page: {errors}"


def generation(pg):
    return int(pg.get_attribute("#views", "data-generation"))


def wait_views(pg, after):
    """Waits until the views finished a computation newer than generation `after`."""
    pg.wait_for_function(
        "g => Number(document.getElementById('views').dataset.generation) > g"
        " && document.getElementById('views').dataset.busy === '0'",
        arg=after,
        timeout=SLOW_MS,
    )


def plane_rows(pg):
    return pg.eval_on_selector_all(
        "#plane-table tr[data-f]",
        "rows => rows.map(r => ({ti: r.dataset.thetaI, pi: r.dataset.phiI,"
        " tr: r.dataset.thetaR, pr: r.dataset.phiR, f: Number(r.dataset.f)}))",
    )


def woven_eval(tmp_path, toml_text, rows):
    material = tmp_path / "material.toml"
    material.write_text(toml_text)
    dirs = tmp_path / "dirs.csv"
    dirs.write_text("theta_i,phi_i,theta_r,phi_r\n" + "".join(f"{r['ti']},{r['pi']},{r['tr']},{r['pr']}\n" for r in rows))
    out = tmp_path / "brdf.csv"
    subprocess.run([WOVEN, "eval", "--material", str(material), "--input", str(dirs), "-o", str(out)], check=True)
    with open(out) as f:
        return [float(r["brdf"]) for r in csv.DictReader(f)]


def test_the_page_edits_a_material_and_its_views_follow(page, tmp_path):
    pg = page
    wait_views(pg, 0)
    # A preset: belt cloth (twisted fibres: slower, with progress), then the sateen.
    g = generation(pg)
    pg.select_option("#preset", "belt-cloth")
    wait_views(pg, g)
    expect(pg.locator("#summary")).to_contain_text("twist")
    g = generation(pg)
    pg.select_option("#preset", "polyester-sateen")
    wait_views(pg, g)
    before = plane_rows(pg)
    assert len(before) == 179

    # Move the roughness slider with the keyboard, as a user does: five steps of 0.005.
    g = generation(pg)
    slider = pg.locator("#fiber-roughness-range")
    slider.focus()
    for _ in range(5):
        slider.press("ArrowRight")
    # Superseded requests are cancelled; wait for the views of the last value.
    pg.wait_for_function(
        "JSON.parse(document.getElementById('views').dataset.material || '{}').fiber?.roughness === 0.075"
        " && document.getElementById('views').dataset.busy === '0'",
        timeout=SLOW_MS,
    )
    expect(pg.locator("#fiber-roughness")).to_have_value("0.075")
    expect(pg.locator("#toml-view")).to_contain_text("roughness = 0.075")
    after = plane_rows(pg)
    changed = sum(1 for a, b in zip(before, after) if abs(a["f"] - b["f"]) > 1e-9 * max(a["f"], b["f"]))
    assert changed > 100, f"only {changed} plotted values changed"

    # The plotted numbers are `woven eval`'s for the material the page shows.
    probes = [after[k] for k in (20, 89, 120, 134, 160)]
    want = woven_eval(tmp_path, pg.text_content("#toml-view"), probes)
    for p, w in zip(probes, want):
        assert math.isclose(p["f"], w, rel_tol=1e-12, abs_tol=1e-300), (p, w)


def test_plots_and_the_material_download(page):
    pg = page
    with pg.expect_download() as d:
        pg.click('[data-csv="plane"]')
    lines = open(d.value.path()).read().splitlines()
    rows = plane_rows(pg)
    assert lines[0] == "theta_i,phi_i,theta_r,phi_r,value"
    assert len(lines) == 1 + len(rows)
    assert float(lines[1].split(",")[4]) == rows[0]["f"]
    with pg.expect_download() as d:
        pg.click("#download-toml")
    assert "roughness = 0.075" in open(d.value.path()).read()
    with pg.expect_download() as d:
        pg.click('[data-png="gonio-canvas"]')
    assert open(d.value.path(), "rb").read(8) == b"\x89PNG\r\n\x1a\n"


def test_measured_data_is_laid_over_the_model(page, tmp_path):
    pg = page
    rows = plane_rows(pg)[::10]
    model = woven_eval(tmp_path, pg.text_content("#toml-view"), rows)
    data = tmp_path / "measured.csv"
    # "Measurements" 10 % above the model: the RMS log ratio is ln 1.1.
    data.write_text("theta_i,phi_i,theta_r,phi_r,value\n" + "".join(
        f"{r['ti']},{r['pi']},{r['tr']},{r['pr']},{1.1 * f!r}\n" for r, f in zip(rows, model)))
    # A malformed file first: its error, naming the line, in place of the comparison.
    bad = tmp_path / "bad.csv"
    bad.write_text("theta_i,phi_i,theta_r,phi_r,value\n0.1,0,x,0,1\n")
    pg.set_input_files("#data-file", str(bad))
    expect(pg.locator("#data-status")).to_contain_text("bad.csv: line 2, column `theta_r`")
    pg.set_input_files("#data-file", str(data))
    pg.wait_for_function("document.getElementById('data-status').dataset.rows !== undefined", timeout=SLOW_MS)
    assert int(pg.get_attribute("#data-status", "data-rows")) == len(rows)
    log_rms = float(pg.get_attribute("#data-status", "data-log-rms"))
    assert math.isclose(log_rms, math.log(1.1), rel_tol=1e-9), log_rms


    # A bundled measurement, picked by name: CUReT's linen, 205 rows.
    pg.select_option("#data-bundled", "curet-44-linen")
    pg.wait_for_function(
        "document.getElementById('data-status').dataset.rows === '205'", timeout=SLOW_MS
    )
    expect(pg.locator("#data-status")).to_contain_text("relatively calibrated")
    # The fit button: the cloth model fitted to the linen from the page's material.
    pg.click("#data-fit")
    pg.wait_for_function(
        "document.getElementById('fit-status').dataset.logRms !== undefined", timeout=3 * SLOW_MS
    )
    assert float(pg.get_attribute("#fit-status", "data-log-rms")) < 0.3


def test_an_out_of_range_value_is_shown_next_to_its_field(page):
    pg = page
    box = pg.locator("#fiber-roughness")
    box.fill("7")
    box.press("Enter")
    slot = pg.locator('[data-error-for="fiber.roughness"]')
    expect(slot).to_contain_text("7: expected a number in [0.005, 2]")
    expect(box).to_have_class("invalid")
    expect(pg.locator("#views-status")).to_contain_text("not updated")
    # The page still works: a valid value clears the error and the views update.
    g = generation(pg)
    box.fill("0.1")
    box.press("Enter")
    wait_views(pg, g)
    expect(slot).to_be_empty()


def test_clicking_the_hemisphere_moves_the_light(page):
    pg = page
    g = generation(pg)
    box = pg.locator("#hemi-canvas").bounding_box()
    # The disc's centre is at (140, 150) of the 380 × 300 canvas, radius 130: click at 0.5 r
    # straight up (the warp, y): θi = 30°, φi = 90°.
    sx, sy = box["width"] / 380, box["height"] / 300
    pg.mouse.click(box["x"] + 140 * sx, box["y"] + (150 - 65) * sy)
    wait_views(pg, g)
    expect(pg.locator("#incidence")).to_contain_text("θi = 30.0°, φi = 90.0°")
    rows = plane_rows(pg)
    assert math.isclose(float(rows[0]["pi"]), math.pi / 2, rel_tol=1e-9)
    shot = os.environ.get("SCREENSHOT")
    if shot:
        pg.wait_for_function("Number(document.getElementById('preview-canvas').dataset.pass || 0) >= 32", timeout=SLOW_MS)
        pg.screenshot(path=shot, full_page=True)
