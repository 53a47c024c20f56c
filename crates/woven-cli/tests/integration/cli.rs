//! End-to-end tests of the `woven` binary.

use assert_cmd::Command;
use predicates::prelude::*;
use std::path::{Path, PathBuf};
use woven::material::Material;
use woven::Vec3;

const HEADER: &str = "theta_i,phi_i,theta_r,phi_r";

fn woven() -> Command {
    Command::cargo_bin("woven").unwrap()
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn material() -> PathBuf {
    fixture("polyester.toml")
}

/// A material file with `body` in a fresh directory (kept alive by the returned guard).
fn material_file(body: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.toml");
    std::fs::write(&path, body).unwrap();
    (dir, path)
}

/// Direction pairs covering normal, specular, back-scatter, out-of-plane and grazing cases.
const ROWS: &[[&str; 4]] = &[
    ["0", "0", "0", "0"],
    [
        "0.7853981633974483",
        "0",
        "0.7853981633974483",
        "3.141592653589793",
    ],
    ["0.5", "1.0", "0.3", "-2.0"],
    ["1.2", "0.1", "1.2", "0.1"],
    ["0.3", "12.5", "1.4", "4.0"],
    ["1.5707963267948966", "0", "0.5", "3.14"],
    ["0.25", "0", "1.5707963267948966", "3.14"],
];

fn rows_csv() -> String {
    let mut s = format!("{HEADER}\n");
    for row in ROWS {
        s.push_str(&row.join(","));
        s.push('\n');
    }
    s
}

/// Checks `woven eval` output against the library, row by row.
fn check_eval_output(out: &str) {
    let model = Material::from_path(material())
        .unwrap()
        .build(550.0)
        .unwrap();
    let mut lines = out.lines();
    assert_eq!(lines.next(), Some("theta_i,phi_i,theta_r,phi_r,brdf"));
    let mut n = 0;
    for (line, row) in lines.zip(ROWS) {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), 5, "{line}");
        assert_eq!(&fields[..4], row, "input columns are echoed as read");
        let a: Vec<f64> = row.iter().map(|x| x.parse().unwrap()).collect();
        let want = if a[0] >= std::f64::consts::FRAC_PI_2 || a[2] >= std::f64::consts::FRAC_PI_2 {
            0.0
        } else {
            model.eval(
                Vec3::from_spherical(a[0], a[1]),
                Vec3::from_spherical(a[2], a[3]),
            )
        };
        let got: f64 = fields[4].parse().unwrap();
        assert_eq!(got, want, "row {row:?}: got {got}, library gives {want}");
        n += 1;
    }
    assert_eq!(n, ROWS.len());
}

#[test]
fn eval_matches_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("dirs.csv");
    let output = dir.path().join("brdf.csv");
    std::fs::write(&input, rows_csv()).unwrap();
    woven()
        .args(["eval", "--material"])
        .arg(material())
        .arg("--input")
        .arg(&input)
        .arg("--output")
        .arg(&output)
        .assert()
        .success()
        .stdout("");
    let out = std::fs::read_to_string(&output).unwrap();
    check_eval_output(&out);
    // The specular direction is bright, back-scatter far off it dim, grazing exactly 0.
    let brdf = |row: usize| -> f64 {
        let line = out.lines().nth(row + 1).unwrap();
        line.rsplit(',').next().unwrap().parse().unwrap()
    };
    assert!(brdf(1) > 10.0 * brdf(3), "{} vs {}", brdf(1), brdf(3));
    assert!(out.lines().nth(6).unwrap().ends_with(",0"));
    // Only the output file is left: no temporary file.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
}

#[test]
fn eval_reads_stdin_and_writes_stdout() {
    let assert = woven()
        .args(["eval", "-m"])
        .arg(material())
        .args(["--input", "-"])
        .write_stdin(rows_csv())
        .assert()
        .success();
    check_eval_output(&String::from_utf8(assert.get_output().stdout.clone()).unwrap());
}

#[test]
fn eval_bad_row_names_line_and_column_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.csv");
    woven()
        .args(["eval", "-m"])
        .arg(material())
        .args(["--input", "-", "--output"])
        .arg(&output)
        .write_stdin(format!("{HEADER}\n0.1,0,0.2,0\n0.1,0,abc,0\n0.3,0,0.2,0\n"))
        .assert()
        .code(1)
        .stderr(predicate::str::contains("line 3, column 3 `theta_r`"))
        .stderr(predicate::str::contains("`abc` is not a number"));
    assert!(!output.exists());
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "no temporary file left"
    );

    // An existing output is left untouched by a failed run.
    std::fs::write(&output, "previous").unwrap();
    woven()
        .args(["eval", "-m"])
        .arg(material())
        .args(["--input", "-", "--output"])
        .arg(&output)
        .write_stdin(format!("{HEADER}\n0.1,0,0.2\n"))
        .assert()
        .code(1)
        .stderr(predicate::str::contains("line 2"))
        .stderr(predicate::str::contains("column `phi_r` is missing"));
    assert_eq!(std::fs::read_to_string(&output).unwrap(), "previous");
}

#[test]
fn eval_rejects_non_finite_and_extra_columns() {
    for (body, needle) in [
        ("0.1,NaN,0.2,0\n", "line 2, column 2 `phi_i`"),
        ("0.1,0,0.2,inf\n", "line 2, column 4 `phi_r`"),
        ("0.1,0,0.2,0,7\n", "extra column 5"),
    ] {
        woven()
            .args(["eval", "-m"])
            .arg(material())
            .args(["--input", "-"])
            .write_stdin(format!("{HEADER}\n{body}"))
            .assert()
            .code(1)
            .stderr(predicate::str::contains(needle));
    }
}

#[test]
fn eval_rejects_a_wrong_header() {
    woven()
        .args(["eval", "-m"])
        .arg(material())
        .args(["--input", "-"])
        .write_stdin("theta_in,phi_in,theta_out,phi_out\n0.1,0,0.2,0\n")
        .assert()
        .code(1)
        .stderr(predicate::str::contains("line 1"))
        .stderr(predicate::str::contains(
            "expected the header `theta_i,phi_i,theta_r,phi_r`",
        ))
        .stderr(predicate::str::contains("theta_in"));
}

#[test]
fn eval_rejects_theta_out_of_range() {
    woven()
        .args(["eval", "-m"])
        .arg(material())
        .args(["--input", "-"])
        .write_stdin(format!("{HEADER}\n0.1,0,0.2,0\n0.1,0,0.2,0\n2.0,0,0.2,0\n"))
        .assert()
        .code(1)
        .stderr(predicate::str::contains("line 4, column 1 `theta_i`"))
        .stderr(predicate::str::contains(
            "value 2.0 is outside the valid range [0, π/2]",
        ));
}

#[test]
fn eval_reports_a_missing_input_file() {
    woven()
        .args(["eval", "-m"])
        .arg(material())
        .args(["--input", "/nonexistent/dirs.csv"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("/nonexistent/dirs.csv"));
}

#[test]
fn material_file_errors_name_the_key() {
    let (_dir, unknown) = material_file("[fiber]\neta = 1.6\nroughness = 0.1\nshininess = 3\n");
    woven()
        .args(["albedo", "--theta-deg", "45", "-m"])
        .arg(&unknown)
        .assert()
        .code(1)
        .stderr(predicate::str::contains("shininess"))
        .stderr(predicate::str::contains("m.toml"));

    let (_dir, rough) = material_file("[fiber]\neta = 1.6\nroughness = 7.5\n");
    woven()
        .args(["eval", "--input", "-", "-m"])
        .arg(&rough)
        .write_stdin(rows_csv())
        .assert()
        .code(1)
        .stdout("")
        .stderr(predicate::str::contains("fiber.roughness"))
        .stderr(predicate::str::contains("7.5"))
        .stderr(predicate::str::contains("[0.005, 2]"));

    woven()
        .args(["albedo", "-m", "/nonexistent/material.toml"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("/nonexistent/material.toml"));
}

#[test]
fn albedo_table_is_at_most_one() {
    let assert = woven()
        .args(["albedo", "--theta-deg", "0:80:20", "-m"])
        .arg(material())
        .assert()
        .success();
    let out = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    let mut lines = out.lines();
    assert_eq!(lines.next(), Some("theta_i_deg,albedo"));
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let (t, a) = l.split_once(',').unwrap();
            (t.parse().unwrap(), a.parse().unwrap())
        })
        .collect();
    assert_eq!(
        rows.iter().map(|r| r.0).collect::<Vec<_>>(),
        [0.0, 20.0, 40.0, 60.0, 80.0]
    );
    for (theta, albedo) in rows {
        assert!(albedo > 0.0 && albedo <= 1.0, "albedo {albedo} at {theta}°");
    }
}

