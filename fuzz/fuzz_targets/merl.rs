//! MERL BRDF files: any bytes give a complete table or an error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use woven::export::merl::MerlBrdf;

fuzz_target!(|data: &[u8]| {
    if let Ok(merl) = MerlBrdf::read(data) {
        assert!(merl.value(0).iter().all(|v| v.is_finite()));
    }
});
