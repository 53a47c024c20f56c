//! Every woven preset's yarn families projected onto the standard lobes
//! ([`woven_fit::projection`]): for each family (the weft along `x`, the warp along `y`, each
//! with its own dye and the preset's float tilt), the exact model's luminance at the 2 328
//! projection pairs (to 80°), the fitted sheen + Lambert + anisotropic GGX against the best
//! single isotropic GGX + Lambert: their RMS log errors (best overall scale removed) and the
//! mixture's parameters, as a Markdown table. The warp's GGX is fitted in the warp's own frame
//! (the yarn along `x`), so "along" is along its yarn too.
//!
//! ```text
//! cargo run --release -p woven-fit --example projection [PRESET ...]
//! ```
//! (default: every woven preset; a few minutes on 2 cores).

use woven::catalog::AnyMaterial;
use woven::material::{Material, Weave};
use woven::Vec3;
use woven_fit::projection::{project, LobeSet, Reference};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<String> = if args.is_empty() {
        Material::all_preset_names()
            .iter()
            .map(|s| s.to_string())
            .collect()
    } else {
        args
    };
    println!("| preset | family | mixture RMS log | isotropic GGX + Lambert | mixture's lobes |");
    println!("|---|---|---|---|---|");
    for name in &names {
        for (family, gamma) in [("weft", 1.0), ("warp", 0.0)] {
            let mut m = Material::preset(name)?;
            m.weave = Some(Weave::WeftFraction(gamma));
            let bsdf = AnyMaterial::Woven(m).build_rgb(550.0)?;
            // The warp runs along y: turned so that its yarn runs along x, as the weft's does.
            let turn = |d: Vec3| {
                if gamma == 0.0 {
                    Vec3::new(-d.y, d.x, d.z)
                } else {
                    d
                }
            };
            let reference = Reference::sample(|wi, wo| bsdf.eval(turn(wi), turn(wo)).luminance());
            let mixture = project(&reference, LobeSet::Fabric)?;
            println!(
                "| {name} | {family} | {:.3} | {:.3} | {} |",
                mixture.rms_log,
                mixture.baseline.as_ref().map_or(f64::NAN, |b| b.rms_log),
                mixture.lobes.describe()
            );
        }
    }
    Ok(())
}
