//! The keys of a woven surface (`woven::surface::SURFACE_KEYS`): one home for each key's name,
//! default, valid range and meaning. The defaults are those `SurfaceSpec::new` lays, the ranges
//! those the library's checks state, and docs/python.md shows the same table, row for row. Every
//! front end reads them through `SurfaceSpec::from_keys`, each key by its own entry.

use woven::color::Rgb;
use woven::fiber::DEFAULT_WAVELENGTH_NM;
use woven::keys::{KeyValue, Keys};
use woven::material::{Material, Weave};
use woven::surface::{
    Detail, Irregularity, SurfaceKey, SurfaceSpec, DEFAULT_YARNS_PER_UNIT, SURFACE_KEYS,
};

/// The key `name`.
fn key(name: &str) -> &'static SurfaceKey {
    SurfaceKey::named(name).unwrap_or_else(|| panic!("no surface key `{name}`"))
}

/// The table as docs/python.md shows it: a header and one row per key, in the table's order.
fn markdown() -> String {
    let cell = |s: String| s.replace('|', "\\|");
    let mut out = String::from("| key | default | valid | meaning |\n|---|---|---|---|\n");
    for k in SURFACE_KEYS {
        out += &format!(
            "| `{}` | {} | {} | {} |\n",
            k.name,
            cell(k.default()),
            cell(k.valid()),
            cell(k.meaning())
        );
    }
    out
}

/// docs/python.md holds the table exactly (every key's row, its default and its range, and no
/// other row): to update it, paste what this test prints.
#[test]
fn the_python_docs_show_the_surface_keys_table() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/python.md");
    let docs = std::fs::read_to_string(path).unwrap();
    let table = markdown();
    let Some(at) = docs.find(&table) else {
        panic!(
            "docs/python.md does not show SURFACE_KEYS as it is; its table should read:\n\n{table}"
        );
    };
    let before = docs[..at].lines().last().unwrap_or("");
    let after = docs[at + table.len()..].lines().next().unwrap_or("");
    assert!(
        !before.starts_with('|') && !after.starts_with('|'),
        "docs/python.md's table of surface keys has rows that are not in SURFACE_KEYS"
    );
    assert_eq!(
        docs.matches("| key | default | valid | meaning |").count(),
        1,
        "docs/python.md shows the table once"
    );
}

/// Every key is named once, and every cell says something.
#[test]
fn surface_keys_are_named_once_and_filled() {
    for (i, k) in SURFACE_KEYS.iter().enumerate() {
        assert!(
            SURFACE_KEYS[..i].iter().all(|o| o.name != k.name),
            "`{}` twice",
            k.name
        );
        for text in [k.default(), k.valid(), k.meaning()] {
            assert!(!text.trim().is_empty(), "`{}` has an empty cell", k.name);
        }
    }
    for name in [
        "material",
        "pattern",
        "weft_fraction",
        "yarns_per_unit",
        "weft_color",
        "warp_color",
        "u_max_deg",
        "gap",
        "detail",
        "irregularity",
        "irregularity_length",
        "wavelength_nm",
        "footprint_filter",
    ] {
        key(name);
    }
}

/// The numeric defaults are those a surface is laid with where not told (`SurfaceSpec::new`,
/// `Irregularity::default`, the library's wavelength), and 40 cells per unit.
#[test]
fn surface_keys_state_the_defaults_surface_spec_lays() {
    let number = |name: &str| -> f64 {
        key(name)
            .default()
            .parse()
            .unwrap_or_else(|e| panic!("`{name}`'s default: {e}"))
    };
    let spec = SurfaceSpec::new(Material::preset("polyester-sateen").unwrap());
    assert_eq!(DEFAULT_YARNS_PER_UNIT, 40.0);
    assert_eq!(spec.yarns_per_unit, [number("yarns_per_unit"); 2]);
    // The gap and the transmission are the material's own (`[weave]`), else none.
    assert!(key("gap")
        .default()
        .starts_with("the material's [weave] gap, else 0"));
    assert!(key("transmission")
        .default()
        .starts_with("the material's [weave] transmission, else false"));
    assert_eq!((spec.gap, spec.transmission), (0.0, false));
    let voile = SurfaceSpec::new(Material::preset("cotton-voile").unwrap());
    assert_eq!((voile.gap, voile.transmission), (0.5, true));
    assert_eq!(spec.irregularity.spread, [number("irregularity"); 2]);
    assert_eq!(spec.irregularity.length, number("irregularity_length"));
    assert_eq!(spec.irregularity, Irregularity::default());
    assert_eq!(DEFAULT_WAVELENGTH_NM, number("wavelength_nm"));
    assert_eq!(key("detail").default(), format!("{:?}", spec.detail.name()));
    assert_eq!(spec.detail, Detail::default());
    assert_eq!(key("footprint_filter").default(), "true");
}

