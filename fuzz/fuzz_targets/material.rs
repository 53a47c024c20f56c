//! Material TOML: parse and validate ([fiber], [yarn], [weave], named and inline patterns); an
//! accepted material writes back to TOML that reads back to the same material.
#![no_main]

use libfuzzer_sys::fuzz_target;
use woven::material::Material;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(material) = Material::from_toml_str(text, "<fuzz>") else {
        return;
    };
    let gamma = material.weft_fraction();
    assert!((0.0..=1.0).contains(&gamma), "weft fraction {gamma}");
    let again = Material::from_toml_str(&material.to_self_contained_toml_string(), "<again>")
        .expect("a material's own TOML reads back");
    assert_eq!(again.fiber, material.fiber);
    assert_eq!(again.yarn, material.yarn);
});
