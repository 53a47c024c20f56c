//! The keys of a woven surface (`woven::surface::SURFACE_KEYS`): one home for each key's name,
//! default, valid range and meaning. The defaults are those `SurfaceSpec::new` lays, the ranges
//! those the library's checks state, and docs/python.md shows the same table, row for row.

use woven::color::Rgb;
use woven::fiber::DEFAULT_WAVELENGTH_NM;
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
    assert_eq!(spec.gap, number("gap"));
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