/// The sheer preset lets light through: `albedo` adds its transmittance, and `eval` its
/// transmission toward a viewer below (`theta_r` > π/2), where an opaque material gives 0.
#[test]
fn a_transmitting_material_prints_its_transmittance_and_evaluates_below() {
    let out = woven()
        .args(["albedo", "-m", "cotton-voile", "--theta-deg", "0,60"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let out = String::from_utf8(out).unwrap();
    let mut lines = out.lines();
    assert_eq!(lines.next(), Some("theta_i_deg,albedo,transmittance"));
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        // The gaps alone pass 0.25 along the normal and 0.15 at 60°; nothing makes light.
        assert!(v[2] > 0.15 && v[1] + v[2] <= 1.0, "{line}");
    }
    let input = "theta_i,phi_i,theta_r,phi_r\n0.3,0,2.5,1\n0.3,0,0.5,1\n";
    let below = |material: &str| -> Vec<f64> {
        let out = woven()
            .args(["eval", "-m", material, "--input", "-"])
            .write_stdin(input)
            .assert()
            .success()
            .get_output()
            .stdout
            .clone();
        String::from_utf8(out)
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
            .collect()
    };
    let (voile, silk) = (below("cotton-voile"), below("silk"));
    assert!(voile[0] > 0.0 && voile[1] > 0.0, "{voile:?}");
    assert!(silk[0] == 0.0 && silk[1] > 0.0, "{silk:?}");
    woven()
        .args(["eval", "-m", "silk", "--input", "-"])
        .write_stdin("theta_i,phi_i,theta_r,phi_r\n0.3,0,3.5,1\n")
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "column 3 `theta_r`: value 3.5 is outside the valid range [0, π]",
        ));
}

#[test]
fn albedo_rejects_bad_angle_lists() {
    for (value, needle) in [
        (
            "0:95:5",
            "angle 90° is outside the valid range [0, 90) degrees",
        ),
        ("10:0:5", "STOP = 0 is below START = 10"),
        ("0:10:0", "STEP = 0 must be greater than 0"),
        ("0:10", "START:STOP:STEP"),
        ("5,x", "`x` is not a finite number"),
        ("-10", "[0, 90)"),
    ] {
        woven()
            .args(["albedo", "-m"])
            .arg(material())
            .args(["--theta-deg", value])
            .assert()
            .code(2)
            .stderr(predicate::str::contains("--theta-deg"))
            .stderr(predicate::str::contains(needle));
    }
}

#[test]
fn plots_write_valid_svg_and_png() {
    let dir = tempfile::tempdir().unwrap();
    for fig in ["fig3", "fig4", "fig5"] {
        let svg = dir.path().join(format!("{fig}.svg"));
        let png = dir.path().join(format!("{fig}.png"));
        woven()
            .args(["plot", fig, "--width", "640", "--height", "420", "-o"])
            .arg(&svg)
            .arg("-o")
            .arg(&png)
            .assert()
            .success();
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.starts_with("<svg"), "{fig}.svg");
        assert!(text.trim_end().ends_with("</svg>"), "{fig}.svg");
        assert!(
            text.matches("<polyline").count() >= 3,
            "{fig}.svg has its curves"
        );
        assert!(text.contains("Fig. "), "{fig}.svg has a title");
        assert!(
            text.contains("η = 1.6"),
            "{fig}.svg states the assumed index"
        );
        assert!(text.contains("sr⁻¹"), "{fig}.svg has the y unit");
        let bytes = std::fs::read(&png).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{fig}.png");
        assert!(
            bytes.len() > 10_000,
            "{fig}.png is only {} bytes",
            bytes.len()
        );
        // The IHDR chunk records the requested size.
        assert_eq!(u32::from_be_bytes(bytes[16..20].try_into().unwrap()), 640);
        assert_eq!(u32::from_be_bytes(bytes[20..24].try_into().unwrap()), 420);
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 6);
}

#[test]
fn plot_rejects_unknown_formats_and_figures() {
    let dir = tempfile::tempdir().unwrap();
    let jpg = dir.path().join("fig3.jpg");
    woven()
        .args(["plot", "fig3", "-o"])
        .arg(&jpg)
        .assert()
        .code(1)
        .stderr(predicate::str::contains(".svg or .png"));
    assert!(!jpg.exists());
    woven()
        .args(["plot", "fig42", "-o", "x.svg"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("fig42"));
    woven()
        .args(["plot", "fig3", "-o", "x.svg", "--width", "10"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--width"));
}

/// The modules of src/commands/ (files and folders, `mod.rs` aside), sorted: one per command.
fn command_modules() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/commands");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|entry| {
            let path = entry.unwrap().path();
            path.file_stem().unwrap().to_string_lossy().into_owned()
        })
        .filter(|name| name != "mod")
        .collect();
    names.sort();
    names
}

/// What `woven ARGS` prints on standard output (a successful run).
fn help_text(args: &[&str]) -> String {
    let out = woven().args(args).assert().success();
    String::from_utf8(out.get_output().stdout.clone()).unwrap()
}

/// The commands a help text lists under `Commands:` (each entry's first word; wrapped
/// descriptions are indented further), `help` aside, sorted.
fn listed_commands(help: &str) -> Vec<String> {
    let section = help
        .split_once("Commands:\n")
        .unwrap_or_else(|| panic!("no Commands: section in\n{help}"))
        .1;
    let mut names: Vec<String> = section
        .lines()
        .take_while(|line| !line.trim().is_empty())
        .filter(|line| line.starts_with("  ") && !line.starts_with("   "))
        .filter_map(|line| line.split_whitespace().next())
        .filter(|&name| name != "help")
        .map(str::to_string)
        .collect();
    names.sort();
    names
}

#[test]
fn help_is_complete() {
    // Every command, named here and checked against the sources (one module per command in
    // src/commands/), so that a command added to either is noticed.
    let mut commands = [
        "albedo",
        "convert",
        "eval",
        "export",
        "fit",
        "gonio",
        "materials",
        "plot",
        "render",
        "serve",
        "tabulate",
    ];
    commands.sort_unstable();
    assert_eq!(commands.to_vec(), command_modules());
    let help = help_text(&["--help"]);
    assert!(help.contains("woven-out") && help.contains("Examples:"));
    assert_eq!(listed_commands(&help), commands, "{help}");
    let mut figures = [
        "fig10",
        "fig3",
        "fig4",
        "fig5",
        "fig8",
        "fig9",
        "hemisphere",
    ];
    figures.sort_unstable();
    assert_eq!(listed_commands(&help_text(&["plot", "--help"])), figures);
    for figure in ["fig8", "hemisphere"] {
        woven()
            .args(["plot", figure, "--help"])
            .assert()
            .success()
            .stdout(predicate::str::contains("--output"))
            .stdout(predicate::str::contains("Examples:"));
    }
    // --material names the presets.
    woven()
        .args(["eval", "--help"])
        .assert()
        .success()
        .stdout(predicate::str::contains("PRESET|FILE"))
        .stdout(predicate::str::contains("belt-cloth"));
    for (command, needle) in [
        ("eval", "theta_i,phi_i,theta_r,phi_r"),
        ("albedo", "--theta-deg"),
        ("gonio", "azimuth_deg,tilt_deg,theta_i,theta_r,radiance"),
        ("materials", "--show"),
        ("plot", "fig4"),
        ("plot", "hemisphere"),
        ("eval", "--table"),
        ("tabulate", "--n-h-isotropic"),
        ("tabulate", "--report-samples"),
        ("export", "merl"),
        ("export", "--table"),
        ("render", "--exposure"),
        ("render", "--example"),
    ] {
        woven()
            .args([command, "--help"])
            .assert()
            .success()
            .stdout(predicate::str::contains(needle))
            .stdout(predicate::str::contains("Examples:"))
            .stdout(predicate::str::contains("--help"));
    }
    woven().arg("--version").assert().success();
}

