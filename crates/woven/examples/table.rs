//! Material → Model → Table: tabulate a material for a renderer, save and load the table, then
//! evaluate, sample and compute densities with the `Bsdf` trait (directions named as a renderer
//! names them: `wi` toward the light, `wo` toward the viewer).
//!
//! Run with `cargo run --release -p woven --example table`. The grid here is deliberately coarse so
//! that the example builds in about a second; `woven tabulate` (or `TableOptions::for_model`) gives
//! the accurate default grid.

use woven::bsdf::{Bsdf, Transport};
use woven::material::Material;
use woven::table::{Table, TableOptions};
use woven::Vec3;

fn main() -> Result<(), woven::Error> {
    let material = Material::preset("polyester-sateen")?;
    let model = material.build(550.0)?;

    // A small grid: 12 incidence angles × 7 azimuths × 31² half vectors.
    let options = TableOptions {
        n_theta: 12,
        n_phi: 7,
        n_h: 31,
        ..TableOptions::default()
    };
    let no_progress = |_done: usize, _total: usize| {};
    let table = Table::build(&model, &material, &options, &no_progress)?;

    // A table is a file: save it, and load it back (a renderer loads one written by
    // `woven tabulate`).
    let path = std::env::temp_dir().join(format!("woven-example-{}.wtab", std::process::id()));
    table.save(&path)?;
    let table = Table::load(&path)?;
    std::fs::remove_file(&path).ok();
    println!(
        "a table at {} nm, {:?} symmetry",
        table.wavelength_nm(),
        table.symmetry()
    );

    let wi = Vec3::from_spherical(0.6, 0.0); // toward the light (the paper's s), local frame
    let wo = Vec3::from_spherical(0.5, 3.0); // toward the viewer (v)
    let f = table.eval(wi, wo); // BRDF in 1/sr, no cosine; 0 below the horizon
    let exact = model.eval(wi, wo);
    println!("f(wi, wo): table {f:.4} sr⁻¹, exact {exact:.4} sr⁻¹");

    // A camera path knows wo and draws wi (Transport::Radiance; a light path knows wi and
    // draws wo: Transport::Importance). `uc` picks a lobe, `u` draws within it: uniforms in [0, 1).
    let (uc, u) = (0.5, [0.3, 0.7]);
    if let Some(sample) = table.sample(wo, uc, u, Transport::Radiance) {
        // sample.wi is drawn ∝ f cos θi; sample.pdf is per unit solid angle, and the weight
        // f cos θi / pdf is the path throughput factor.
        println!(
            "sampled θi = {:.3} rad, f = {:.4} sr⁻¹, pdf = {:.4} sr⁻¹, weight = {:.4}",
            sample.wi.z.acos(),
            sample.f,
            sample.pdf,
            sample.weight(Transport::Radiance)
        );
        // `eval_pdf` gives f and the density `sample` draws with, in one call.
        let (f, pdf) = table.eval_pdf(sample.wi, wo, Transport::Radiance);
        assert!(f == sample.f && (pdf - sample.pdf).abs() <= 1e-6 * sample.pdf);
    }
    Ok(())
}
