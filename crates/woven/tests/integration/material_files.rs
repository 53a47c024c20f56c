//! Material files (the `[fiber]` table of the project's material-file contract): round trips
//! through `to_toml_string`, and error messages that name the key, the offending value and the
//! valid range.

use woven::fiber::{FiberModel, FiberParams, Ior, Normalization};
use woven::material::Material;
use woven::Error;

/// Parses `text`, failing the test with the error.
fn parse(text: &str) -> Material {
    Material::from_toml_str(text, "<test>").unwrap_or_else(|e| panic!("{e}\n--- text ---\n{text}"))
}

/// Parses `text`, which must fail; returns the error and its message.
fn parse_err(text: &str) -> (Error, String) {
    match Material::from_toml_str(text, "<test>") {
        Ok(m) => panic!("expected an error, parsed {m:?}\n--- text ---\n{text}"),
        Err(e) => {
            let msg = e.to_string();
            (e, msg)
        }
    }
}

/// Asserts that `msg` contains every one of `parts`.
#[track_caller]
fn assert_mentions(msg: &str, parts: &[&str], text: &str) {
    for p in parts {
        assert!(
            msg.contains(p),
            "error message should mention {p:?}\n  message: {msg}\n  --- text ---\n{text}"
        );
    }
}

/// Asserts an [`Error::InvalidParameter`] naming `key` whose message mentions `parts`.
#[track_caller]
fn assert_invalid(text: &str, key: &str, parts: &[&str]) {
    let (err, msg) = parse_err(text);
    match &err {
        Error::InvalidParameter { name, .. } => {
            assert_eq!(
                name, key,
                "wrong key named; message: {msg}\n--- text ---\n{text}"
            )
        }
        other => {
            panic!("expected InvalidParameter for `{key}`, got {other:?}\n--- text ---\n{text}")
        }
    }
    assert_mentions(&msg, parts, text);
}

/// Asserts an [`Error::Parse`] whose message mentions `parts`.
#[track_caller]
fn assert_parse_error(text: &str, parts: &[&str]) {
    let (err, msg) = parse_err(text);
    assert!(
        matches!(err, Error::Parse { .. }),
        "expected a parse error, got {err:?}\n--- text ---\n{text}"
    );
    assert_mentions(&msg, parts, text);
}

// ---------------------------------------------------------------------------------------------
// Valid files and round trips
// ---------------------------------------------------------------------------------------------

#[test]
fn valid_files_parse_to_the_stated_parameters() {
    let m = parse(
        r#"
name = "polyester sateen"
[fiber]
model = "rough"
eta = 1.6
roughness = 0.05
diffuse = 0.1
normalization = "none"
"#,
    );
    assert_eq!(m.name.as_deref(), Some("polyester sateen"));
    assert_eq!(
        m.fiber,
        FiberParams {
            model: FiberModel::Rough { roughness: 0.05 },
            eta: Ior::Constant(1.6),
            diffuse: 0.1,
            normalization: Normalization::None,
            body_gloss: 0.0,
            body_roughness: 0.0,
        }
    );
    // Defaults: model "rough", diffuse 0, normalization "paper"; integers are numbers.
    let m = parse("[fiber]\neta = 2\nroughness = 1\n");
    assert_eq!(m.name, None);
    assert_eq!(m.fiber, FiberParams::rough(2.0, 1.0, 0.0));
    // The full model with a Cauchy index, inline and as a sub-table.
    let htsg = FiberParams {
        model: FiberModel::Htsg {
            sigma_h_um: 0.2,
            tau_um: 2.0,
        },
        eta: Ior::Cauchy {
            cauchy_a: 1.55,
            cauchy_b_nm2: 4000.0,
        },
        diffuse: 0.0,
        normalization: Normalization::Paper,
        body_gloss: 0.0,
        body_roughness: 0.0,
    };
    let inline = parse(
        "[fiber]\nmodel = \"htsg\"\neta = { cauchy_a = 1.55, cauchy_b_nm2 = 4000.0 }\n\
         sigma_h_um = 0.2\ntau_um = 2.0\n",
    );
    assert_eq!(inline.fiber, htsg);
    let table = parse(
        "[fiber]\nmodel = \"htsg\"\nsigma_h_um = 0.2\ntau_um = 2.0\n\
         [fiber.eta]\ncauchy_a = 1.55\ncauchy_b_nm2 = 4000\n",
    );
    assert_eq!(table.fiber, htsg);
}