/// The interval an error states as expected (`[0, 0.95]`), if any.
fn interval(expected: &str) -> Option<&str> {
    let start = expected.find('[')?;
    let end = start + expected[start..].find(']')?;
    Some(&expected[start..=end])
}

/// What the library's checks refuse, they refuse with the range the key states: each error's
/// expected interval (or list of names) is in the key's `valid`.
#[test]
fn surface_keys_state_the_ranges_the_library_checks() {
    let mut material = Material::preset("polyester-sateen").unwrap();
    material.weave = Some(Weave::named("plain").unwrap());
    let spec = SurfaceSpec::new(material.clone());
    let refused = |name: &str, bad: SurfaceSpec| {
        let Err(woven::Error::InvalidParameter {
            name: n, expected, ..
        }) = bad.validate()
        else {
            panic!("`{name}`: not refused as an invalid parameter");
        };
        (n, expected)
    };
    let cases = [
        (
            "gap",
            refused(
                "gap",
                SurfaceSpec {
                    gap: 0.99,
                    ..spec.clone()
                },
            ),
        ),
        (
            "u_max_deg",
            refused(
                "u_max_deg",
                SurfaceSpec {
                    u_max: 95f64.to_radians(),
                    ..spec.clone()
                },
            ),
        ),
        (
            "weft_color",
            refused(
                "weft_color",
                SurfaceSpec {
                    weft_color: Some(Rgb([1.5, 0.0, 0.0])),
                    ..spec.clone()
                },
            ),
        ),
        (
            "irregularity",
            refused(
                "irregularity",
                SurfaceSpec {
                    irregularity: Irregularity {
                        spread: [1.5, 0.0],
                        ..Irregularity::default()
                    },
                    ..spec.clone()
                },
            ),
        ),
        (
            "irregularity_length",
            refused(
                "irregularity_length",
                SurfaceSpec {
                    irregularity: Irregularity {
                        length: 0.0,
                        ..Irregularity::default()
                    },
                    ..spec.clone()
                },
            ),
        ),
    ];
    for (name, (_, expected)) in &cases {
        let range = interval(expected).unwrap_or_else(|| panic!("`{name}`: {expected}"));
        // The library's check of u_max states its range in degrees with a sign: `[0, 80°]`.
        let range = range.replace('°', "");
        assert!(
            key(name).valid().contains(&range),
            "`{name}`: the check expects {expected}, the key says {}",
            key(name).valid()
        );
    }
    let Err(woven::Error::InvalidParameter { expected, .. }) = Detail::from_name("threads") else {
        panic!("`detail` = \"threads\" accepted");
    };
    assert_eq!(expected, key("detail").valid());
    for name in Detail::NAMES {
        assert_eq!(Detail::from_name(name).unwrap().name(), name);
    }
    let Err(e) = material.build(1.0) else {
        panic!("a wavelength of 1 nm accepted");
    };
    let message = e.to_string();
    let range = interval(&message).unwrap_or_else(|| panic!("{message}"));
    assert!(key("wavelength_nm").valid().contains(range), "{message}");
}