#[test]
fn usage_errors_exit_with_status_2() {
    // (Bare `woven` renders the showcase: see `bare_woven_renders_the_showcase`.)
    woven().arg("frobnicate").assert().code(2);
    woven()
        .args(["eval", "--input", "-"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--material"));
    woven()
        .args(["albedo", "-m", "x.toml", "--wavelength-nm", "abc"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--wavelength-nm"));
}

#[test]
fn wavelength_out_of_range_is_reported() {
    woven()
        .args(["albedo", "--theta-deg", "45", "--wavelength-nm", "5", "-m"])
        .arg(material())
        .assert()
        .code(1)
        .stderr(predicate::str::contains("--wavelength-nm 5"))
        .stderr(predicate::str::contains("wavelength_nm"));
}

// ---------------------------------------------------------------------------------------------
// Presets: `woven materials` and `--material NAME`.

#[test]
fn materials_lists_every_preset_with_its_parameters() {
    let assert = woven().arg("materials").assert().success();
    let out = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    let (woven_table, microcylinder) = out.split_once("\n\n").expect("two tables");
    let lines: Vec<&str> = woven_table.lines().collect();
    assert_eq!(lines.len(), 1 + Material::all_preset_names().len(), "{out}");
    // Then one line per microcylinder fabric, under its heading.
    let fabrics = woven::microcylinder::Microcylinder::preset_names();
    assert_eq!(microcylinder.lines().count(), 1 + fabrics.len(), "{out}");
    for name in fabrics {
        assert!(microcylinder.contains(name), "{name} missing: {out}");
    }
    for heading in [
        "NAME",
        "FIBER",
        "η",
        "σh/τ",
        "L",
        "μ",
        "σ",
        "FIBERS",
        "γ",
        "DESCRIPTION",
    ] {
        assert!(
            lines[0].contains(heading),
            "{heading} missing: {}",
            lines[0]
        );
    }
    for name in Material::all_preset_names() {
        let line = lines
            .iter()
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("no row for {name}:\n{out}"));
        // The row ends with the first line of the preset's leading comment.
        let comment = Material::preset_toml(name)
            .unwrap()
            .lines()
            .next()
            .unwrap()
            .trim_start_matches('#')
            .trim();
        assert!(line.ends_with(comment), "{line}");
    }
    let row = |name: &str| *lines.iter().find(|l| l.starts_with(name)).unwrap();
    assert!(
        row("polyester-sateen").contains("0.05")
            && row("polyester-sateen").contains("one orientation")
    );
    assert!(
        row("belt-cloth").contains("twist σt = 0.35") && row("belt-cloth").contains("twill-2/1")
    );
    assert!(row("silk").contains("isotropic"));
}

#[test]
fn materials_show_prints_the_preset_toml_exactly() {
    for name in Material::all_preset_names() {
        let assert = woven()
            .args(["materials", "--show", name])
            .assert()
            .success();
        let out = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
        assert_eq!(out, Material::preset_toml(name).unwrap(), "{name}");
        let parsed = Material::from_toml_str(&out, "<stdout>").unwrap();
        assert_eq!(parsed, Material::preset(name).unwrap(), "{name}");
    }
    woven()
        .args(["materials", "--show", "denim"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("denim"))
        .stderr(predicate::str::contains("polyester-sateen"))
        .stderr(predicate::str::contains("silk"));
}

#[test]
fn eval_accepts_a_preset_name() {
    // Three rows of a slow cloth preset (about a millisecond each).
    let rows = "0.3,0,0.5,3.1\n0.9,1.2,0.2,-2\n1.1,0.5,1.0,0.5\n";
    let assert = woven()
        .args(["eval", "--material", "belt-cloth", "--input", "-"])
        .write_stdin(format!("{HEADER}\n{rows}"))
        .assert()
        .success();
    let out = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    let model = Material::preset("belt-cloth")
        .unwrap()
        .build(550.0)
        .unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 4, "{out}");
    for (line, row) in lines[1..].iter().zip(rows.lines()) {
        let a: Vec<f64> = row.split(',').map(|x| x.parse().unwrap()).collect();
        let want = model.eval(
            Vec3::from_spherical(a[0], a[1]),
            Vec3::from_spherical(a[2], a[3]),
        );
        let got: f64 = line.rsplit(',').next().unwrap().parse().unwrap();
        assert_eq!(got, want, "{line}");
        assert!(got > 0.0);
    }
}

#[test]
fn an_unknown_material_lists_the_presets() {
    woven()
        .args(["albedo", "--theta-deg", "45", "-m", "sateen"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("`sateen`"))
        .stderr(predicate::str::contains(
            "polyester-sateen, belt-cloth, silk",
        ));
}

// ---------------------------------------------------------------------------------------------
// `woven gonio`.

/// Parses gonio CSV into rows of five numbers, checking the header.
fn gonio_rows(out: &str) -> Vec<[f64; 5]> {
    let mut lines = out.lines();
    assert_eq!(
        lines.next(),
        Some("azimuth_deg,tilt_deg,theta_i,theta_r,radiance")
    );
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            assert_eq!(v.len(), 5, "{l}");
            [v[0], v[1], v[2], v[3], v[4]]
        })
        .collect()
}

#[test]
fn gonio_default_grid_matches_the_library() {
    let assert = woven()
        .args(["gonio", "--material", "polyester-sateen"])
        .assert()
        .success();
    let rows = gonio_rows(&String::from_utf8(assert.get_output().stdout.clone()).unwrap());
    // Azimuths 0, 45, 90 (outer), tilts −42 … 42 by 3 (inner).
    assert_eq!(rows.len(), 3 * 29);
    assert_eq!((rows[0][0], rows[0][1]), (0.0, -42.0));
    assert_eq!((rows[28][0], rows[28][1]), (0.0, 42.0));
    assert_eq!((rows[29][0], rows[29][1]), (45.0, -42.0));
    assert_eq!((rows[86][0], rows[86][1]), (90.0, 42.0));
    let model = Material::preset("polyester-sateen")
        .unwrap()
        .build(550.0)
        .unwrap();
    for row in [0, 14, 40, 58, 86].map(|k| rows[k]) {
        let [a, t, theta_i, theta_r, radiance] = row;
        assert!((theta_i - (45.0 + t).to_radians()).abs() < 1e-15, "{row:?}");
        assert!((theta_r - (45.0 - t).to_radians()).abs() < 1e-15, "{row:?}");
        // Light and sensor in one plane through the normal, on opposite sides.
        let s = Vec3::from_spherical(theta_i, a.to_radians());
        let v = Vec3::from_spherical(theta_r, a.to_radians() + std::f64::consts::PI);
        let want = model.eval(s, v) * theta_i.cos();
        assert!(
            (radiance - want).abs() <= 1e-15 * want,
            "{row:?}: library {want}"
        );
        assert!(radiance > 0.0);
    }
}

#[test]
fn gonio_takes_lists_and_writes_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("belt.csv");
    woven()
        .args([
            "gonio",
            "-m",
            "belt-cloth",
            "--azimuth-deg",
            "30",
            "--tilt-deg",
            "-40,0,40",
            "-o",
        ])
        .arg(&out)
        .assert()
        .success()
        .stdout("");
    let rows = gonio_rows(&std::fs::read_to_string(&out).unwrap());
    assert_eq!(rows.len(), 3);
    let model = Material::preset("belt-cloth")
        .unwrap()
        .build(550.0)
        .unwrap();
    for [a, t, theta_i, theta_r, radiance] in rows {
        assert_eq!(a, 30.0);
        let s = Vec3::from_spherical(theta_i, a.to_radians());
        let v = Vec3::from_spherical(theta_r, a.to_radians() + std::f64::consts::PI);
        let want = model.eval(s, v) * theta_i.cos();
        assert!(
            (radiance - want).abs() <= 1e-15 * want,
            "t = {t}: {radiance} vs {want}"
        );
    }
}

#[test]
fn gonio_rejects_bad_angles_naming_the_flag() {
    for (args, flag, needle) in [
        (
            ["--tilt-deg", "-45:45:5"],
            "--tilt-deg",
            "angle -45° is outside the valid range (-45, 45)",
        ),
        (["--tilt-deg", "50"], "--tilt-deg", "(-45, 45)"),
        (["--tilt-deg", "0:10"], "--tilt-deg", "START:STOP:STEP"),
        (
            ["--tilt-deg", "x"],
            "--tilt-deg",
            "`x` is not a finite number",
        ),
        (["--azimuth-deg", "400"], "--azimuth-deg", "[-360, 360]"),
        (
            ["--azimuth-deg", "0,nan"],
            "--azimuth-deg",
            "not a finite number",
        ),
    ] {
        woven()
            .args(["gonio", "-m", "silk"])
            .args(args)
            .assert()
            .code(2)
            .stderr(predicate::str::contains(flag))
            .stderr(predicate::str::contains(needle));
    }
    woven()
        .args(["gonio", "-m", "no-such-cloth"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains(
            "polyester-sateen, belt-cloth, silk",
        ));
}

// ---------------------------------------------------------------------------------------------
// `woven plot fig8|fig9|fig10` and `woven plot hemisphere`.

/// The width and height recorded in a PNG's IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    (
        u32::from_be_bytes(bytes[16..20].try_into().unwrap()),
        u32::from_be_bytes(bytes[20..24].try_into().unwrap()),
    )
}