#[test]
fn materials_round_trip_through_toml() {
    let materials = [
        Material::flat(FiberParams::rough(1.6, 0.05, 0.1)),
        Material {
            name: Some("belt cloth \"Fig. 9\"".into()),
            ..Material::flat(
                FiberParams::rough(1.54, 0.2, 0.0).with_normalization(Normalization::None),
            )
        },
        Material {
            name: Some("silk".into()),
            ..Material::flat(FiberParams {
                model: FiberModel::Htsg {
                    sigma_h_um: 0.123456789012345,
                    tau_um: 1.0 / 3.0,
                },
                eta: Ior::Cauchy {
                    cauchy_a: 1.54,
                    cauchy_b_nm2: 3456.7,
                },
                diffuse: 0.3,
                normalization: Normalization::Paper,
                body_gloss: 0.0,
                body_roughness: 0.0,
            })
        },
        Material::flat(FiberParams::rough(1.0, 0.005, 0.0)),
        Material::flat(FiberParams::rough(4.0, 2.0, 0.99)),
    ];
    for m in materials {
        let text = m.to_toml_string();
        let back = Material::from_toml_str(&text, "<round trip>")
            .unwrap_or_else(|e| panic!("{m:?} wrote text that does not read back: {e}\n{text}"));
        assert_eq!(
            back, m,
            "round trip changed the material\n--- text ---\n{text}"
        );
        // And writing again gives the same text.
        assert_eq!(
            back.to_toml_string(),
            text,
            "text not stable under a second round trip"
        );
    }
}

#[test]
fn golden_materials_and_presets_round_trip() {
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/vectors");
    let mut sets: Vec<_> = std::fs::read_dir(&root)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.path().join("material.toml"))
        .filter(|p| p.is_file())
        .collect();
    sets.sort();
    assert!(
        sets.len() >= 3,
        "expected the golden sets under {}",
        root.display()
    );
    for path in sets {
        let m = Material::from_path(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let text = m.to_toml_string();
        assert_eq!(
            parse(&text),
            m,
            "{}\n--- written ---\n{text}",
            path.display()
        );
    }
    for name in Material::preset_names() {
        let m = Material::preset(name).unwrap_or_else(|e| panic!("preset {name}: {e}"));
        let text = m.to_toml_string();
        assert_eq!(parse(&text), m, "preset {name}\n--- written ---\n{text}");
    }
}

#[test]
fn a_missing_file_is_an_io_error_naming_the_path() {
    let err = Material::from_path("/nonexistent/woven/material.toml").unwrap_err();
    assert!(matches!(err, Error::Io { .. }), "{err:?}");
    assert_mentions(&err.to_string(), &["/nonexistent/woven/material.toml"], "");
}

// ---------------------------------------------------------------------------------------------
// Errors name the key, the value and the valid range
// ---------------------------------------------------------------------------------------------

#[test]
fn unknown_key_in_fiber_table() {
    let text = "[fiber]\neta = 1.6\nroughness = 0.05\nroughnes = 0.1\n";
    // Unknown keys are rejected by the parser, with the line.
    assert_parse_error(text, &["roughnes", "unknown field", "line 4"]);
}

#[test]
fn unknown_top_level_table() {
    let text = "[fiber]\neta = 1.6\nroughness = 0.05\n\n[glitter]\namount = 3\n";
    assert_parse_error(text, &["glitter", "unknown field", "line 5"]);
}

#[test]
fn missing_fiber_table() {
    assert_parse_error("name = \"bare\"\n", &["fiber", "missing"]);
}

