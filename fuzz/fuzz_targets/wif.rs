//! WIF drafts: any text gives a pattern within the size limits or an error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use woven::weave::{Pattern, MAX_THREADS};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(p) = Pattern::from_wif_str(text, "<fuzz>") {
        assert!((1..=MAX_THREADS).contains(&p.rows()) && (1..=MAX_THREADS).contains(&p.cols()));
        let gamma = p.weft_fraction();
        assert!((0.0..=1.0).contains(&gamma), "weft fraction {gamma}");
    }
});
