//! docs/spec.md §6.2's bound, albedo ≤ 1, on the twisted and isotropic presets (`belt-cloth`,
//! `silk`) and on their white-furnace versions (unit Fresnel: only masking removes energy), at
//! θi 0°, 30°, 60°, 80° and φi 0.3, 1.9. Each albedo takes seconds, the whole run about ten
//! minutes on two cores: too long for CI, whose test `albedo_is_at_most_one_in_paper_mode`
//! checks the same bound on the single-orientation yarns and the sateen.
//!
//! Prints every albedo with its sanity floor (a quarter of the flat fiber's albedo, or 0.25 in
//! the furnace) and the largest of each case; exits with status 1 when one is above 1 + 10⁻³
//! (the quadrature's slack) or below its floor.
//!
//! ```text
//! cargo run --release -p woven --example albedo_bound [PRESET…]
//! ```

use woven::cloth::Structure;
use woven::fiber::Fiber;
use woven::material::Material;
use woven::yarn::Yarn;
use woven::Model;

const WAVELENGTH_NM: f64 = 550.0;
const THETAS_DEG: [f64; 4] = [0.0, 30.0, 60.0, 80.0];
const PHIS: [f64; 2] = [0.3, 1.9];
/// The slack allowed above 1 for the albedo quadrature.
const SLACK: f64 = 1e-3;

/// Every albedo of `model` against the bound and `floor(θi)`; returns the failures.
fn check(what: &str, model: &Model, floor: impl Fn(f64) -> f64) -> usize {
    let (mut largest, mut failures) = (0.0f64, 0);
    for t in THETAS_DEG {
        for phi in PHIS {
            let start = std::time::Instant::now();
            let a = model.albedo(t.to_radians(), phi);
            let lo = floor(t.to_radians());
            let verdict = if !a.is_finite() || a > 1.0 + SLACK {
                "ABOVE 1"
            } else if a < lo {
                "BELOW THE FLOOR"
            } else {
                "ok"
            };
            failures += usize::from(verdict != "ok");
            largest = largest.max(a);
            println!(
                "{what:24} θi {t:2}° φi {phi}: albedo {a:.6} (floor {lo:.6}) {verdict} [{:.1} s]",
                start.elapsed().as_secs_f64()
            );
        }
    }
    println!("{what:24} largest {largest:.6}");
    failures
}

fn main() -> Result<(), woven::Error> {
    let mut names: Vec<String> = std::env::args().skip(1).collect();
    if names.is_empty() {
        names = vec!["belt-cloth".into(), "silk".into()];
    }
    let mut failures = 0;
    for name in &names {
        let m = Material::preset(name)?;
        let f = Fiber::new(&m.fiber, WAVELENGTH_NM)?;
        let model = m.build(WAVELENGTH_NM)?;
        failures += check(name, &model, |t| 0.25 * f.albedo(t.cos()));
        let params = m.yarn.expect("the preset has a [yarn] table");
        let white = Model::new(Structure::Woven {
            yarn: Box::new(Yarn::new(f.clone().with_unit_fresnel(), params)?),
            weft_fraction: m.weft_fraction(),
            gap: 0.0,
        });
        failures += check(&format!("{name}, unit Fresnel"), &white, |_| 0.25);
    }
    if failures > 0 {
        eprintln!("{failures} albedo(s) outside their bounds");
        std::process::exit(1);
    }
    Ok(())
}
