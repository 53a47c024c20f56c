//! The server's request bodies: what `woven serve` reads from a client — a material as JSON
//! (`woven_serve::material::from_json`, behind every endpoint that takes one) and an uploaded
//! measurement CSV (`woven_serve::data::read_csv`). The first byte picks the reader. Either
//! gives a material that writes back to a file woven reads, a dataset of 1 to `MAX_ROWS` rows,
//! or an error (the server's 400 or 422); nothing panics.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&which, body)) = data.split_first() else {
        return;
    };
    if which % 2 == 0 {
        let Ok(value) = serde_json::from_slice::<serde_json::Value>(body) else {
            return;
        };
        if let Ok(material) = woven_serve::material::from_json(&value) {
            let text = material.to_toml_string();
            assert!(woven::material::Material::from_toml_str(&text, "<back>").is_ok());
        }
    } else if let Ok(dataset) = woven_serve::data::read_csv(&String::from_utf8_lossy(body), "<fuzz>")
    {
        let n = dataset.samples.len();
        assert!((1..=woven_serve::data::MAX_ROWS).contains(&n));
    }
});