/// A value each key takes, and one it refuses: every key of the table has both, so a key added
/// to `SURFACE_KEYS` without a reader that takes and refuses values fails here.
fn samples(name: &str) -> (KeyValue, KeyValue) {
    use KeyValue::{Bool, Float, Integer, List, Text};
    let rgb = |r, g, b| List(vec![Float(r), Float(g), Float(b)]);
    match name {
        "material" => (Text("belt-cloth".into()), Text("velvet".into())),
        "pattern" => (Text("twill-2/1".into()), Integer(3)),
        "weft_fraction" => (Float(0.3), Float(1.5)),
        "yarns_per_unit" => (Text("40, 60.5".into()), List(vec![Float(40.0)])),
        "weft_color" => (rgb(0.6, 0.1, 0.1), rgb(1.5, 0.0, 0.0)),
        "warp_color" => (rgb(0.1, 0.1, 0.6), List(vec![Float(0.5); 2])),
        "u_max_deg" => (Integer(30), Float(95.0)),
        "gap" => (Float(0.2), Float(f64::NAN)),
        "detail" => (Text("fibers".into()), Text("threads".into())),
        "relief" => (Bool(true), Text("yes".into())),
        "transmission" => (Bool(true), Integer(1)),
        "irregularity" => (List(vec![Float(0.1), Float(0.4)]), Float(1.5)),
        "irregularity_length" => (Integer(60), Float(0.5)),
        "wavelength_nm" => (Float(450.0), Float(1.0)),
        "footprint_filter" => (Bool(false), Text("false".into())),
        other => panic!("no sample values for the surface key `{other}`: add them here"),
    }
}

/// The keys a key needs beside it to be read alone (irregularity needs a pattern).
fn beside(name: &str) -> Keys {
    let keys = Keys::new().with("material", KeyValue::Text("silk".into()));
    match name {
        "irregularity" | "irregularity_length" | "relief" => {
            keys.with("pattern", KeyValue::Text("plain".into()))
        }
        _ => keys,
    }
}

/// One reader for every door: each key's value is read onto the surface and marked given, and
/// a value out of its range or of another shape is refused naming the key, the value and the
/// range the table states.
#[test]
fn from_keys_reads_and_refuses_each_key_by_its_entry() {
    for k in SURFACE_KEYS {
        let (good, bad) = samples(k.name);
        let read = SurfaceSpec::from_keys(&beside(k.name).with(k.name, good.clone()))
            .unwrap_or_else(|e| panic!("`{}` = {good}: {e}", k.name));
        assert!(read.given(k.name), "{}", k.name);
        let e = SurfaceSpec::from_keys(&beside(k.name).with(k.name, bad.clone()))
            .err()
            .unwrap_or_else(|| panic!("`{}` = {bad} accepted", k.name));
        let message = e.to_string();
        assert!(e.key.starts_with(k.name), "`{}`: {message}", k.name);
        assert!(message.contains(&format!("`{}`", k.name)), "{message}");
        if k.name != "material" && k.name != "pattern" {
            assert!(message.contains(&k.valid()), "`{}`: {message}", k.name);
        }
    }
    // What each read value became.
    let read = |name: &str| {
        SurfaceSpec::from_keys(&beside(name).with(name, samples(name).0))
            .unwrap()
            .spec
    };
    assert_eq!(read("yarns_per_unit").yarns_per_unit, [40.0, 60.5]);
    assert_eq!(read("u_max_deg").u_max, 30f64.to_radians());
    assert_eq!(read("gap").gap, 0.2);
    assert_eq!(read("detail").detail, Detail::Fibers);
    assert_eq!(read("weft_color").weft_color, Some(Rgb([0.6, 0.1, 0.1])));
    assert_eq!(read("irregularity").irregularity.spread, [0.1, 0.4]);
    assert_eq!(
        read("weft_fraction").material.weave,
        Some(Weave::WeftFraction(0.3))
    );
    assert_eq!(
        read("material").material.name.as_deref(),
        Some("belt-cloth")
    );
    let other =
        SurfaceSpec::from_keys(&beside("x").with("wavelength_nm", KeyValue::Float(450.0))).unwrap();
    assert_eq!((other.wavelength_nm, other.footprint_filter), (450.0, true));
}

