//! scratch: table accuracy and build time
use woven::material::Material;
use woven::table::{Table, TableOptions};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map(|s| s.as_str()).unwrap_or("flat");
    let nh: usize = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(81);
    let m = match name {
        "flat" => {
            Material::from_toml_str("[fiber]\neta = 1.5\nroughness = 0.2\ndiffuse = 0.1\n", "x")
                .unwrap()
        }
        "smooth" => {
            Material::from_toml_str("[fiber]\neta = 1.5\nroughness = 0.02\ndiffuse = 0.1\n", "x")
                .unwrap()
        }
        p => Material::preset(p).unwrap(),
    };
    let model = m.build(550.0).unwrap();
    let nt: usize = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(30);
    let np: usize = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(13);
    let opts = TableOptions {
        n_h: nh,
        n_h_isotropic: nh * 2 - 1,
        n_theta: nt,
        n_phi: np,
        ..Default::default()
    };
    let t0 = std::time::Instant::now();
    let table = Table::build(&model, &m.to_toml_string(), &opts, &|_, _| {}).unwrap();
    let build = t0.elapsed();
    let n = if name == "belt-cloth" || name == "silk" {
        1000
    } else {
        4000
    };
    let r = table.accuracy(&model, n, 80f64.to_radians(), 7);
    let bytes = table.to_bytes();
    let t1 = std::time::Instant::now();
    let _t2 = Table::from_bytes(&bytes, "x").unwrap();
    if std::env::var("WORST").is_ok() {
        worst(&table, &model);
    }
    println!(
        "{name} n_h {nh}: build {build:?}, size {:.1} MB, load {:?}, rms {:.4} p99 {:.4} max {:.3}",
        bytes.len() as f64 / 1e6,
        t1.elapsed(),
        r.weighted_rel_rms,
        r.p99_rel,
        r.max_rel
    );
}
#[allow(dead_code)]
fn worst(table: &Table, model: &woven::Model) {
    let mut rng = woven::table::report::SplitMix(7);
    let mut v: Vec<(f64, String)> = (0..4000)
        .map(|_| {
            let s = rng.direction(80f64.to_radians());
            let w = rng.direction(80f64.to_radians());
            let e = model.eval(s, w);
            let t = table.eval(s, w);
            let (ti, pi) = s.to_spherical();
            let (tr, pr) = w.to_spherical();
            let h = (s + w).normalize();
            (
                (t - e).abs() / e.max(1e-6),
                format!(
                    "ti {:.1} tr {:.1} dphi {:.1} h ({:.3},{:.3}) exact {e:.4e} table {t:.4e}",
                    ti.to_degrees(),
                    tr.to_degrees(),
                    (pr - pi).to_degrees(),
                    h.x,
                    h.y
                ),
            )
        })
        .collect();
    v.sort_by(|a, b| b.0.total_cmp(&a.0));
    for x in v.iter().take(12) {
        println!("{:.3} {}", x.0, x.1);
    }
}
