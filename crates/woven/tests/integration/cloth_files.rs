//! Material files: the `[yarn]` and `[weave]` tables (the project's material-file contract;
//! docs/spec.md §2, §2.7). Every error names the key, the offending value and the valid range; a
//! WIF pattern is read relative to the material file's folder; a pattern gives `γ`.

use std::path::{Path, PathBuf};
use woven::cloth::Structure;
use woven::material::{Material, PatternSpec, Weave};
use woven::weave::Pattern;
use woven::Error;

/// A valid `[fiber]` table for every case.
const FIBER: &str = "[fiber]\neta = 1.6\nroughness = 0.1\n";
/// A valid `[yarn]` table.
const YARN: &str = "[yarn]\nlateral_length = 4.0\nslope_mean = 0.4\n";

/// The material `FIBER` + `rest`.
fn text(rest: &str) -> String {
    format!("{FIBER}{rest}")
}

/// Parses `FIBER` + `rest`, failing the test with the error.
fn parse(rest: &str) -> Material {
    let t = text(rest);
    Material::from_toml_str(&t, "<test>").unwrap_or_else(|e| panic!("{e}\n--- text ---\n{t}"))
}

/// Parses `FIBER` + `rest`, which must fail; returns the error and its message.
fn parse_err(rest: &str) -> (Error, String) {
    let t = text(rest);
    match Material::from_toml_str(&t, "<test>") {
        Ok(m) => panic!("expected an error, parsed {m:?}\n--- text ---\n{t}"),
        Err(e) => {
            let msg = e.to_string();
            (e, msg)
        }
    }
}

/// Asserts that `msg` contains every one of `parts`.
#[track_caller]
fn assert_mentions(msg: &str, parts: &[&str], rest: &str) {
    for p in parts {
        assert!(
            msg.contains(p),
            "error message should mention {p:?}\n  message: {msg}\n  --- text ---\n{}",
            text(rest)
        );
    }
}

/// Asserts an [`Error::InvalidParameter`] naming `key` whose message mentions `parts`.
#[track_caller]
fn assert_invalid(rest: &str, key: &str, parts: &[&str]) {
    let (err, msg) = parse_err(rest);
    match &err {
        Error::InvalidParameter { name, .. } => assert_eq!(
            name,
            key,
            "wrong key named; message: {msg}\n--- text ---\n{}",
            text(rest)
        ),
        other => panic!(
            "expected InvalidParameter for `{key}`, got {other:?}\n--- text ---\n{}",
            text(rest)
        ),
    }
    assert_mentions(&msg, parts, rest);
    // STYLE.md: lower-case messages without a trailing period.
    assert!(!msg.ends_with('.'), "message ends with a period: {msg}");
}

/// Asserts an [`Error::Parse`] naming the origin, whose message mentions `parts`.
#[track_caller]
fn assert_parse_error(rest: &str, parts: &[&str]) {
    let (err, msg) = parse_err(rest);
    assert!(
        matches!(err, Error::Parse { .. }),
        "expected a parse error, got {err:?}\n--- text ---\n{}",
        text(rest)
    );
    assert_mentions(&msg, &["<test>"], rest);
    assert_mentions(&msg, parts, rest);
}

