//! The direction CSV of `woven eval`: every record parses to valid angles or a row error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use woven::directions::{DirectionReader, DirectionRecord};

fuzz_target!(|data: &[u8]| {
    let Ok(mut reader) = DirectionReader::new(data, "<fuzz>") else {
        return;
    };
    let mut record = DirectionRecord::new();
    while let Ok(true) = reader.read_record(&mut record) {
        if let Ok([theta_i, phi_i, theta_r, phi_r]) = record.angles() {
            let polar = 0.0..=std::f64::consts::FRAC_PI_2;
            assert!(polar.contains(&theta_i) && polar.contains(&theta_r));
            assert!(phi_i.is_finite() && phi_r.is_finite());
        }
    }
});
