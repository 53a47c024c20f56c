//! scratch
use woven::material::Material;
fn main() {
    for dir in std::fs::read_dir("crates/woven/tests/data/vectors").unwrap() {
        let dir = dir.unwrap().path(); if !dir.is_dir() { continue; }
        let m = Material::from_path(dir.join("material.toml")).unwrap();
        let model = m.build(550.0).unwrap();
        let text = std::fs::read_to_string(dir.join("cases.csv")).unwrap();
        let mut worst: f64 = 0.0;
        let t = std::time::Instant::now();
        let mut n = 0;
        for line in text.lines().skip(1) {
            let x: Vec<f64> = line.split(',').map(|t| t.parse().unwrap()).collect();
            let s = woven::Vec3::from_spherical(x[0], x[1]);
            let v = woven::Vec3::from_spherical(x[2], x[3]);
            let got = model.eval(s, v);
            if x[4].abs() > 1e-9 { worst = worst.max(((got - x[4]) / x[4]).abs()); }
            n += 1;
        }
        println!("{:30} worst rel {:.2e}  {:?}/eval", dir.file_name().unwrap().to_string_lossy(), worst, t.elapsed() / n);
    }
    for name in Material::preset_names() {
        let model = Material::preset(name).unwrap().build(550.0).unwrap();
        let t = std::time::Instant::now();
        let mut acc = 0.0;
        for k in 0..20 {
            let s = woven::Vec3::from_spherical(0.2 + 0.06 * k as f64, 0.3 * k as f64);
            let v = woven::Vec3::from_spherical(0.9 - 0.03 * k as f64, 2.0 + 0.2 * k as f64);
            acc += model.eval(s, v);
        }
        println!("{name:20} {:?}/eval ({acc:.6})", t.elapsed() / 20);
    }
}
