//! Helpers shared by the integration tests.

use std::path::PathBuf;
use woven::math::rng::SplitMix;
use woven::Vec3;

/// Directions from `(θ_i, φ_i, θ_r, φ_r)`.
pub fn dirs(ti: f64, pi: f64, tr: f64, pr: f64) -> (Vec3, Vec3) {
    (Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr))
}

/// The vector folders: the project's copy in `tests/data/vectors`, and `../shared/vectors` when the
/// checkout sits beside a `shared/` folder (it may carry newer cases).
pub fn vector_roots() -> Vec<PathBuf> {
    let here = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut roots = vec![here.join("tests/data/vectors")];
    let shared = here.join("../../../shared/vectors");
    if shared.is_dir() {
        roots.push(shared);
    }
    roots
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