/// A fresh, empty folder under the system's temporary folder (`tempfile` is not a
/// dev-dependency), removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static COUNT: AtomicUsize = AtomicUsize::new(0);
        let n = COUNT.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!(
            "woven-cloth-files-{}-{tag}-{n}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        TempDir(dir)
    }

    fn path(&self) -> &Path {
        &self.0
    }

    /// Writes `contents` to `name` (relative; folders are created).
    fn write(&self, name: &str, contents: &str) -> PathBuf {
        let p = self.0.join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).unwrap();
        }
        std::fs::write(&p, contents).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        p
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The text of a WIF file of `tests/data/wif`.
fn wif_text(name: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/wif")
        .join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The weft fraction a built model uses.
fn built_gamma(m: &Material) -> f64 {
    match m.build(550.0).unwrap().structure() {
        Structure::Woven { weft_fraction, .. } => *weft_fraction,
        Structure::Flat(_) => panic!("a woven material built flat"),
    }
}

// ---------------------------------------------------------------------------------------------
// Valid [yarn] and [weave] tables
// ---------------------------------------------------------------------------------------------

#[test]
fn yarn_table_defaults_and_values() {
    let m = parse(YARN);
    let y = m.yarn.unwrap();
    assert_eq!((y.lateral_length, y.slope_mean), (4.0, 0.4));
    assert_eq!(
        (
            y.slope_std,
            y.interreflection,
            y.interreflection_albedo,
            y.twist_std,
            y.isotropic
        ),
        (0.0, 0.0, 0.0, 0.0, false),
        "documented defaults"
    );
    // No [weave]: γ = 1, one orientation along x.
    assert_eq!(m.weave, None);
    assert_eq!(m.weft_fraction(), 1.0);
    assert_eq!(built_gamma(&m), 1.0);
    let full = parse(
        "[yarn]\nlateral_length = 20.0\nslope_mean = 0.0\nslope_std = 1.2\ninterreflection = 0.15\n\
         interreflection_albedo = 0.6\ntwist_std = 0.0\nisotropic = false\n[weave]\nweft_fraction = 0.0\n",
    );
    let y = full.yarn.unwrap();
    assert_eq!(
        (
            y.lateral_length,
            y.slope_std,
            y.interreflection,
            y.interreflection_albedo
        ),
        (20.0, 1.2, 0.15, 0.6)
    );
    assert_eq!(full.weave, Some(Weave::WeftFraction(0.0)));
    assert_eq!(built_gamma(&full), 0.0);
    // Range ends are valid: touching cylinders (μ = π/2 with L = 0), ħ = ρ = 1, γ = 1.
    let ends = parse(
        "[yarn]\nlateral_length = 0.0\nslope_mean = 1.5707963267948966\ninterreflection = 1.0\n\
         interreflection_albedo = 1.0\ntwist_std = 3.141592653589793\n[weave]\nweft_fraction = 1.0\n",
    );
    assert!(ends.build(550.0).is_ok());
}

#[test]
fn mistyped_values_are_parse_errors() {
    // A TOML integer is read as the number it is.
    let m = parse("[yarn]\nlateral_length = 20\nslope_mean = 0\n[weave]\nweft_fraction = 1\n");
    assert_eq!(m.yarn.unwrap().lateral_length, 20.0);
    assert_eq!(m.weft_fraction(), 1.0);
    // A string or a wrong type is a parse error naming the key and the line.
    assert_parse_error(
        "[yarn]\nlateral_length = \"20\"\nslope_mean = 0.0\n",
        &["lateral_length"],
    );
    assert_parse_error(
        "[yarn]\nlateral_length = 2.0\nslope_mean = 0.0\nisotropic = \"yes\"\n",
        &["isotropic"],
    );
}

/// `γ` of a named pattern, a matrix and a WIF file (docs/spec.md §2.7: the mean of the matrix).
#[test]
fn pattern_gives_the_weft_fraction() {
    for (pattern, want) in [
        ("\"plain\"", 0.5),
        (
            "\"satin-5\"",
            Pattern::from_name("satin-5").unwrap().weft_fraction(),
        ),
        (
            "\"twill-2/1\"",
            Pattern::from_name("twill-2/1").unwrap().weft_fraction(),
        ),
        ("[[1, 1, 0], [0, 1, 1], [1, 0, 1]]", 2.0 / 3.0),
        (
            "[[1, 0, 0, 0, 0], [0, 0, 1, 0, 0], [0, 0, 0, 0, 1], [0, 1, 0, 0, 0], [0, 0, 0, 1, 0]]",
            0.2,
        ),
        ("[[0]]", 0.0),
        ("[[1, 1], [1, 1]]", 1.0),
    ] {
        let rest = format!("{YARN}[weave]\npattern = {pattern}\n");
        let m = parse(&rest);
        let g = m.weft_fraction();
        assert!(
            (g - want).abs() < 1e-15,
            "pattern {pattern}: γ {g}, want {want}"
        );
        assert_eq!(built_gamma(&m), g, "pattern {pattern}: the built model's γ");
    }
    // A 2/1 twill is a third or two thirds weft (docs/spec.md §2.7); satin-5 a fifth or four fifths.
    let twill = parse(&format!("{YARN}[weave]\npattern = \"twill-2/1\"\n")).weft_fraction();
    assert!(
        (twill - 1.0 / 3.0).abs() < 1e-15 || (twill - 2.0 / 3.0).abs() < 1e-15,
        "twill-2/1: {twill}"
    );
    let satin = parse(&format!("{YARN}[weave]\npattern = \"satin-5\"\n")).weft_fraction();
    assert!(
        (satin - 0.2).abs() < 1e-15 || (satin - 0.8).abs() < 1e-15,
        "satin-5: {satin}"
    );
    // The spec is kept as written.
    let m = parse(&format!("{YARN}[weave]\npattern = [[1, 0], [0, 1]]\n"));
    match m.weave {
        Some(Weave::Pattern {
            spec: PatternSpec::Matrix(ref rows),
            ..
        }) => assert_eq!(rows, &vec![vec![1u8, 0], vec![0, 1]]),
        other => panic!("{other:?}"),
    }
}

/// A WIF pattern named relative to the material file is read from the file's folder (not the
/// working directory), in a sub-folder too; and the material round-trips through TOML.
#[test]
fn wif_pattern_is_relative_to_the_material_file() {
    let dir = TempDir::new("wif");
    let wif = wif_text("twill-2-1.wif");
    let want = Pattern::from_wif_str(&wif, "<twill>")
        .unwrap()
        .weft_fraction();
    dir.write("twill.wif", &wif);
    dir.write("weaves/twill.wif", &wif);
    for (name, wif_ref) in [("a.toml", "twill.wif"), ("b.toml", "weaves/twill.wif")] {
        let path = dir.write(
            name,
            &text(&format!(
                "{YARN}[weave]\npattern = {{ wif = \"{wif_ref}\" }}\n"
            )),
        );
        // The working directory (the crate's folder) has no such file: success shows the
        // material file's folder was used.
        assert!(!Path::new(wif_ref).exists());
        let m = Material::from_path(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            (m.weft_fraction() - want).abs() < 1e-15,
            "{wif_ref}: γ {}",
            m.weft_fraction()
        );
        assert_eq!(built_gamma(&m), m.weft_fraction());
        match &m.weave {
            Some(Weave::Pattern {
                spec: PatternSpec::Wif(p),
                ..
            }) => assert_eq!(p, Path::new(wif_ref), "the path is kept as written"),
            other => panic!("{other:?}"),
        }
        // Round trip through a file in the same folder.
        let again = dir.write(&format!("again-{name}"), &m.to_toml_string());
        assert_eq!(
            Material::from_path(&again).unwrap(),
            m,
            "round trip of {name}"
        );
        // The self-contained text (what a table records) parses with no folder at all, to the
        // same pattern; the path-keeping text does not.
        let anywhere = Material::from_toml_str(&m.to_self_contained_toml_string(), "<record>")
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        match (&anywhere.weave, &m.weave) {
            (
                Some(Weave::Pattern {
                    spec: PatternSpec::Matrix(_),
                    pattern: a,
                }),
                Some(Weave::Pattern { pattern: b, .. }),
            ) => assert_eq!(a, b, "{name}"),
            other => panic!("{other:?}"),
        }
        assert!(Material::from_toml_str(&m.to_toml_string(), "<record>").is_err());
    }
    // An absolute path works from anywhere.
    let abs = dir.path().join("twill.wif");
    let m = parse(&format!(
        "{YARN}[weave]\npattern = {{ wif = {:?} }}\n",
        abs.display().to_string()
    ));
    assert!((m.weft_fraction() - want).abs() < 1e-15);
}

// ---------------------------------------------------------------------------------------------
// Errors of the [yarn] table
// ---------------------------------------------------------------------------------------------

#[test]
fn unknown_key_in_yarn_table() {
    assert_parse_error(
        "[yarn]\nlateral_length = 4.0\nslope_mean = 0.4\nslope_meen = 0.2\n",
        &["slope_meen", "line"],
    );
}

#[test]
fn missing_lateral_length_or_slope_mean() {
    assert_invalid(
        "[yarn]\nslope_mean = 0.4\n",
        "yarn.lateral_length",
        &["yarn.lateral_length", "missing", "required"],
    );
    assert_invalid(
        "[yarn]\nlateral_length = 4.0\n",
        "yarn.slope_mean",
        &["yarn.slope_mean", "missing", "required"],
    );
    // An empty [yarn] names the first missing key.
    assert_invalid("[yarn]\n", "yarn.lateral_length", &["missing"]);
}

#[test]
fn yarn_values_out_of_range() {
    for (line, key, value) in [
        ("slope_mean = 2.0", "yarn.slope_mean", "2"),
        ("slope_mean = -0.1", "yarn.slope_mean", "-0.1"),
        ("lateral_length = -1.0", "yarn.lateral_length", "-1"),
        ("lateral_length = 2e6", "yarn.lateral_length", "2000000"),
        ("lateral_length = inf", "yarn.lateral_length", "inf"),
        ("slope_std = -0.5", "yarn.slope_std", "-0.5"),
        ("slope_std = 4.0", "yarn.slope_std", "4"),
        ("interreflection = 1.5", "yarn.interreflection", "1.5"),
        ("interreflection = -0.5", "yarn.interreflection", "-0.5"),
        (
            "interreflection_albedo = 1.01",
            "yarn.interreflection_albedo",
            "1.01",
        ),
        ("twist_std = -0.2", "yarn.twist_std", "-0.2"),
        ("twist_std = nan", "yarn.twist_std", "NaN"),
    ] {
        // The offending line replaces the valid one of the same key, or is added.
        let k = line.split(' ').next().unwrap();
        let mut rest = String::from("[yarn]\n");
        for default in ["lateral_length = 4.0", "slope_mean = 0.4"] {
            if !default.starts_with(k) {
                rest.push_str(default);
                rest.push('\n');
            }
        }
        rest.push_str(line);
        rest.push('\n');
        // The message names the key, the value and the valid range.
        assert_invalid(&rest, key, &[key, value, "expected"]);
    }
}

#[test]
fn vertical_laterals_are_rejected() {
    // θa = π/2 with L > 0 (one slope): laterals would be vertical slits (docs/spec.md §2.1).
    assert_invalid(
        "[yarn]\nlateral_length = 1.0\nslope_mean = 1.5707963267948966\n",
        "yarn.slope_mean",
        &["lateral_length"],
    );
    // With L = 0 (touching cylinders) or a spread of slopes it is valid.
    parse("[yarn]\nlateral_length = 0.0\nslope_mean = 1.5707963267948966\n");
    parse("[yarn]\nlateral_length = 1.0\nslope_mean = 1.5707963267948966\nslope_std = 0.3\n");
}

#[test]
fn twist_with_isotropic_is_an_error() {
    assert_invalid(
        "[yarn]\nlateral_length = 4.0\nslope_mean = 0.4\nisotropic = true\ntwist_std = 0.3\n",
        "yarn.twist_std",
        &["yarn.twist_std", "0.3", "isotropic"],
    );
    // twist_std = 0 with isotropic = true is fine.
    let m = parse(
        "[yarn]\nlateral_length = 4.0\nslope_mean = 0.4\nisotropic = true\ntwist_std = 0.0\n",
    );
    assert!(m.yarn.unwrap().isotropic);
}

// ---------------------------------------------------------------------------------------------
// Errors of the [weave] table
// ---------------------------------------------------------------------------------------------

#[test]
fn unknown_key_in_weave_table() {
    assert_parse_error(
        &format!("{YARN}[weave]\nweft_fraction = 0.5\nwarp_fraction = 0.5\n"),
        &["warp_fraction", "line"],
    );
}

#[test]
fn weft_fraction_and_pattern_together() {
    assert_invalid(
        &format!("{YARN}[weave]\nweft_fraction = 0.5\npattern = \"plain\"\n"),
        "weave.pattern",
        &["weft_fraction", "pattern"],
    );
}

#[test]
fn empty_weave_table() {
    assert_invalid(
        &format!("{YARN}[weave]\n"),
        "weave.weft_fraction",
        &["missing", "pattern"],
    );
}

#[test]
fn weft_fraction_out_of_range() {
    for (g, shown) in [("1.5", "1.5"), ("-0.1", "-0.1"), ("nan", "NaN")] {
        assert_invalid(
            &format!("{YARN}[weave]\nweft_fraction = {g}\n"),
            "weave.weft_fraction",
            &[shown, "[0, 1]"],
        );
    }
}

#[test]
fn weave_without_yarn() {
    assert_invalid("[weave]\nweft_fraction = 0.5\n", "weave", &["[yarn]"]);
    assert_invalid("[weave]\npattern = \"plain\"\n", "weave", &["[yarn]"]);
}

#[test]
fn bad_pattern_name() {
    for name in ["satin5", "tartan", "twill-2", "satin-+5", ""] {
        assert_invalid(
            &format!("{YARN}[weave]\npattern = {name:?}\n"),
            "weave.pattern",
            &["plain", "twill", "satin"],
        );
    }
}

#[test]
fn pattern_of_the_wrong_type() {
    assert_invalid(
        &format!("{YARN}[weave]\npattern = 3\n"),
        "weave.pattern",
        &["a name"],
    );
    assert_invalid(
        &format!("{YARN}[weave]\npattern = [1, 0]\n"),
        "weave.pattern[0]",
        &["matrix"],
    );
    assert_invalid(
        &format!("{YARN}[weave]\npattern = {{ file = \"plain.wif\" }}\n"),
        "weave.pattern.file",
        &["wif"],
    );
    assert_invalid(
        &format!("{YARN}[weave]\npattern = {{ wif = 3 }}\n"),
        "weave.pattern.wif",
        &["WIF"],
    );
}

#[test]
fn matrix_that_is_not_zeros_and_ones() {
    assert_invalid(
        &format!("{YARN}[weave]\npattern = [[1, 2], [0, 1]]\n"),
        "weave.pattern[0][1]",
        &["2", "0 or 1"],
    );
    assert_invalid(
        &format!("{YARN}[weave]\npattern = [[1, 0], [0, -1]]\n"),
        "weave.pattern[1][1]",
        &["-1"],
    );
    assert_invalid(
        &format!("{YARN}[weave]\npattern = [[1, 0], [0, 0.5]]\n"),
        "weave.pattern[1][1]",
        &["0.5"],
    );
    // Ragged and empty matrices.
    assert_invalid(
        &format!("{YARN}[weave]\npattern = [[1, 0], [0]]\n"),
        "weave.pattern",
        &["rectangular"],
    );
    assert_invalid(
        &format!("{YARN}[weave]\npattern = []\n"),
        "weave.pattern",
        &["non-empty"],
    );
}

#[test]
fn missing_wif_file_is_an_io_error_naming_the_path() {
    // From a string: relative to the working directory.
    let (err, msg) = parse_err(&format!(
        "{YARN}[weave]\npattern = {{ wif = \"missing.wif\" }}\n"
    ));
    match &err {
        Error::Io { path, .. } => assert_eq!(path, Path::new("missing.wif")),
        other => panic!("expected an I/O error, got {other:?}"),
    }
    assert!(msg.contains("missing.wif"), "{msg}");
    // From a file: the path joined to the file's folder.
    let dir = TempDir::new("missing");
    let path = dir.write(
        "m.toml",
        &text(&format!(
            "{YARN}[weave]\npattern = {{ wif = \"missing.wif\" }}\n"
        )),
    );
    let err = Material::from_path(&path).unwrap_err();
    match &err {
        Error::Io { path: p, .. } => assert_eq!(p, &dir.path().join("missing.wif")),
        other => panic!("expected an I/O error, got {other:?}"),
    }
    assert!(err
        .to_string()
        .contains(&dir.path().join("missing.wif").display().to_string()));
}

#[test]
fn malformed_wif_file_is_a_parse_error_naming_the_wif_path() {
    let dir = TempDir::new("bad-wif");
    dir.write("bad.wif", &wif_text("bad-line.wif"));
    let path = dir.write(
        "m.toml",
        &text(&format!(
            "{YARN}[weave]\npattern = {{ wif = \"bad.wif\" }}\n"
        )),
    );
    let err = Material::from_path(&path).unwrap_err();
    assert!(matches!(err, Error::Parse { .. }), "{err:?}");
    let wif_path = dir.path().join("bad.wif").display().to_string();
    assert!(
        err.to_string().contains(&wif_path),
        "{err} should name {wif_path}"
    );
}