#[test]
fn cloth_figures_name_their_preset_and_parameters() {
    let dir = tempfile::tempdir().unwrap();
    for (fig, preset, claim) in [
        ("fig8", "polyester-sateen", "masking off"),
        ("fig9", "belt-cloth", "45° and warp curves differ"),
        ("fig10", "silk", "isotropic"),
    ] {
        let svg = dir.path().join(format!("{fig}.svg"));
        let png = dir.path().join(format!("{fig}.png"));
        woven()
            .args(["plot", fig, "--width", "800", "--height", "560", "-o"])
            .arg(&svg)
            .arg("-o")
            .arg(&png)
            .assert()
            .success();
        let text = std::fs::read_to_string(&svg).unwrap();
        for needle in [preset, "σh/τ", "tilt", "sr⁻¹", "weft", "warp", "45°", claim] {
            assert!(text.contains(needle), "{fig}.svg lacks `{needle}`");
        }
        assert_eq!(png_size(&std::fs::read(&png).unwrap()), (800, 560));
    }
}

#[test]
fn hemisphere_writes_a_png_of_the_documented_size() {
    let dir = tempfile::tempdir().unwrap();
    // A fast material on a fine grid, a slow one on a coarse grid, and a log scale.
    for (material, extra) in [
        ("polyester-sateen", vec!["--grid", "96"]),
        ("silk", vec!["--grid", "12", "--log", "--phi-i-deg", "-30"]),
    ] {
        let png = dir.path().join(format!("{material}.png"));
        woven()
            .args([
                "plot",
                "hemisphere",
                "-m",
                material,
                "--theta-i-deg",
                "30",
                "--size",
                "256",
            ])
            .args(&extra)
            .arg("-o")
            .arg(&png)
            .assert()
            .success();
        // The image is --size high and 5/4 as wide.
        assert_eq!(
            png_size(&std::fs::read(&png).unwrap()),
            (320, 256),
            "{material}"
        );
    }
    woven()
        .args(["plot", "hemisphere", "-m", "silk", "-o"])
        .arg(dir.path().join("h.svg"))
        .assert()
        .code(1)
        .stderr(predicate::str::contains(".png"));
    woven()
        .args([
            "plot",
            "hemisphere",
            "-m",
            "silk",
            "--theta-i-deg",
            "90",
            "-o",
            "h.png",
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--theta-i-deg"));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
}

// ---------------------------------------------------------------------------------------------
// `woven tabulate`, `woven eval --table`, `woven export`.

/// A flat fiber surface: fast to tabulate and to export exactly.
const FLAT: &str = "[fiber]\neta = 1.5\nroughness = 0.3\ndiffuse = 0.1\n";

/// Tabulates the flat fiber on a small grid into `dir/flat.wtab`; returns the path and stdout.
fn small_table(dir: &Path, extra: &[&str]) -> (PathBuf, String) {
    let material = dir.join("flat.toml");
    std::fs::write(&material, FLAT).unwrap();
    let table = dir.join("flat.wtab");
    let assert = woven()
        .args(["tabulate", "--n-theta", "12", "--n-h-isotropic", "33", "-m"])
        .arg(&material)
        .arg("-o")
        .arg(&table)
        .args(extra)
        .assert()
        .success();
    let stdout = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    (table, stdout)
}

#[test]
fn tabulated_table_evaluates_as_the_library_does() {
    let dir = tempfile::tempdir().unwrap();
    let (path, stdout) = small_table(dir.path(), &[]);
    for needle in [
        "isotropic",
        "two halves",
        "12 polar × 33²",
        "26,136 values",
        "kB",
        "thread",
    ] {
        assert!(
            stdout.contains(needle),
            "summary lacks `{needle}`:\n{stdout}"
        );
    }
    assert!(!stdout.contains("Accuracy"), "{stdout}");
    let table = woven::table::Table::load(&path).unwrap();
    assert_eq!(table.dims(), (12, 1, 33));
    assert_eq!(table.wavelength_nm(), 550.0);
    // The material and the table: no temporary file is left.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);

    let input = dir.path().join("dirs.csv");
    std::fs::write(&input, rows_csv()).unwrap();
    let assert = woven()
        .args(["eval", "--table"])
        .arg(&path)
        .arg("--input")
        .arg(&input)
        .assert()
        .success();
    let out = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    let mut lines = out.lines();
    assert_eq!(lines.next(), Some("theta_i,phi_i,theta_r,phi_r,brdf"));
    let mut n = 0;
    for (line, row) in lines.zip(ROWS) {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(&fields[..4], row, "input columns are echoed as read");
        let a: Vec<f64> = row.iter().map(|x| x.parse().unwrap()).collect();
        let want = if a[0] >= std::f64::consts::FRAC_PI_2 || a[2] >= std::f64::consts::FRAC_PI_2 {
            0.0
        } else {
            table.eval(
                Vec3::from_spherical(a[0], a[1]),
                Vec3::from_spherical(a[2], a[3]),
            )
        };
        let got: f64 = fields[4].parse().unwrap();
        assert_eq!(
            got, want,
            "row {row:?}: got {got}, Table::eval gives {want}"
        );
        n += 1;
    }
    assert_eq!(n, ROWS.len());

    // The table's own wavelength may be repeated; another one is an error naming both.
    woven()
        .args(["eval", "--wavelength-nm", "550", "--input", "-", "--table"])
        .arg(&path)
        .write_stdin(rows_csv())
        .assert()
        .success();
    woven()
        .args(["eval", "--wavelength-nm", "650", "--input", "-", "--table"])
        .arg(&path)
        .write_stdin(rows_csv())
        .assert()
        .code(1)
        .stderr(predicate::str::contains("--wavelength-nm 650"))
        .stderr(predicate::str::contains("built at 550 nm"));
}

#[test]
fn tabulate_report_prints_the_accuracy() {
    let dir = tempfile::tempdir().unwrap();
    let (_, stdout) = small_table(dir.path(), &["--report", "--report-samples", "300"]);
    for needle in [
        "300 random direction pairs",
        "θ = max(θi, θr)",
        "rel. RMS (cos-weighted)",
        "99th pct.",
        "largest",
        "≤ 80°",
        "80°–89°",
        "89°–90°",
        " %",
    ] {
        assert!(
            stdout.contains(needle),
            "report lacks `{needle}`:\n{stdout}"
        );
    }
    // It ran with --report: no hint to add --report.
    assert!(!stdout.contains("--report checks"), "{stdout}");
    // A coarse grid of a smooth lobe: a few per cent, not wildly off, in every band.
    for band in ["≤ 80°", "80°–89°", "89°–90°"] {
        let rms: f64 = stdout
            .lines()
            .find(|l| l.trim_start().starts_with(band))
            .and_then(|l| l.trim_start()[band.len()..].split_whitespace().next())
            .and_then(|x| x.parse().ok())
            .unwrap_or_else(|| panic!("no RMS figure for {band} in\n{stdout}"));
        assert!(rms > 0.0 && rms < 10.0, "{band}: RMS {rms} %");
    }
}

#[test]
fn tabulate_rejects_bad_options_naming_the_flag() {
    for (args, needle) in [
        (vec!["--n-theta", "1"], "--n-theta"),
        (vec!["--n-h", "5000"], "--n-h"),
        (vec!["--n-phi", "x"], "--n-phi"),
        (vec!["--report-samples", "500"], "--report"),
        (
            vec!["--report", "--report-samples", "5"],
            "--report-samples",
        ),
    ] {
        woven()
            .args(["tabulate", "-m", "silk", "-o", "never.wtab"])
            .args(&args)
            .assert()
            .code(2)
            .stderr(predicate::str::contains(needle));
    }
    woven()
        .args(["tabulate", "-m", "silk"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--output"));
    // Too many nodes for a table file: refused before any work.
    let dir = tempfile::tempdir().unwrap();
    woven()
        .args([
            "tabulate",
            "-m",
            "belt-cloth",
            "--n-theta",
            "1024",
            "--n-phi",
            "1024",
            "-o",
        ])
        .arg(dir.path().join("never.wtab"))
        .assert()
        .code(1)
        .stderr(predicate::str::contains("--n-phi 1024"));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn damaged_tables_are_refused_and_leave_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let (path, _) = small_table(dir.path(), &[]);
    let bytes = std::fs::read(&path).unwrap();
    let truncated = dir.path().join("truncated.wtab");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    let flipped = dir.path().join("flipped.wtab");
    let mut damaged = bytes.clone();
    let k = damaged.len() - 100;
    damaged[k] ^= 0x40;
    std::fs::write(&flipped, &damaged).unwrap();
    let not_a_table = dir.path().join("dirs.wtab");
    std::fs::write(&not_a_table, rows_csv()).unwrap();
    for (file, needle) in [
        (&truncated, "truncated"),
        (&flipped, "checksum"),
        (&not_a_table, "magic"),
    ] {
        let output = dir.path().join("out.csv");
        woven()
            .args(["eval", "--input", "-", "--table"])
            .arg(file)
            .arg("--output")
            .arg(&output)
            .write_stdin(rows_csv())
            .assert()
            .code(1)
            .stderr(predicate::str::contains("cannot load --table"))
            .stderr(predicate::str::contains("not a valid woven table"))
            .stderr(predicate::str::contains(needle));
        assert!(!output.exists(), "{}", file.display());
    }
    woven()
        .args(["eval", "--input", "-", "--table"])
        .arg(dir.path().join("missing.wtab"))
        .write_stdin(rows_csv())
        .assert()
        .code(1)
        .stderr(predicate::str::contains("missing.wtab"));
}

#[test]
fn eval_takes_exactly_one_of_material_and_table() {
    woven()
        .args([
            "eval",
            "--input",
            "-",
            "--table",
            "t.wtab",
            "--material",
            "silk",
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--table"))
        .stderr(predicate::str::contains("cannot be used with"));
    woven()
        .args(["eval", "--input", "-"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--material"))
        .stderr(predicate::str::contains("--table"));
}

#[test]
fn export_merl_of_a_flat_fiber_round_trips() {
    use woven::export::merl::{Bin, MerlBrdf, FILE_SIZE, MERL_BINS};
    let dir = tempfile::tempdir().unwrap();
    let (_material_dir, material) = material_file(FLAT);
    let output = dir.path().join("flat.binary");
    // No --format: merl is the default.
    woven()
        .args(["export", "-m"])
        .arg(&material)
        .arg("-o")
        .arg(&output)
        .assert()
        .success()
        .stdout(predicate::str::contains("from the exact model"))
        .stdout(predicate::str::contains("1,458,000 bins"));
    assert_eq!(std::fs::metadata(&output).unwrap().len(), FILE_SIZE as u64);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    let merl = MerlBrdf::load(&output).unwrap();
    let model = Material::from_toml_str(FLAT, "flat")
        .unwrap()
        .build(550.0)
        .unwrap();
    // Bin centres from the specular peak to grazing, in and out of the plane of incidence.
    let mut checked = 0;
    for (theta_h, theta_d, phi_d) in [
        (0, 0, 0),
        (0, 45, 90),
        (10, 30, 17),
        (30, 60, 179),
        (45, 10, 100),
        (60, 40, 45),
        (89, 0, 5),
    ] {
        let bin = Bin {
            theta_h,
            theta_d,
            phi_d,
        };
        assert!(bin.index() < MERL_BINS);
        let Some(d) = bin.directions() else {
            assert_eq!(merl.value(bin.index()), [0.0; 3], "{bin:?}");
            continue;
        };
        let want = model.eval(d.s, d.v);
        let got = merl.lookup(d.s, d.v);
        for c in got {
            assert!(
                (c - want).abs() <= 1e-12 * want,
                "{bin:?}: file {c}, model {want}"
            );
        }
        checked += 1;
    }
    assert!(checked >= 5, "{checked} bins above the horizon");
}

#[test]
fn export_refuses_anisotropic_materials() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("sateen.binary");
    woven()
        .args(["export", "-m", "polyester-sateen", "--format", "merl", "-o"])
        .arg(&output)
        .assert()
        .code(1)
        .stderr(predicate::str::contains("polyester-sateen"))
        .stderr(predicate::str::contains("no half-vector azimuth"))
        .stderr(predicate::str::contains("woven tabulate"))
        .stderr(predicate::str::contains("isotropic = true"));
    assert!(!output.exists());
    woven()
        .args(["export", "-m", "silk", "--format", "obj", "-o"])
        .arg(&output)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--format"));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

/// The field names of a tensor file, in order (its header, as Mitsuba 3 and pbrt-v4 read it).
fn tensor_fields(file: &[u8]) -> Vec<String> {
    assert_eq!(&file[..12], b"tensor_file\0");
    let n = u32::from_le_bytes(file[14..18].try_into().unwrap());
    let mut at = 18;
    (0..n)
        .map(|_| {
            let len = u16::from_le_bytes(file[at..at + 2].try_into().unwrap()) as usize;
            let name = String::from_utf8(file[at + 2..at + 2 + len].to_vec()).unwrap();
            let rank = u16::from_le_bytes(file[at + 2 + len..at + 4 + len].try_into().unwrap());
            at += 2 + len + 2 + 1 + 8 + 8 * rank as usize;
            name
        })
        .collect()
}

#[test]
fn export_rgl_writes_the_fields_readers_need_and_names_bad_flags() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("velvet.bsdf");
    let small = ["--n-theta-i", "3", "--n-phi-i", "5", "--n-grid", "8"];
    woven()
        .args(["export", "--format", "rgl", "-m", "microcylinder-velvet"])
        .args(small)
        .arg("-o")
        .arg(&output)
        .assert()
        .success()
        .stdout(predicate::str::contains("3 θi × 5 φi"))
        .stdout(predicate::str::contains("\"type\": \"measured\""));
    let file = std::fs::read(&output).unwrap();
    assert_eq!(
        tensor_fields(&file),
        [
            "description",
            "jacobian",
            "theta_i",
            "phi_i",
            "ndf",
            "sigma",
            "vndf",
            "luminance",
            "rgb"
        ]
    );
    let spectral = dir.path().join("velvet-spectral.bsdf");
    woven()
        .args([
            "export",
            "--format",
            "rgl",
            "--spectral",
            "-m",
            "microcylinder-velvet",
        ])
        .args(small)
        .arg("-o")
        .arg(&spectral)
        .assert()
        .success()
        .stdout(predicate::str::contains("spectral at 450, 540, 610 nm"));
    let fields = tensor_fields(&std::fs::read(&spectral).unwrap());
    assert_eq!(&fields[8..], ["wavelengths", "spectra"]);

    let refused = dir.path().join("refused.bsdf");
    for (args, says) in [
        (vec!["--n-grid", "2"], "--n-grid"),
        (vec!["--n-phi-i", "2000"], "--n-phi-i"),
        (vec!["--table", "t.wtab"], "--table"),
    ] {
        woven()
            .args(["export", "--format", "rgl", "-m", "microcylinder-velvet"])
            .args(args)
            .arg("-o")
            .arg(&refused)
            .assert()
            .code(1)
            .stderr(predicate::str::contains(says));
    }
    woven()
        .args(["export", "-m", "silk", "--spectral", "-o"])
        .arg(&refused)
        .assert()
        .code(1)
        .stderr(predicate::str::contains("--format rgl"));
    assert!(!refused.exists());
}

#[test]
fn export_takes_a_table_of_its_material() {
    let dir = tempfile::tempdir().unwrap();
    let (table, _) = small_table(dir.path(), &[]);
    let output = dir.path().join("t.binary");
    woven()
        .args(["export", "--format", "merl", "--table"])
        .arg(&table)
        .arg("-o")
        .arg(&output)
        .assert()
        .success()
        .stdout(predicate::str::contains("from the table"));
    let merl = woven::export::merl::MerlBrdf::load(&output).unwrap();
    let t = woven::table::Table::load(&table).unwrap();
    let (s, v) = (
        Vec3::from_spherical(0.4, 0.0),
        Vec3::from_spherical(0.4, std::f64::consts::PI),
    );
    let bin = merl.lookup(s, v)[0];
    assert!(
        (bin - t.eval(s, v)).abs() < 0.05 * t.eval(s, v),
        "{bin} vs {}",
        t.eval(s, v)
    );
    // A table of another material than --material is refused.
    woven()
        .args(["export", "--format", "merl", "-m", "silk", "--table"])
        .arg(&table)
        .arg("-o")
        .arg(&output)
        .assert()
        .code(1)
        .stderr(predicate::str::contains("another material"));
}

#[test]
fn gonio_without_material_runs_the_main_job_in_the_current_folder() {
    let dir = tempfile::tempdir().unwrap();
    let assert = woven()
        .arg("gonio")
        .current_dir(dir.path())
        .assert()
        .success();
    let stdout = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    for needle in [
        "polyester-sateen",
        "woven-out/gonio-polyester-sateen.csv",
        "woven-out/fig8.png",
        "weft",
        "warp",
        "woven --help",
        "woven materials",
        "woven plot hemisphere",
    ] {
        assert!(
            stdout.contains(needle),
            "summary lacks `{needle}`:\n{stdout}"
        );
    }
    let out = dir.path().join("woven-out");
    let csv = std::fs::read_to_string(out.join("gonio-polyester-sateen.csv")).unwrap();
    assert_eq!(gonio_rows(&csv).len(), 3 * 29);
    let svg = std::fs::read_to_string(out.join("fig8.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("Fig. 8"));
    assert_eq!(
        png_size(&std::fs::read(out.join("fig8.png")).unwrap()),
        (1200, 800)
    );
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 3);
}

/// `woven eval` with a flat material and the given arguments, stopped after 60 s at most.
fn eval_with(args: &[&str]) -> assert_cmd::assert::Assert {
    woven()
        .arg("eval")
        .args(args)
        .timeout(std::time::Duration::from_secs(60))
        .assert()
}

#[cfg(unix)]
#[test]
fn endless_inputs_are_refused_naming_the_file() {
    let m = material();
    let m = m.to_str().unwrap();
    eval_with(&["-m", m, "--input", "/dev/zero"])
        .failure()
        .stderr(predicate::str::contains("/dev/zero"))
        .stderr(predicate::str::contains("longer than 4096 bytes"));
    eval_with(&["-m", "/dev/zero", "--input", "-"])
        .failure()
        .stderr(predicate::str::contains(
            "/dev/zero: a character device, not a regular file: a material file is read only \
             from a regular file",
        ));
    eval_with(&["--table", "/dev/zero", "--input", "-"])
        .failure()
        .stderr(predicate::str::contains(
            "/dev/zero: a character device, not a regular file: a table is read only from a \
             regular file",
        ));
    // An endless line on standard input.
    woven()
        .args(["eval", "-m", m, "--input", "-"])
        .write_stdin(format!("{HEADER}\n0,0,0,0\n{}", "1".repeat(100_000)))
        .timeout(std::time::Duration::from_secs(60))
        .assert()
        .failure()
        .stderr(predicate::str::contains(
            "<stdin>: line 3 is longer than 4096 bytes",
        ));
}

#[cfg(unix)]
#[test]
fn output_onto_a_read_only_file_is_refused_and_kept() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("d.csv");
    std::fs::write(&input, rows_csv()).unwrap();
    let out = dir.path().join("out.csv");
    std::fs::write(&out, "keep me").unwrap();
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o444)).unwrap();
    let m = material();
    eval_with(&[
        "-m",
        m.to_str().unwrap(),
        "--input",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ])
    .failure()
    .stderr(predicate::str::contains(
        "out.csv` is read-only: refusing to replace it",
    ));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep me");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    // A writable file is replaced as before.
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o644)).unwrap();
    eval_with(&[
        "-m",
        m.to_str().unwrap(),
        "--input",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ])
    .success();
    check_eval_output(&std::fs::read_to_string(&out).unwrap());
}

#[cfg(unix)]
#[test]
fn write_failures_name_the_file() {
    // /dev/full behind a name with the extension the command wants (a device: written in place).
    if !Path::new("/dev/full").exists() {
        eprintln!("no /dev/full: skipped");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("full.png");
    std::os::unix::fs::symlink("/dev/full", &png).unwrap();
    woven()
        .args(["plot", "fig3", "-o", png.to_str().unwrap()])
        .assert()
        .failure()
        .stderr(predicate::str::contains("cannot write `"))
        .stderr(predicate::str::contains("full.png`"));
    let input = dir.path().join("d.csv");
    std::fs::write(&input, rows_csv()).unwrap();
    let m = material();
    eval_with(&[
        "-m",
        m.to_str().unwrap(),
        "--input",
        input.to_str().unwrap(),
        "-o",
        "/dev/full",
    ])
    .failure()
    .stderr(predicate::str::contains("`/dev/full`"));
}

#[test]
fn a_file_that_is_not_a_wif_is_named_not_printed() {
    let (dir, path) = material_file(
        "[fiber]\neta = 1.5\nroughness = 0.2\n[yarn]\nlateral_length = 1.0\nslope_mean = 0.5\n\
         [weave]\npattern = { wif = \"secret.txt\" }\n",
    );
    std::fs::write(dir.path().join("secret.txt"), "password=hunter2\n").unwrap();
    woven()
        .args(["eval", "-m", path.to_str().unwrap(), "--input", "-"])
        .write_stdin(rows_csv())
        .assert()
        .failure()
        .stderr(predicate::str::contains("secret.txt"))
        .stderr(predicate::str::contains("weaving information file"))
        .stderr(predicate::str::contains("hunter2").not());
}

/// Starts a long `woven eval -o` (the belt cloth, ~1 ms a row, 10⁶ rows), waits for its temporary
/// file, sends `signal`, and checks that neither the temporary file nor the output remain.
#[cfg(unix)]
fn interrupted_eval_leaves_nothing(signal: &str) {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("d.csv");
    let mut csv = format!("{HEADER}\n");
    for k in 0..1_000_000 {
        csv.push_str(&format!("0.{},0,0.3,{}\n", k % 10, k % 7));
    }
    std::fs::write(&input, csv).unwrap();
    let out = dir.path().join("out.csv");
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("woven"))
        .args(["eval", "-m", "belt-cloth", "--input"])
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let tmp_files = || {
        std::fs::read_dir(dir.path())
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
            .count()
    };
    let start = std::time::Instant::now();
    while tmp_files() == 0 {
        assert!(start.elapsed().as_secs() < 60, "no temporary file appeared");
        assert!(child.try_wait().unwrap().is_none(), "eval ended early");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    // Some rows in: the temporary file is being written.
    std::thread::sleep(std::time::Duration::from_millis(300));
    let killed = std::process::Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert!(!status.success(), "{signal}: {status:?}");
    assert_eq!(tmp_files(), 0, "{signal} left a temporary file");
    assert!(!out.exists(), "{signal} left an output");
}

#[cfg(unix)]
#[test]
fn an_interrupted_eval_removes_its_temporary_file() {
    interrupted_eval_leaves_nothing("-TERM");
    interrupted_eval_leaves_nothing("-INT");
}

// `woven render`.

/// A small diffuse scene: renders in well under a second.
const SMALL_SCENE: &str = r#"
[camera]
origin = [0, -2.5, 2.5]
target = [0, 0, 0]
fov_deg = 45
[film]
width = 32
height = 24
spp = 4
[integrator]
max_depth = 2
[[light]]
type = "point"
position = [0.4, 0.5, 1.5]
intensity = [10, 10, 10]
[[shape]]
type = "rectangle"
corner = [-1, -1, 0]
edge_u = [2, 0, 0]
edge_v = [0, 2, 0]
material = "plane"
[material.plane]
type = "diffuse"
reflectance = [0.5, 0.5, 0.5]
"#;

#[test]
fn render_writes_exr_and_png_by_default_and_one_with_output() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("small.toml"), SMALL_SCENE).unwrap();
    let assert = woven()
        .args(["render", "small.toml", "--width", "20", "--height", "10"])
        .current_dir(dir.path())
        .assert()
        .success();
    let stdout = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    assert!(
        stdout.contains("woven-out/small.exr") && stdout.contains("woven-out/small.png"),
        "{stdout}"
    );
    let png = std::fs::read(dir.path().join("woven-out/small.png")).unwrap();
    assert_eq!(png_size(&png), (20, 10));
    let exr = std::fs::read(dir.path().join("woven-out/small.exr")).unwrap();
    assert_eq!(&exr[..4], &[0x76, 0x2f, 0x31, 0x01], "not an OpenEXR file");
    // No temporary files are left behind.
    assert_eq!(
        std::fs::read_dir(dir.path().join("woven-out"))
            .unwrap()
            .count(),
        2
    );

    woven()
        .args([
            "render",
            "small.toml",
            "-o",
            "one.png",
            "--spp",
            "1",
            "--seed",
            "3",
        ])
        .current_dir(dir.path())
        .assert()
        .success();
    assert_eq!(
        png_size(&std::fs::read(dir.path().join("one.png")).unwrap()),
        (32, 24)
    );
    assert!(!dir.path().join("one.exr").exists());
}

#[test]
fn render_errors_name_the_file_key_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = SMALL_SCENE.replace("spp = 4", "spp = 4\nsppp = 5");
    std::fs::write(dir.path().join("bad.toml"), bad).unwrap();
    woven()
        .args(["render", "bad.toml"])
        .current_dir(dir.path())
        .assert()
        .code(1)
        .stderr(predicate::str::contains("bad.toml:10"))
        .stderr(predicate::str::contains("sppp"));
    std::fs::write(dir.path().join("small.toml"), SMALL_SCENE).unwrap();
    woven()
        .args(["render", "small.toml", "-o", "x.jpg"])
        .current_dir(dir.path())
        .assert()
        .code(1)
        .stderr(predicate::str::contains(".exr"));
    woven()
        .args(["render", "small.toml", "--spp", "0"])
        .assert()
        .code(2);
}

/// `--sampler` overrides `[film] sampler`: the flag and the key render the same image, the two
/// samplers different ones; an unknown sampler is an error in either place.
#[test]
fn render_sampler_flag_overrides_the_film_key() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("small.toml"), SMALL_SCENE).unwrap();
    let keyed = SMALL_SCENE.replace("spp = 4", "spp = 4\nsampler = \"independent\"");
    std::fs::write(dir.path().join("keyed.toml"), keyed).unwrap();
    let render = |args: &[&str]| {
        woven()
            .args(args)
            .current_dir(dir.path())
            .assert()
            .success();
    };
    render(&[
        "render",
        "small.toml",
        "-o",
        "flag.exr",
        "--sampler",
        "independent",
    ]);
    render(&["render", "keyed.toml", "-o", "key.exr"]);
    render(&[
        "render",
        "keyed.toml",
        "-o",
        "sobol.exr",
        "--sampler",
        "sobol",
    ]);
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert_eq!(read("flag.exr"), read("key.exr"));
    assert_ne!(read("flag.exr"), read("sobol.exr"));
    woven()
        .args(["render", "small.toml", "--sampler", "halton"])
        .current_dir(dir.path())
        .assert()
        .code(2)
        .stderr(predicate::str::contains("sobol"));
    let bad = SMALL_SCENE.replace("spp = 4", "spp = 4\nsampler = \"halton\"");
    std::fs::write(dir.path().join("bad.toml"), bad).unwrap();
    woven()
        .args(["render", "bad.toml"])
        .current_dir(dir.path())
        .assert()
        .code(1)
        .stderr(predicate::str::contains("halton"))
        .stderr(predicate::str::contains("independent"));
}

