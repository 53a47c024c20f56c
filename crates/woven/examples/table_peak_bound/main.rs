//! The true bound behind "a table is within x % of the material's peak of `f cos θi cos θr`":
//! builds a preset's table on the default grid (`TableOptions::for_model`, what `woven tabulate`
//! and the ignored test `table_accuracy_at_default_grid` use), draws N pairs of directions, each
//! uniform in solid angle over its hemisphere (no cosine weighting, no bands), for each seed, and
//! prints the worst `|f_table − f_exact| cos θi cos θr` relative to the material's peak
//! (`Table::peak_error`, the peak `Table::accuracy` reports) and where it occurs.
//!
//! The measurement quoted in README.md and docs/model.md §6 (a default-grid table takes 1.5–3.5
//! minutes to build on 2 cores; exact evaluation ~27 µs a pair for the sateen and the filament
//! satin, ~1 ms for the twisted and isotropic yarns):
//!
//! ```text
//! cargo run --release -p woven --example table_peak_bound -- polyester-sateen 1000000 1 2 3
//! cargo run --release -p woven --example table_peak_bound -- filament-satin 1000000 1 2
//! cargo run --release -p woven --example table_peak_bound -- belt-cloth 100000 1
//! cargo run --release -p woven --example table_peak_bound -- silk 100000 1
//! ```
//!
//! Arguments: `PRESET [N [SEED...]]`, N 10⁶ and seeds 1 2 3 unless given. With no arguments it is
//! a smoke run of under a minute: the sateen on a coarse grid (12 θ × 7 φ × 31² half vectors),
//! 2·10⁴ pairs, seed 1 — its figure says nothing about the default grid.

use woven::material::Material;
use woven::table::{Table, TableOptions};
use woven::Vec3;

fn main() -> Result<(), woven::Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let smoke = args.is_empty();
    let preset = args.first().map_or("polyester-sateen", String::as_str);
    let n = match args.get(1) {
        Some(a) => a
            .parse::<f64>()
            .ok()
            .filter(|n| *n >= 1.0)
            .map(|n| n as usize),
        None => Some(if smoke { 20_000 } else { 1_000_000 }),
    };
    let seeds: Option<Vec<u64>> = if args.len() > 2 {
        args[2..].iter().map(|a| a.parse().ok()).collect()
    } else if smoke {
        Some(vec![1])
    } else {
        Some(vec![1, 2, 3])
    };
    let (Some(n), Some(seeds)) = (n, seeds) else {
        eprintln!("usage: table_peak_bound [PRESET [N [SEED...]]]");
        std::process::exit(2);
    };

    let material = Material::preset(preset)?;
    let model = material.build(550.0)?;
    let options = if smoke {
        TableOptions {
            n_theta: 12,
            n_phi: 7,
            n_h: 31,
            ..TableOptions::default()
        }
    } else {
        TableOptions::for_model(&model)
    };
    let grid = if smoke {
        "coarse (smoke run)"
    } else {
        "default"
    };
    eprintln!("{preset}: building the table on the {grid} grid …");
    let start = std::time::Instant::now();
    let table = Table::build(&model, &material, &options, &|_, _| {})?;
    eprintln!("  built in {:.0} s", start.elapsed().as_secs_f64());

    println!("{preset}, {grid} grid, {n} uniform pairs per seed");
    let mut worst = 0.0f64;
    for &seed in &seeds {
        let start = std::time::Instant::now();
        let step = (n / 10).max(1);
        let progress = |done: usize, total: usize| {
            if done % step == 0 {
                eprintln!("  seed {seed}: {done} / {total}");
            }
        };
        let e = table.peak_error(&model, n, seed, &progress);
        let deg = |d: Vec3| {
            let (t, p) = d.to_spherical();
            (t.to_degrees(), p.to_degrees())
        };
        let ((ti, pi), (tr, pr)) = (deg(e.s), deg(e.v));
        println!(
            "  seed {seed}: worst {:.3} % of the peak {:.4} sr⁻¹ at θi {ti:.2}° φi {pi:.1}°, \
             θr {tr:.2}° φr {pr:.1}° (table {:.4}, exact {:.4} sr⁻¹) [{:.0} s]",
            100.0 * e.max_peak_rel,
            e.peak,
            e.table,
            e.exact,
            start.elapsed().as_secs_f64()
        );
        worst = worst.max(e.max_peak_rel);
    }
    println!(
        "  worst over {} seed(s): {:.3} % of the peak",
        seeds.len(),
        100.0 * worst
    );
    Ok(())
}
