//! Helpers shared by the integration tests.

use std::path::PathBuf;
use woven::math::rng::SplitMix;
use woven::Vec3;

/// Directions from `(θ_i, φ_i, θ_r, φ_r)`.
pub fn dirs(ti: f64, pi: f64, tr: f64, pr: f64) -> (Vec3, Vec3) {
    (Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr))
}

/// The vector folders: the repository's `tests/data/vectors` (docs/spec.md §6.7).
pub fn vector_roots() -> Vec<PathBuf> {
    let here = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    vec![here.join("tests/data/vectors")]
}

/// Asserts `|got − want| ≤ rel · |want|` (or `≤ abs_floor` absolutely), printing both.
#[track_caller]
pub fn assert_close(got: f64, want: f64, rel: f64, abs_floor: f64, what: &str) {
    let err = (got - want).abs();
    assert!(
        err <= rel * want.abs() || err <= abs_floor,
        "{what}: got {got:.12e}, want {want:.12e}, |err| {err:.3e}, rel tolerance {rel:.1e}"
    );
}

/// The library's test generator ([`woven::math::rng::SplitMix`]) under a local name, so that
/// test files can add the draws they need in their own `impl Rng` blocks; every run draws the
/// same cases.
pub struct Rng(pub u64);

impl Rng {
    /// Runs `draw` on the library generator in this state, keeping the state it leaves.
    fn draw<T>(&mut self, draw: impl FnOnce(&mut SplitMix) -> T) -> T {
        let mut g = SplitMix(self.0);
        let x = draw(&mut g);
        self.0 = g.0;
        x
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.draw(SplitMix::next_u64)
    }

    /// Uniform in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        self.draw(SplitMix::uniform)
    }

    /// Uniform in `[a, b)`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        self.draw(|g| g.range(a, b))
    }

    /// `10^x`, `x` uniform in `[lo, hi)`.
    pub fn log_range(&mut self, lo: f64, hi: f64) -> f64 {
        self.draw(|g| g.log_range(lo, hi))
    }
}

/// A material for the table tests: a preset, `rough` and `smooth` flat fibers, or `smooth-sateen`
/// (the sateen preset at the smooth fiber's roughness 0.02).
pub fn table_material(name: &str) -> woven::material::Material {
    use woven::material::Material;
    match name {
        "rough" => {
            Material::from_toml_str("[fiber]\neta = 1.5\nroughness = 0.2\ndiffuse = 0.1\n", name)
                .unwrap()
        }
        "smooth" => Material::from_toml_str(
            "[fiber]\neta = 1.5\nroughness = 0.02\ndiffuse = 0.1\n",
            name,
        )
        .unwrap(),
        "smooth-sateen" => {
            let sateen = Material::preset("polyester-sateen")
                .unwrap()
                .to_toml_string();
            let text = sateen.replace("roughness = 0.05", "roughness = 0.02");
            assert_ne!(text, sateen, "the sateen's roughness moved");
            Material::from_toml_str(&text, name).unwrap()
        }
        preset => Material::preset(preset).unwrap(),
    }
}

/// The model and the default-grid table ([`woven::table::TableOptions::for_model`]) of
/// [`table_material`]`(name)`, built once per test binary: the slow tests of several files share
/// them (a full table takes tens of seconds).
pub fn default_table(name: &str) -> &'static (woven::Model, woven::table::Table) {
    use std::sync::{Mutex, OnceLock};
    use woven::table::{Table, TableOptions};
    type Entry = (String, &'static OnceLock<(woven::Model, Table)>);
    static CACHE: OnceLock<Mutex<Vec<Entry>>> = OnceLock::new();
    let cell = {
        let mut cache = CACHE.get_or_init(Default::default).lock().unwrap();
        match cache.iter().find(|(n, _)| n == name) {
            Some((_, cell)) => *cell,
            None => {
                let cell: &'static OnceLock<_> = Box::leak(Box::default());
                cache.push((name.to_string(), cell));
                cell
            }
        }
    };
    cell.get_or_init(|| {
        let m = table_material(name);
        let model = m.build(550.0).unwrap();
        let t = Table::build(&model, &m, &TableOptions::for_model(&model), &|_, _| {}).unwrap();
        (model, t)
    })
}