/// `--tonemap` and `--exposure` override `[film] tonemap` and `exposure`; the EXR stays linear
/// whatever they say.
#[test]
fn render_display_flags_override_the_film_keys() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("small.toml"), SMALL_SCENE).unwrap();
    let keyed = SMALL_SCENE.replace("spp = 4", "spp = 4\ntonemap = \"clamp\"\nexposure = 2");
    std::fs::write(dir.path().join("keyed.toml"), keyed).unwrap();
    let render = |args: &[&str]| {
        woven()
            .args(args)
            .current_dir(dir.path())
            .assert()
            .success();
    };
    render(&["render", "small.toml", "-o", "filmic.png"]);
    render(&[
        "render",
        "small.toml",
        "-o",
        "flag.png",
        "--tonemap",
        "clamp",
        "--exposure",
        "2",
    ]);
    render(&["render", "keyed.toml", "-o", "key.png"]);
    render(&["render", "small.toml", "-o", "plain.exr"]);
    render(&["render", "keyed.toml", "-o", "keyed.exr"]);
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert_eq!(read("flag.png"), read("key.png"));
    assert_ne!(read("flag.png"), read("filmic.png"));
    assert_eq!(read("plain.exr"), read("keyed.exr"));
    for (flag, value, needle) in [
        ("--tonemap", "aces", "filmic"),
        ("--exposure", "25", "[-20, 20]"),
    ] {
        woven()
            .args(["render", "small.toml", flag, value])
            .current_dir(dir.path())
            .assert()
            .failure()
            .stderr(predicate::str::contains(needle));
    }
}

