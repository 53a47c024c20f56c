//! `.wtab` tables. The input is a table file without its last four bytes: the target appends
//! the right CRC-32, so the fuzzer explores the header and payload checks rather than the checksum.
//! A table that loads must evaluate, give densities and sample without panicking, finite and
//! non-negative.
#![no_main]

use libfuzzer_sys::fuzz_target;
use woven::bsdf::{Bsdf, Transport};
use woven::table::Table;
use woven::Vec3;

fuzz_target!(|data: &[u8]| {
    let mut bytes = data.to_vec();
    bytes.extend_from_slice(&crc32fast::hash(data).to_le_bytes());
    let Ok(table) = Table::from_bytes(&bytes, "<fuzz>") else {
        return;
    };
    let dirs = [
        Vec3::from_spherical(0.0, 0.0),
        Vec3::from_spherical(0.7, 0.3),
        Vec3::from_spherical(1.5, -2.0),
        Vec3::from_spherical(1.57, 4.0),
    ];
    for &wi in &dirs {
        for &wo in &dirs {
            let f = table.eval(wi, wo);
            assert!(f.is_finite() && f >= 0.0, "eval {f}");
            for mode in [Transport::Radiance, Transport::Importance] {
                let pdf = table.pdf(wi, wo, mode);
                assert!(pdf.is_finite() && pdf >= 0.0, "pdf {pdf}");
            }
        }
        for (u1, u2) in [(0.1, 0.2), (0.9, 0.999)] {
            for mode in [Transport::Radiance, Transport::Importance] {
                if let Some(s) = table.sample(wi, 0.5, [u1, u2], mode) {
                    assert!(s.pdf.is_finite() && s.f.is_finite(), "{s:?}");
                }
            }
        }
    }
});
