//! Material → Model → BRDF: evaluate the polyester sateen of the paper's Fig. 8.
//!
//! Run with `cargo run --release -p woven --example evaluate`.

use woven::material::Material;
use woven::Vec3;

fn main() -> Result<(), woven::Error> {
    // A material: a preset name, or a TOML file with Material::from_path("my-fabric.toml").
    let material = Material::preset("polyester-sateen")?;
    // Prepared at one wavelength (nm): β table, refractive index, quadrature.
    let model = material.build(550.0)?;

    // Directions in the cloth's frame (z the normal, weft along x, warp along y), both pointing
    // away from the surface: s toward the light, v toward the viewer. Angles in radians.
    let s = Vec3::from_spherical(45f64.to_radians(), 0.0);
    for theta_r_deg in [0.0, 15.0, 30.0, 45.0, 60.0, 75.0] {
        let v = Vec3::from_spherical(f64::to_radians(theta_r_deg), std::f64::consts::PI);
        let f = model.eval(s, v); // BRDF in 1/sr, without the cosine
        println!("θi = 45°, θr = {theta_r_deg:>2}° in the plane of incidence: f = {f:.4} sr⁻¹");
    }

    // Energy: the directional albedo ∫ f cos θr dω is at most 1.
    let albedo = model.albedo(45f64.to_radians(), 0.0);
    println!("directional albedo at θi = 45°: {albedo:.4}");
    assert!(albedo > 0.0 && albedo <= 1.0);
    Ok(())
}
