//! Measures the energy guard of each microcylinder preset on the fine grid and prints the table
//! `woven::microcylinder::PRESET_GUARDS` holds, then each preset's directional albedo with and
//! without its guard (docs/microcylinder.md §6, "Energy guard").
//!
//! ```text
//! cargo run --release -p woven --example microcylinder_guard
//! ```

use woven::microcylinder::{
    default_rule, EnergyGuard, Microcylinder, PRESET_GUARD_MARGIN, PRESET_GUARD_PHI_COUNT,
};

fn main() -> Result<(), woven::Error> {
    println!("pub const PRESET_GUARDS: [[f64; 13]; 6] = [");
    for name in Microcylinder::preset_names() {
        let threads = Microcylinder::preset_threads(name)?;
        let cloth = Microcylinder::with_options(*name, threads, &default_rule, false)?;
        let guard = EnergyGuard::build(
            &|wi, wo| cloth.eval_unguarded(wi, wo),
            PRESET_GUARD_PHI_COUNT,
            PRESET_GUARD_MARGIN,
        );
        let row: Vec<String> = guard.table().iter().map(|h| format!("{h:e}")).collect();
        println!("    // {name}\n    [{}],", row.join(", "));
    }
    println!("];");
    // The record of docs/microcylinder.md §6: each preset's directional albedo (largest
    // channel) at φi = 0, guarded (printed model in brackets).
    for name in Microcylinder::preset_names() {
        let cloth = Microcylinder::preset(name)?;
        print!("| {name} |");
        for t in [0.0, 30.0, 60.0, 75.0, 85.0, 89.0] {
            let theta = f64::to_radians(t);
            let (g, u) = (
                cloth.albedo(theta, 0.0).max(),
                cloth.albedo_unguarded(theta, 0.0).max(),
            );
            print!(" {g:.3} ({u:.3}) |");
        }
        println!();
    }
    Ok(())
}