/// `--denoise` and `--no-denoise` override `[film] denoise`: the flag and the key give the same
/// file, unlike the raw render, and the run says it denoised.
#[test]
fn render_denoise_flags_override_the_film_key() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("small.toml"), SMALL_SCENE).unwrap();
    let keyed = SMALL_SCENE.replace("spp = 4", "spp = 4\ndenoise = true");
    assert_ne!(keyed, SMALL_SCENE);
    std::fs::write(dir.path().join("keyed.toml"), keyed).unwrap();
    let render = |args: &[&str]| {
        let out = woven()
            .args(args)
            .current_dir(dir.path())
            .assert()
            .success();
        String::from_utf8(out.get_output().stdout.clone()).unwrap()
    };
    assert!(render(&["render", "small.toml", "-o", "flag.exr", "--denoise"]).contains("denoised"));
    render(&["render", "keyed.toml", "-o", "key.exr"]);
    let raw = render(&["render", "keyed.toml", "-o", "raw.exr", "--no-denoise"]);
    assert!(!raw.contains("denoised"), "{raw}");
    render(&["render", "small.toml", "-o", "plain.exr"]);
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert_eq!(read("flag.exr"), read("key.exr"));
    assert_eq!(read("raw.exr"), read("plain.exr"));
    assert_ne!(read("flag.exr"), read("plain.exr"));
}