#[test]
fn missing_eta() {
    assert_invalid(
        "[fiber]\nroughness = 0.05\n",
        "fiber.eta",
        &["fiber.eta", "missing", "[1, 4]"],
    );
}

#[test]
fn missing_roughness_for_the_rough_model() {
    assert_invalid(
        "[fiber]\nmodel = \"rough\"\neta = 1.6\n",
        "fiber.roughness",
        &["fiber.roughness", "missing", "[0.005, 2]", "rough"],
    );
    // Also when the model is left at its default.
    assert_invalid(
        "[fiber]\neta = 1.6\n",
        "fiber.roughness",
        &["fiber.roughness", "missing"],
    );
}

#[test]
fn missing_sigma_h_or_tau_for_the_full_model() {
    assert_invalid(
        "[fiber]\nmodel = \"htsg\"\neta = 1.6\ntau_um = 2.0\n",
        "fiber.sigma_h_um",
        &["fiber.sigma_h_um", "missing", "htsg"],
    );
    assert_invalid(
        "[fiber]\nmodel = \"htsg\"\neta = 1.6\nsigma_h_um = 0.2\n",
        "fiber.tau_um",
        &["fiber.tau_um", "missing", "htsg"],
    );
}

#[test]
fn roughness_with_the_full_model_is_the_wrong_key() {
    assert_invalid(
        "[fiber]\nmodel = \"htsg\"\neta = 1.6\nroughness = 0.05\nsigma_h_um = 0.2\ntau_um = 2.0\n",
        "fiber.roughness",
        &["fiber.roughness", "0.05", "htsg", "sigma_h_um", "tau_um"],
    );
}

#[test]
fn sigma_h_or_tau_with_the_rough_model_is_the_wrong_key() {
    assert_invalid(
        "[fiber]\nmodel = \"rough\"\neta = 1.6\nroughness = 0.05\nsigma_h_um = 0.25\n",
        "fiber.sigma_h_um",
        &["fiber.sigma_h_um", "0.25", "rough", "roughness"],
    );
    assert_invalid(
        "[fiber]\neta = 1.6\nroughness = 0.05\ntau_um = 2.5\n",
        "fiber.tau_um",
        &["fiber.tau_um", "2.5", "rough"],
    );
}

#[test]
fn bad_model_name() {
    assert_invalid(
        "[fiber]\nmodel = \"lambertian\"\neta = 1.6\nroughness = 0.05\n",
        "fiber.model",
        &["fiber.model", "lambertian", "rough", "htsg"],
    );
}

#[test]
fn bad_normalization() {
    assert_invalid(
        "[fiber]\neta = 1.6\nroughness = 0.05\nnormalization = \"energy\"\n",
        "fiber.normalization",
        &["fiber.normalization", "energy", "paper", "none"],
    );
}

#[test]
fn roughness_out_of_range() {
    for (value, shown) in [
        ("0.0", "= 0:"),
        ("7.0", "= 7:"),
        ("0.004", "= 0.004:"),
        ("-0.1", "= -0.1:"),
    ] {
        assert_invalid(
            &format!("[fiber]\neta = 1.6\nroughness = {value}\n"),
            "fiber.roughness",
            &["fiber.roughness", shown, "[0.005, 2]"],
        );
    }
    // The ends of the range are valid.
    parse("[fiber]\neta = 1.6\nroughness = 0.005\n");
    parse("[fiber]\neta = 1.6\nroughness = 2.0\n");
}

#[test]
fn full_model_roughness_ratio_out_of_range() {
    // σ_h/τ = 0.001 < 0.005.
    assert_invalid(
        "[fiber]\nmodel = \"htsg\"\neta = 1.6\nsigma_h_um = 0.01\ntau_um = 10.0\n",
        "fiber.sigma_h_um / fiber.tau_um",
        &["sigma_h_um", "tau_um", "0.001", "[0.005, 2]"],
    );
    assert_invalid(
        "[fiber]\nmodel = \"htsg\"\neta = 1.6\nsigma_h_um = 0.0\ntau_um = 1.0\n",
        "fiber.sigma_h_um",
        &["fiber.sigma_h_um", "= 0:", "(0, "],
    );
}