/// Keys not given are the library's defaults: the surface `SurfaceSpec::new` lays on the
/// material, which keeps its own dyes and tilt.
#[test]
fn from_keys_leaves_what_is_not_given_at_its_default() {
    let read = SurfaceSpec::from_keys(
        &Keys::new().with("material", KeyValue::Text("satin-charmeuse".into())),
    )
    .unwrap();
    let own = SurfaceSpec::new(Material::preset("satin-charmeuse").unwrap());
    assert_eq!(format!("{:?}", read.spec), format!("{own:?}"));
    assert_eq!(read.wavelength_nm, DEFAULT_WAVELENGTH_NM);
    assert!(read.footprint_filter && read.given_keys() == ["material"]);
}

/// What no single key can check: unknown keys (listing the known), `pattern` with
/// `weft_fraction`, a tilt or gap on a flat fiber surface, irregularity without a pattern, and
/// a material given twice.
#[test]
fn from_keys_refuses_what_the_keys_cannot_be_together() {
    let silk = || Keys::new().with("material", KeyValue::Text("silk".into()));
    let refused = |keys: Keys| SurfaceSpec::from_keys(&keys).unwrap_err();
    let e = refused(silk().with("colour", KeyValue::Float(1.0)));
    assert_eq!(e.key, "colour");
    assert!(e.to_string().contains("`footprint_filter`"), "{e}");
    let e = refused(
        silk()
            .with("pattern", KeyValue::Text("plain".into()))
            .with("weft_fraction", KeyValue::Float(0.5)),
    );
    assert_eq!(e.key, "weft_fraction", "{e}");
    let sateen = Keys::new().with("material", KeyValue::Text("polyester-sateen".into()));
    let e = refused(sateen.with("irregularity", KeyValue::Float(0.2)));
    assert!(
        e.key == "irregularity" && e.to_string().contains("pattern"),
        "{e}"
    );
    let dir = std::env::temp_dir().join(format!("woven-keys-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("fiber.toml"),
        "[fiber]\neta = 1.6\nroughness = 0.1\ndiffuse = 0\nnormalization = \"none\"\n",
    )
    .unwrap();
    let flat = Keys::new()
        .with("material", KeyValue::Text("fiber.toml".into()))
        .in_folder(&dir);
    let e = refused(flat.clone().with("gap", KeyValue::Float(0.1)));
    assert!(e.key == "gap" && e.to_string().contains("no [yarn]"), "{e}");
    assert!(
        SurfaceSpec::from_keys(&flat).is_ok(),
        "the folder resolves the file"
    );
    std::fs::remove_dir_all(&dir).unwrap();
    let e = SurfaceSpec::from_keys_on(Material::preset("silk").unwrap(), &silk()).unwrap_err();
    assert_eq!(e.key, "material", "{e}");
    let e = refused(Keys::new().with("gap", KeyValue::Float(0.1)));
    assert_eq!(e.key, "material", "{e}");
}

/// `to_keys` is `from_keys_on`'s inverse: a surface with every key set, and one with none, read
/// back from its keys on its material as the same surface.
#[test]
fn to_keys_reads_back_as_the_same_surface() {
    let keys = Keys::new()
        .with("material", KeyValue::Text("satin-charmeuse".into()))
        .with("pattern", KeyValue::Text("twill-3/1".into()))
        .with("yarns_per_unit", KeyValue::Text("80, 120".into()))
        .with("weft_color", samples("weft_color").0)
        .with("gap", KeyValue::Float(0.1))
        .with("detail", KeyValue::Text("yarns".into()))
        .with("irregularity", KeyValue::Float(0.3))
        .with("irregularity_length", KeyValue::Float(40.0))
        .with("u_max_deg", KeyValue::Float(17.0));
    let plain = Keys::new().with("material", KeyValue::Text("satin-charmeuse".into()));
    for source in [keys, plain] {
        let spec = SurfaceSpec::from_keys(&source).unwrap().spec;
        let again = SurfaceSpec::from_keys_on(spec.material.clone(), &spec.to_keys()).unwrap();
        let (a, b) = (format!("{spec:?}"), format!("{:?}", again.spec));
        if a != b {
            // Degrees and back may round the tilt by an ulp; nothing else may change.
            assert!((spec.u_max - again.spec.u_max).abs() < 1e-15, "{a}\n{b}");
            let again = SurfaceSpec {
                u_max: spec.u_max,
                ..again.spec
            };
            assert_eq!(a, format!("{again:?}"));
        }
    }
}