#[test]
fn render_example_prints_a_commented_scene() {
    let assert = woven().args(["render", "--example"]).assert().success();
    let stdout = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    for needle in [
        "[camera]",
        "[film]",
        "[integrator]",
        "type = \"cloth\"",
        "type = \"woven\"",
        "# ",
    ] {
        assert!(stdout.contains(needle), "the example lacks `{needle}`");
    }
}

/// Bare `woven` renders the built-in showcase (about 85 s on 2 cores with a cold table cache: it
/// builds the showcase's tables at the default grid, in the user's cache, and renders 960×540).
#[test]
#[ignore = "slow: the showcase's tables and render (~85 s on 2 cores); CI runs it"]
fn bare_woven_renders_the_showcase() {
    let dir = tempfile::tempdir().unwrap();
    let assert = woven().current_dir(dir.path()).assert().success();
    let stdout = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    assert!(stdout.contains("woven-out/showcase.png"), "{stdout}");
    assert!(!stdout.contains("warning"), "{stdout}");
    let png = std::fs::read(dir.path().join("woven-out/showcase.png")).unwrap();
    assert_eq!(png_size(&png), (960, 540));
}

/// `--rgb` writes three columns: a microcylinder fabric its colours (the library's values), an
/// undyed woven material its one value three times; without `--rgb` a coloured material writes
/// its luminance.
#[test]
fn eval_rgb_writes_three_columns_for_every_kind_of_material() {
    let rows = "0.5,1.5707963267948966,0.5,-1.5707963267948966\n0.3,0,0.5,3.1\n";
    let run = |material: &str, rgb: bool| -> Vec<Vec<f64>> {
        let mut cmd = woven();
        cmd.args(["eval", "--material", material, "--input", "-"]);
        if rgb {
            cmd.arg("--rgb");
        }
        let assert = cmd
            .write_stdin(format!("{HEADER}\n{rows}"))
            .assert()
            .success();
        let out = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
        let mut lines = out.lines();
        let header = lines.next().unwrap();
        let want = if rgb { "brdf_r,brdf_g,brdf_b" } else { "brdf" };
        assert_eq!(header, format!("{HEADER},{want}"));
        lines
            .map(|l| l.split(',').skip(4).map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let satin =
        woven::microcylinder::Microcylinder::preset("microcylinder-satin-charmeuse").unwrap();
    let colour = run("microcylinder-satin-charmeuse", true);
    let grey = run("microcylinder-satin-charmeuse", false);
    for ((row, c), g) in rows.lines().zip(&colour).zip(&grey) {
        let a: Vec<f64> = row.split(',').map(|x| x.parse().unwrap()).collect();
        let want = woven::bsdf::Bsdf::eval(
            &satin,
            Vec3::from_spherical(a[0], a[1]),
            Vec3::from_spherical(a[2], a[3]),
        );
        assert_eq!(c.as_slice(), want.0.as_slice());
        assert!(c[0] > c[2], "the charmeuse is red: {c:?}");
        assert_eq!(g[0], want.luminance());
    }
    for c in run("silk", true) {
        assert!(c[0] > 0.0 && c[0] == c[1] && c[1] == c[2], "{c:?}");
    }
}

/// A small microcylinder fabric file (docs/microcylinder.md §8): two straight threads, one
/// tangent each, so that measuring its energy guard takes well under a second.
const FABRIC: &str = "model = \"microcylinder\"\nname = \"test threads\"\n\n\
[[thread]]\neta = 1.46\nalbedo = [0.06, 0.24, 0.3]\nkd = 0.3\ngamma_s_deg = 12.0\n\
gamma_v_deg = 24.0\ncoverage = 0.5\ntangent_offsets_deg = [0.0]\n\n\
[[thread]]\neta = 1.46\nalbedo = [0.3, 0.2, 0.1]\nkd = 0.3\ngamma_s_deg = 12.0\n\
gamma_v_deg = 24.0\ncoverage = 0.5\ntangent_offsets_deg = [0.0]\n";

/// `woven gonio` takes a microcylinder fabric (a preset or a file): its radiance is the
/// luminance of the library's RGB value, f cos θi; an unknown name lists both kinds' presets.
#[test]
fn gonio_reads_a_microcylinder_fabric_as_its_luminance() {
    let (_dir, file) = material_file(FABRIC);
    let file = file.to_str().unwrap().to_string();
    for material in ["microcylinder-velvet", file.as_str()] {
        let assert = woven()
            .args(["gonio", "-m", material, "--azimuth-deg", "0,90"])
            .args(["--tilt-deg=-30,0,30"])
            .assert()
            .success();
        let rows = gonio_rows(&String::from_utf8(assert.get_output().stdout.clone()).unwrap());
        assert_eq!(rows.len(), 6);
        let fabric = match woven::catalog::AnyMaterial::from_preset_or_path(material).unwrap() {
            woven::catalog::AnyMaterial::Microcylinder(m) => m,
            other => panic!("{material} read as {other:?}"),
        };
        for [a, _, theta_i, theta_r, radiance] in rows {
            let s = Vec3::from_spherical(theta_i, a.to_radians());
            let v = Vec3::from_spherical(theta_r, a.to_radians() + std::f64::consts::PI);
            let want = fabric.eval_rgb(s, v).luminance() * theta_i.cos();
            assert_eq!(radiance, want, "{material}");
            assert!(radiance > 0.0);
        }
    }
    woven()
        .args(["gonio", "-m", "microcylinder-nope"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("microcylinder-velvet"))
        .stderr(predicate::str::contains("belt-cloth"));
}

/// `woven plot hemisphere` draws a microcylinder fabric, its luminance (a fabric file takes the
/// same path, `load_mono`, as in `woven gonio`, which tests it).
#[test]
fn hemisphere_plots_a_microcylinder_fabric() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("charmeuse.png");
    woven()
        .args(["plot", "hemisphere", "-m", "microcylinder-satin-charmeuse"])
        .args(["--grid", "12", "--size", "256", "-o"])
        .arg(&png)
        .assert()
        .success();
    assert_eq!(png_size(&std::fs::read(&png).unwrap()), (320, 256));
    woven()
        .args(["plot", "hemisphere", "--help"])
        .assert()
        .success()
        .stdout(predicate::str::contains("microcylinder-velvet"));
}

/// A key of a megabyte in a scene is shown cut, not echoed whole.
#[test]
fn a_huge_key_is_not_echoed_whole() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("huge.toml");
    let example = String::from_utf8(
        woven()
            .args(["render", "--example"])
            .output()
            .unwrap()
            .stdout,
    )
    .unwrap();
    let key = "k".repeat(1 << 20);
    std::fs::write(
        &scene,
        example.replacen("[film]", &format!("[film]\n{key} = 1"), 1),
    )
    .unwrap();
    let out = woven()
        .args(["render", scene.to_str().unwrap(), "-o"])
        .arg(dir.path().join("x.png"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.len() < 1000, "{} bytes of error", err.len());
    assert!(
        err.contains("`film.kkkk") && err.contains("characters left out"),
        "{err}"
    );
}