#[test]
fn diffuse_of_one_is_rejected() {
    assert_invalid(
        "[fiber]\neta = 1.6\nroughness = 0.05\ndiffuse = 1.0\n",
        "fiber.diffuse",
        &["fiber.diffuse", "= 1:", "[0, 1)"],
    );
    assert_invalid(
        "[fiber]\neta = 1.6\nroughness = 0.05\ndiffuse = -0.2\n",
        "fiber.diffuse",
        &["fiber.diffuse", "-0.2", "[0, 1)"],
    );
}

#[test]
fn eta_below_one_is_rejected() {
    assert_invalid(
        "[fiber]\neta = 0.5\nroughness = 0.05\n",
        "fiber.eta",
        &["fiber.eta", "0.5", "[1, 4]"],
    );
    // A Cauchy index that leaves [1, 4] somewhere in 380–780 nm names the wavelength.
    assert_invalid(
        "[fiber]\neta = { cauchy_a = 3.9, cauchy_b_nm2 = 40000.0 }\nroughness = 0.05\n",
        "fiber.eta",
        &["fiber.eta", "380 nm", "[1, 4]"],
    );
}

#[test]
fn eta_table_with_an_unknown_key() {
    assert_invalid(
        "[fiber]\neta = { cauchy_a = 1.5, cauchy_c = 12.5 }\nroughness = 0.05\n",
        "fiber.eta.cauchy_c",
        &["fiber.eta.cauchy_c", "12.5", "cauchy_a", "cauchy_b_nm2"],
    );
    // A table missing one coefficient names it.
    assert_invalid(
        "[fiber]\neta = { cauchy_a = 1.5 }\nroughness = 0.05\n",
        "fiber.eta.cauchy_b_nm2",
        &["fiber.eta.cauchy_b_nm2", "missing"],
    );
    // A string is not an index.
    assert_invalid(
        "[fiber]\neta = \"glass\"\nroughness = 0.05\n",
        "fiber.eta",
        &["fiber.eta", "glass", "cauchy_a"],
    );
}

#[test]
fn mistyped_value_is_a_parse_error_with_the_line() {
    assert_parse_error(
        "[fiber]\neta = 1.6\nroughness = \"smooth\"\n",
        &["roughness", "line 3"],
    );
}

#[test]
fn malformed_toml_reports_the_line() {
    let text = "name = \"x\"\n[fiber]\neta = 1.6\nroughness = = 0.05\n";
    assert_parse_error(text, &["<test>", "line 4"]);
    let text = "[fiber\neta = 1.6\n";
    assert_parse_error(text, &["line 1"]);
}

#[test]
fn non_finite_values_are_rejected() {
    assert_invalid(
        "[fiber]\neta = nan\nroughness = 0.05\n",
        "fiber.eta",
        &["fiber.eta", "NaN", "[1, 4]"],
    );
    assert_invalid(
        "[fiber]\neta = 1.5\nroughness = inf\n",
        "fiber.roughness",
        &["fiber.roughness", "inf", "[0.005, 2]"],
    );
}

/// The full model's length ranges are `(0, 10]` µm and `(0, 100]` µm (fiber/mod.rs's parameter
/// table), but `FiberParams::validate` checks them with `check_open(…, 10.0 + 1e-12)`, so the
/// message shows the guard: "expected a number in (0, 10.000000000001)".
#[test]
fn full_model_length_out_of_range_names_the_documented_range() {
    assert_invalid(
        "[fiber]\nmodel = \"htsg\"\neta = 1.6\nsigma_h_um = 20.0\ntau_um = 100.0\n",
        "fiber.sigma_h_um",
        &["fiber.sigma_h_um", "= 20:", "(0, 10]"],
    );
    assert_invalid(
        "[fiber]\nmodel = \"htsg\"\neta = 1.6\nsigma_h_um = 1.0\ntau_um = 150.0\n",
        "fiber.tau_um",
        &["fiber.tau_um", "= 150:", "(0, 100]"],
    );
}
