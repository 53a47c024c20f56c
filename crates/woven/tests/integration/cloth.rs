//! The yarn and cloth BRDFs (paper Eqs. (17)–(23); docs/spec.md §2) against their defining
//! properties (docs/spec.md §6): the profile BRDF against brute-force ray casting, its limits (flat,
//! unmasked Lambertian closed form, V-groove), reciprocity in `none` mode, mirror and rotation
//! symmetries, albedo ≤ 1, convergence of the default quadrature, non-negativity, and the presets.
//!
//! Fast versions run by default (`cargo test --release -p woven --test integration cloth`);
//! exhaustive ones are `#[ignore]`d and run with `-- --include-ignored` (a few minutes).

use crate::common::{assert_close, vector_roots, Rng};
use std::f64::consts::{FRAC_1_PI, FRAC_PI_2, PI};
use woven::cloth::Structure;
use woven::fiber::{Fiber, FiberModel, FiberParams, Ior, Normalization};
use woven::material::Material;
use woven::math::quadrature::{adaptive, GaussLegendre};
use woven::yarn::profile::{Piece, Profile};
use woven::yarn::raycast::is_lit;
use woven::yarn::{Quadrature, Yarn, YarnParams};
use woven::{Model, Vec3};

const WAVELENGTH_NM: f64 = 550.0;
const DEG: f64 = PI / 180.0;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

impl Rng {
    fn chance(&mut self, p: f64) -> bool {
        self.uniform() < p
    }

    /// A polar angle in `[0, max]`: 10 % exactly 0 (normal), 25 % within 8° of `max` (grazing),
    /// else uniform.
    fn theta(&mut self, max: f64) -> f64 {
        let r = self.uniform();
        if r < 0.10 {
            0.0
        } else if r < 0.35 {
            self.range(max - 8.0 * DEG, max)
        } else {
            self.range(0.0, max)
        }
    }

    /// A direction of polar angle [`Rng::theta`]`(max)` and uniform azimuth.
    fn direction(&mut self, max: f64) -> Vec3 {
        let t = self.theta(max);
        Vec3::from_spherical(t, self.range(0.0, 2.0 * PI))
    }
}

/// `n` fibers of `σ_h/τ` log-uniform in `roughness`, η in [1.3, 1.8) and `ρ0` in [0, 0.5)
/// (0 for a third), alternately in `none` and `paper` mode: a pool that random cases draw from,
/// since building a `paper`-mode fiber (its β table) takes ~0.1 s.
fn fiber_pool(rng: &mut Rng, n: usize, roughness: (f64, f64)) -> Vec<Fiber> {
    (0..n)
        .map(|i| {
            let normalization = if i % 2 == 0 {
                Normalization::None
            } else {
                Normalization::Paper
            };
            let r = rng.log_range(roughness.0.log10(), roughness.1.log10());
            let diffuse = if i % 3 == 0 { 0.0 } else { rng.range(0.0, 0.5) };
            fiber(rng.range(1.3, 1.8), r, diffuse, normalization)
        })
        .collect()
}

/// A fiber surface, failing the test with the error.
fn fiber(eta: f64, roughness: f64, diffuse: f64, normalization: Normalization) -> Fiber {
    let p = FiberParams::rough(eta, roughness, diffuse).with_normalization(normalization);
    Fiber::new(&p, WAVELENGTH_NM).unwrap_or_else(|e| panic!("{p:?}: {e}"))
}

/// A yarn, failing the test with the error.
fn yarn(fiber: &Fiber, params: YarnParams) -> Yarn {
    Yarn::new(fiber.clone(), params).unwrap_or_else(|e| panic!("{params:?}: {e}"))
}

/// Yarn parameters: lateral length, slope mean and spread; the rest default.
fn yarn_params(lateral_length: f64, slope_mean: f64, slope_std: f64) -> YarnParams {
    YarnParams {
        lateral_length,
        slope_mean,
        slope_std,
        ..YarnParams::default()
    }
}

/// A woven model of `yarn` with weft fraction `gamma`.
fn woven(yarn: Yarn, gamma: f64) -> Model {
    Model::new(Structure::Woven {
        yarn: Box::new(yarn),
        weft_fraction: gamma,
        gap: 0.0,
    })
}

/// `e_u = (−sin φ_a, cos φ_a, 0)`, across fibers of azimuth `phi_a` (docs/spec.md §2.1).
fn across(phi_a: f64) -> Vec3 {
    let (sp, cp) = phi_a.sin_cos();
    Vec3::new(-sp, cp, 0.0)
}

/// The projected angle `ψ = atan2(d·e_u, d·z)` (docs/spec.md §2.2).
fn psi(d: Vec3, phi_a: f64) -> f64 {
    d.dot(across(phi_a)).atan2(d.z)
}

/// `(θ, φ)` of a direction, for failure messages.
fn sph(d: Vec3) -> String {
    let (t, p) = d.to_spherical();
    format!("(θ {t:.17}, φ {p:.17})")
}

/// `|got − want|` relative to `max(|want|, floor)`.
fn rel_err(got: f64, want: f64, floor: f64) -> f64 {
    (got - want).abs() / want.abs().max(floor)
}

/// Records the worst value of a statistic and what produced it.
#[derive(Default)]
struct Worst {
    value: f64,
    case: String,
}

impl Worst {
    fn update(&mut self, value: f64, case: impl FnOnce() -> String) {
        if value > self.value || (self.case.is_empty() && value >= self.value) {
            self.value = value;
            self.case = case();
        }
    }

    fn report(&self, what: &str) {
        eprintln!("worst {what}: {:.3e} at {}", self.value, self.case);
    }
}

/// A material from TOML text, failing the test with the error.
fn material(text: &str) -> Material {
    Material::from_toml_str(text, "<cloth test>").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// A preset, failing the test with the error.
fn preset(name: &str) -> Material {
    Material::preset(name).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A woven material built with the given quadrature orders (default when `None`).
fn build_with(fiber: &Fiber, m: &Material, q: Option<Quadrature>) -> Model {
    let y = yarn(fiber, m.yarn.expect("a [yarn] table"));
    let y = match q {
        Some(q) => y.with_quadrature(q),
        None => y,
    };
    woven(y, m.weft_fraction())
}

// ---------------------------------------------------------------------------------------------
// 1. Profile BRDF (Eq. (17)) against brute force
// ---------------------------------------------------------------------------------------------

/// The fiber BRDF at a facet of unit normal `a` (in the `(e_u, z)` plane of fibers along
/// `e_f`), evaluated independently of `Fiber::eval_with_normal`: both directions are expressed
/// in the facet's own frame `(e_f, a × e_f, a)` and given to `Fiber::eval` (normal `z`). The
/// fiber surface is isotropic, so any tangent frame gives the same value.
fn fiber_at_facet(fiber: &Fiber, s: Vec3, v: Vec3, a: Vec3, e_f: Vec3) -> f64 {
    let b = a.cross(e_f);
    let local = |d: Vec3| Vec3::new(d.dot(e_f), d.dot(b), d.dot(a));
    fiber.eval(local(s), local(v))
}

/// Samples per piece of the brute force: the arc carries the highlight, so it gets more.
const BRUTE_ARC_SAMPLES: usize = 40_000;
const BRUTE_LATERAL_SAMPLES: usize = 10_000;

/// Eq. (17) by brute force: the midpoint rule over `n` samples per piece of one period, each
/// sample lit and visible (or not) by 2D ray casting ([`is_lit`]), and the fiber BRDF evaluated
/// in the facet's frame. Returns the estimate and a bound on the midpoint rule's error at the
/// ends of the lit-and-visible intervals (each end misplaced by at most half a sample, where the
/// integrand is at most its largest sampled value).
fn brute_force_profile(
    fiber: &Fiber,
    profile: &Profile,
    s: Vec3,
    v: Vec3,
    phi_a: f64,
) -> (f64, f64) {
    let e_u = across(phi_a);
    let e_f = Vec3::new(e_u.y, -e_u.x, 0.0);
    let (psi_s, psi_v) = (psi(s, phi_a), psi(v, phi_a));
    let (mut sum, mut bound) = (0.0, 0.0);
    for piece in Piece::ALL {
        let (lo, hi) = profile.parameter_range(piece);
        if hi <= lo {
            continue;
        }
        let n = if piece == Piece::Arc {
            BRUTE_ARC_SAMPLES
        } else {
            BRUTE_LATERAL_SAMPLES
        };
        let dx = (hi - lo) / n as f64;
        let (mut piece_sum, mut g_max) = (0.0f64, 0.0f64);
        for k in 0..n {
            let x = lo + (k as f64 + 0.5) * dx;
            let normal = profile.normal(piece, x);
            let a = e_u * normal.0 + Vec3::Z * normal.1;
            let (sa, va) = (s.dot(a), v.dot(a));
            if sa <= 0.0 || va <= 0.0 {
                continue;
            }
            let g = fiber_at_facet(fiber, s, v, a, e_f) * sa * va;
            g_max = g_max.max(g);
            let point = profile.point(piece, x);
            if is_lit(profile, point, normal, psi_s) && is_lit(profile, point, normal, psi_v) {
                piece_sum += g;
            }
        }
        sum += piece_sum * dx;
        bound += g_max * dx;
    }
    let denominator = profile.period() * s.z * v.z;
    (sum / denominator, bound / denominator)
}

/// Compares `profile_brdf` with [`brute_force_profile`] for `cases` random profiles, direction
/// pairs (up to 89°) and fibers of roughness `σ_h/τ ∈ roughness` in both modes; asserts
/// agreement to 1e-3 relative beyond the brute force's own sampling bound (values below `floor`
/// sr⁻¹ compare absolutely, to `1e-3 · floor`).
fn profile_against_brute_force(cases: usize, seed: u64, roughness: (f64, f64), floor: f64) {
    let mut rng = Rng(seed);
    let mut worst = Worst::default();
    let mut worst_excess = Worst::default();
    let pool = fiber_pool(&mut rng, 12, roughness);
    for i in 0..cases {
        let f = &pool[(rng.next_u64() % pool.len() as u64) as usize];
        let (theta_a, l) = match i % 6 {
            // Touching cylinders.
            0 => (FRAC_PI_2, 0.0),
            // An arc alone.
            1 => (rng.range(0.05, FRAC_PI_2 - 0.05), 0.0),
            // Shallow profiles.
            2 => (rng.log_range(-2.0, -0.5), rng.log_range(-2.0, 1.5)),
            _ => (rng.range(0.05, 1.5), rng.log_range(-2.0, 1.5)),
        };
        let (s, v) = (rng.direction(89.0 * DEG), rng.direction(89.0 * DEG));
        let phi_a = rng.range(0.0, PI);
        let (e, excess) = assert_profile_matches_brute_force(
            f,
            theta_a,
            l,
            s,
            v,
            phi_a,
            floor,
            &format!("case {i}"),
        );
        let case = || {
            format!(
                "case {i}: θa {theta_a:?}, L {l:?}, φa {phi_a:?}, s {}, v {}, {:?}",
                sph(s),
                sph(v),
                f.params()
            )
        };
        worst.update(e, case);
        worst_excess.update(excess, case);
    }
    worst.report(&format!(
        "profile vs brute force, σh/τ in {roughness:?}, relative"
    ));
    worst_excess.report(&format!(
        "profile vs brute force, σh/τ in {roughness:?}, relative beyond the sampling bound"
    ));
}

/// One comparison of `profile_brdf` with the brute force (see [`profile_against_brute_force`]);
/// returns the relative error and the relative error beyond the sampling bound.
#[track_caller]
fn assert_profile_matches_brute_force(
    f: &Fiber,
    theta_a: f64,
    l: f64,
    s: Vec3,
    v: Vec3,
    phi_a: f64,
    floor: f64,
    what: &str,
) -> (f64, f64) {
    let profile = Profile::new(theta_a, l).unwrap();
    let y = yarn(f, yarn_params(l, theta_a.min(FRAC_PI_2 - 1e-9), 0.0));
    let got = y.profile_brdf(s, v, phi_a, theta_a);
    let (want, bound) = brute_force_profile(f, &profile, s, v, phi_a);
    let err = (got - want).abs();
    let tol = 1e-3 * want.abs().max(floor) + bound;
    assert!(
        err <= tol,
        "{what}: θa {theta_a:?}, L {l:?}, φa {phi_a:?}, s {}, v {}, {:?}: profile_brdf {got:.9e}, brute force {want:.9e} (sampling bound {bound:.2e}), |err| {err:.2e} > tol {tol:.2e}",
        sph(s),
        sph(v),
        f.params()
    );
    (
        err / want.abs().max(floor),
        (err - bound).max(0.0) / want.abs().max(floor),
    )
}

/// docs/spec.md §2.3, §6.5: Eq. (17) with exact masking equals brute-force ray casting, for fibers
/// of `σ_h/τ ∈ [0.1, 0.25]` (see the ignored test below for rougher ones).
#[test]
fn profile_brdf_matches_brute_force_ray_casting() {
    profile_against_brute_force(60, 0x5EED_0001, (0.1, 0.25), 1e-4);
}

/// The exhaustive version: `cargo test --release -p woven --test integration
/// profile_brdf_matches_brute_force_exhaustive -- --ignored` (about a minute).
#[test]
#[ignore = "exhaustive (about a minute); run with --ignored"]
fn profile_brdf_matches_brute_force_exhaustive() {
    profile_against_brute_force(1500, 0x5EED_0002, (0.1, 0.25), 1e-4);
}

/// Rougher fibers (`σ_h/τ ∈ [0.25, 2]`, all valid): the arc integral of `profile_brdf` reads a
/// piecewise-polynomial interpolant of the facet lobe `g(θ)` (`CrossSection::sample_g`) whose
/// panels are `1.5 ρα` wide with no upper bound and no grading toward the ends of the facing
/// range, where `g` has the Smith factor's and `D_B`'s singularities; for `ρα ≳ 0.3` one panel
/// spans up to the whole facing range and the arc integral is off by up to tens of per cent.
#[test]
fn profile_brdf_matches_brute_force_for_rough_fibers() {
    // Regressions found by the random search below (profile_brdf vs brute force):
    // σh/τ = 2, an arc of half-angle 0.021 at grazing: 2.109e-4 vs 1.291e-3.
    let f = fiber(1.5, 2.0, 0.0, Normalization::None);
    assert_profile_matches_brute_force(
        &f,
        0.02145833642027018,
        0.0,
        Vec3::from_spherical(1.41156291568266790, 0.59488106644787764),
        Vec3::from_spherical(1.53430107799348292, -0.12182122720556456),
        0.7564254843169591,
        1e-6,
        "regression σh/τ 2",
    );
    // σh/τ = 0.5: 1.052e-3 vs 8.544e-4.
    let f = fiber(1.5, 0.5, 0.0, Normalization::None);
    assert_profile_matches_brute_force(
        &f,
        0.27807771517870006,
        0.05146778155303804,
        Vec3::from_spherical(1.41210020615493104, -0.13661357572908561),
        Vec3::from_spherical(1.45068446201606660, -0.76132754151158399),
        1.1569647015465596,
        1e-6,
        "regression σh/τ 0.5",
    );
    // σh/τ = 0.198, a shallow profile, the lobe's tail: 1.9183e-6 vs 1.9356e-6.
    let f = fiber(
        1.6360159906606027,
        0.1984009636218903,
        0.0,
        Normalization::Paper,
    );
    assert_profile_matches_brute_force(
        &f,
        0.0343452451664373,
        0.4972928648426746,
        Vec3::from_spherical(1.35257095281729067, -1.52705777655207986),
        Vec3::from_spherical(1.05815940107283635, 2.91308567005645092),
        2.333133703606361,
        1e-6,
        "regression σh/τ 0.198, tail",
    );
    profile_against_brute_force(200, 0x5EED_0003, (0.1, 2.0), 1e-6);
}

// ---------------------------------------------------------------------------------------------
// 2. Limits of the profile (docs/spec.md §2.1, §2.3)
// ---------------------------------------------------------------------------------------------

/// Checks `f_p → f_fiber(s, v; z)` as `θ_a → 0` for the given `(θ_a, L)` pairs, over random
/// fibers (`σ_h/τ ∈ roughness`, both modes) and directions up to 89°; relative tolerance `tol`
/// (or 1e-9 sr⁻¹ absolutely, the golden tests' floor).
fn flat_limit(cases: usize, seed: u64, shapes: &[(f64, f64)], roughness: (f64, f64), tol: f64) {
    let mut rng = Rng(seed);
    let mut worst = Worst::default();
    let pool = fiber_pool(&mut rng, 10, roughness);
    for i in 0..cases {
        let f = &pool[i % pool.len()];
        let (theta_a, l) = shapes[i % shapes.len()];
        let y = yarn(f, yarn_params(l, theta_a, 0.0));
        let (s, v) = if i % 7 == 0 {
            // Normal incidence and normal viewing.
            (
                Vec3::Z,
                if i % 2 == 0 {
                    Vec3::Z
                } else {
                    rng.direction(89.0 * DEG)
                },
            )
        } else {
            (rng.direction(89.0 * DEG), rng.direction(89.0 * DEG))
        };
        let phi_a = rng.range(0.0, PI);
        let got = y.profile_brdf(s, v, phi_a, theta_a);
        let want = f.eval(s, v);
        let case = || {
            format!(
                "θa {theta_a}, L {l}, φa {phi_a:?}, s {}, v {}, {:?}",
                sph(s),
                sph(v),
                f.params()
            )
        };
        assert_close(got, want, tol, 1e-9, &case());
        worst.update(rel_err(got, want, 1e-3), case);
    }
    worst.report(&format!("flat limit {shapes:?}, relative"));
}

/// docs/spec.md §2.1, §2.3: `θ_a → 0` is the flat fiber surface, `f_p = f_fiber(s, v; z)`: with
/// laterals (whose facets `profile_brdf` evaluates directly), and at `θ_a = L = 0` (period 0,
/// the limit taken exactly); `σ_h/τ ≤ 0.5` (rougher fibers and bare arcs: the ignored test
/// below).
#[test]
fn flat_limit_reproduces_the_fiber_brdf() {
    let shapes = [(0.0, 2.0), (1e-6, 2.0), (0.0, 0.0), (1e-9, 50.0)];
    flat_limit(300, 0x5EED_0101, &shapes, (0.005, 0.5), 1e-6);
}

/// The flat limit of a bare arc (`L = 0`, `θ_a = 1e-6`) and of very rough fibers: the arc's
/// integral is the interpolant of the facet lobe at `θ ≈ 0`, off by per cents for rough fibers
/// (σh/τ 0.5, s = v = z: 4.1388e-3 for 4.2379e-3), by ~1e-3 even for smooth ones, and negative
/// in the tails — the cause of [`profile_brdf_matches_brute_force_for_rough_fibers`].
#[test]
fn flat_limit_of_bare_arcs_and_very_rough_fibers() {
    let f = fiber(1.6, 0.5, 0.0, Normalization::None);
    let y = yarn(&f, yarn_params(0.0, 1e-6, 0.0));
    assert_close(
        y.profile_brdf(Vec3::Z, Vec3::Z, 0.3, 1e-6),
        f.eval(Vec3::Z, Vec3::Z),
        1e-6,
        0.0,
        "regression: s = v = z, σh/τ 0.5",
    );
    // σh/τ 1.57 at grazing, with laterals: −2.43e-8 for 1.75e-12.
    let f = fiber(
        1.3487838498161266,
        1.5695783451177288,
        0.0,
        Normalization::Paper,
    );
    let y = yarn(&f, yarn_params(2.0, 1e-6, 0.0));
    let (s, v) = (
        Vec3::from_spherical(1.54279808724606471, -2.22813662577575400),
        Vec3::from_spherical(1.49042474205474229, -2.90180605100609235),
    );
    assert_close(
        y.profile_brdf(s, v, 1.5213747873600652, 1e-6),
        f.eval(s, v),
        1e-6,
        1e-12,
        "regression: σh/τ 1.57, θa 1e-6, L 2, grazing",
    );
    flat_limit(
        300,
        0x5EED_0103,
        &[(0.0, 2.0), (1e-6, 2.0), (1e-9, 50.0)],
        (0.5, 2.0),
        1e-6,
    );
    // A bare arc of half-width θa differs from the flat surface by O((θa / cos θ)²) — up to
    // ~3e-7 at θa = 1e-5 and 89°, the directions' limit here.
    flat_limit(
        300,
        0x5EED_0102,
        &[(1e-6, 0.0), (1e-5, 0.0)],
        (0.005, 2.0),
        1e-6,
    );
}

/// `M_uu`, `M_ww` of docs/spec.md §2.3: `∫ a_u² dl`, `∫ a_w² dl` over one period.
fn second_moments(theta_a: f64, l: f64) -> (f64, f64) {
    let (st, ct) = theta_a.sin_cos();
    (
        theta_a - st * ct + 2.0 * l * st * st,
        theta_a + st * ct + 2.0 * l * ct * ct,
    )
}

/// The Lambertian part of `f_p`, by linearity: `f_p` of a fiber with diffuse albedo `rho` minus
/// `f_p` of the same fiber without (`normalization = "none"`, so the lobe does not depend on `ρ0`).
struct LambertianPart {
    with: Yarn,
    without: Yarn,
    rho: f64,
}

impl LambertianPart {
    fn new(rho: f64, roughness: f64, l: f64) -> Self {
        let p = yarn_params(l, 0.5, 0.0);
        LambertianPart {
            with: yarn(&fiber(1.5, roughness, rho, Normalization::None), p),
            without: yarn(&fiber(1.5, roughness, 0.0, Normalization::None), p),
            rho,
        }
    }

    fn eval(&self, s: Vec3, v: Vec3, phi_a: f64, theta_a: f64) -> f64 {
        self.with.profile_brdf(s, v, phi_a, theta_a)
            - self.without.profile_brdf(s, v, phi_a, theta_a)
    }
}

/// docs/spec.md §2.3: with nothing masked (`|ψ_s|, |ψ_v| < π/2 − θ_a`) a Lambertian fiber gives
/// `f_p = (ρ/π)(s_u v_u M_uu + s_z v_z M_ww)/(P s_z v_z)` — not `ρ/π`.
#[test]
fn unmasked_lambertian_profile_matches_closed_form() {
    let mut rng = Rng(0x5EED_0201);
    let mut worst = Worst::default();
    let mut cases = 0;
    while cases < 150 {
        let (theta_a, l) = (
            rng.range(0.01, 1.45),
            if rng.chance(0.2) {
                0.0
            } else {
                rng.log_range(-2.0, 1.5)
            },
        );
        let lamb = LambertianPart::new(rng.range(0.1, 0.9), rng.range(0.02, 0.5), l);
        let (s, v) = (rng.direction(89.0 * DEG), rng.direction(89.0 * DEG));
        let phi_a = rng.range(0.0, PI);
        let onset = FRAC_PI_2 - theta_a;
        if psi(s, phi_a).abs() >= onset || psi(v, phi_a).abs() >= onset {
            continue;
        }
        cases += 1;
        let got = lamb.eval(s, v, phi_a, theta_a);
        let e_u = across(phi_a);
        let (m_uu, m_ww) = second_moments(theta_a, l);
        let period = Profile::new(theta_a, l).unwrap().period();
        let want = lamb.rho * FRAC_1_PI * (s.dot(e_u) * v.dot(e_u) * m_uu + s.z * v.z * m_ww)
            / (period * s.z * v.z);
        let case = || {
            format!(
                "θa {theta_a}, L {l}, φa {phi_a}, ρ {}, s {}, v {}",
                lamb.rho,
                sph(s),
                sph(v)
            )
        };
        assert_close(got, want, 1e-7, 1e-13, &case());
        worst.update(rel_err(got, want, 1e-13), case);
        // Light returned to other facets is lost: f_p = ρ/π only in the flat limit.
        if theta_a > 0.3 && (s.dot(e_u) * v.dot(e_u)).abs() > 0.1 {
            assert!(
                (got - lamb.rho * FRAC_1_PI).abs() > 1e-4,
                "{}: f_p {got} is ρ/π",
                case()
            );
        }
    }
    worst.report("unmasked Lambertian closed form, relative");
}

/// Torrance–Sparrow's V-groove lit fraction of the lateral of normal angle `+θ_a` (facing `+u`)
/// lit from projected angle `psi` (docs/spec.md §2.3): whole below the masking onset, the V-groove
/// value `2 cos θ_a cos ψ / cos(ψ − θ_a)` past it on the side facing the light, 0 on the other.
fn v_groove_fraction(theta_a: f64, psi: f64) -> f64 {
    let onset = FRAC_PI_2 - theta_a;
    if psi.abs() <= onset {
        1.0
    } else if psi > 0.0 {
        2.0 * theta_a.cos() * psi.cos() / (psi - theta_a).cos()
    } else {
        0.0
    }
}

/// The Lambertian profile BRDF of V-grooves (`L → ∞`): the lit set of a lateral is the part
/// `[0, F L]` next to the apex, so the lit-and-visible length is `L min(F(ψ_s), F(ψ_v))`, and the
/// arc (of finite length) drops out against the period `P ≈ 2 L cos θ_a`:
/// `f = (ρ/π) Σ_± (s·a_±)(v·a_±) min(F_±(ψ_s), F_±(ψ_v)) / (2 cos θ_a s_z v_z)`,
/// `a_± = ±sin θ_a e_u + cos θ_a z`, `F_−(ψ) = F_+(−ψ)`.
fn v_groove_lambertian(rho: f64, theta_a: f64, s: Vec3, v: Vec3, phi_a: f64) -> f64 {
    let e_u = across(phi_a);
    let (ps, pv) = (psi(s, phi_a), psi(v, phi_a));
    let (st, ct) = theta_a.sin_cos();
    let mut sum = 0.0;
    for sign in [1.0, -1.0] {
        let a = e_u * (sign * st) + Vec3::Z * ct;
        let (sa, va) = (s.dot(a), v.dot(a));
        if sa <= 0.0 || va <= 0.0 {
            continue;
        }
        sum += sa
            * va
            * v_groove_fraction(theta_a, sign * ps).min(v_groove_fraction(theta_a, sign * pv));
    }
    rho * FRAC_1_PI * sum / (2.0 * ct * s.z * v.z)
}

/// docs/spec.md §2.1, §2.3: as `L → ∞` the Lambertian part of `f_p` tends to the V-groove value, with
/// an error `O(1/L)` (the arc and the neighbour's arc in the shadow line are of finite size).
#[test]
fn long_laterals_tend_to_the_v_groove_lambertian_brdf() {
    let mut rng = Rng(0x5EED_0301);
    let mut worst = Worst::default();
    let mut masked_cases = 0;
    for i in 0..40 {
        let theta_a = rng.range(0.2, 1.3);
        let rho = 0.7;
        let (s, v) = (rng.direction(88.0 * DEG), rng.direction(88.0 * DEG));
        let phi_a = rng.range(0.0, PI);
        let onset = FRAC_PI_2 - theta_a;
        if psi(s, phi_a).abs() > onset || psi(v, phi_a).abs() > onset {
            masked_cases += 1;
        }
        let want = v_groove_lambertian(rho, theta_a, s, v, phi_a);
        // The scale of the BRDF, for cases where the V-groove value is 0 (nothing both lit and seen).
        let scale = rho * FRAC_1_PI;
        let mut errs = Vec::new();
        for l in [1e2, 1e3, 1e4, 1e5] {
            let got = LambertianPart::new(rho, 0.2, l).eval(s, v, phi_a, theta_a);
            errs.push((l, got, (got - want).abs() / want.abs().max(scale)));
        }
        let case = || {
            format!("case {i}: θa {theta_a}, φa {phi_a}, s {}, v {}: V-groove {want:.9e}, (L, f_p, rel err) {errs:?}", sph(s), sph(v))
        };
        // O(1/L): the error times L stays bounded (by a few: the arc's length is ≤ π, the
        // shadow line's offset ≤ 2).
        for &(l, _, e) in &errs {
            assert!(e * l <= 20.0, "{}: error × L = {} > 20", case(), e * l);
        }
        let (_, _, e_last) = errs[3];
        assert!(
            e_last <= 2e-4,
            "{}: at L = 1e5 the error {e_last:.2e} > 2e-4",
            case()
        );
        worst.update(e_last, case);
    }
    assert!(masked_cases >= 10, "only {masked_cases} cases with masking");
    worst.report("V-groove limit at L = 1e5, relative");
}

// ---------------------------------------------------------------------------------------------
// 3. Reciprocity in `none` mode (docs/spec.md §2.3, §6.3)
// ---------------------------------------------------------------------------------------------

/// Asserts `f(s, v) = f(v, s)` over random pairs, returning the worst relative asymmetry.
fn assert_reciprocal(
    what: &str,
    rng: &mut Rng,
    pairs: usize,
    tol: f64,
    f: impl Fn(Vec3, Vec3) -> f64,
) -> f64 {
    let mut worst = Worst::default();
    for _ in 0..pairs {
        let (s, v) = (rng.direction(88.0 * DEG), rng.direction(88.0 * DEG));
        let (a, b) = (f(s, v), f(v, s));
        let case = || format!("{what}: s {}, v {}", sph(s), sph(v));
        assert!(a.is_finite() && b.is_finite(), "{}: {a} {b}", case());
        let e = rel_err(a, b, 1e-12);
        assert!(
            e <= tol,
            "{}: f(s, v) = {a:.15e}, f(v, s) = {b:.15e}, relative difference {e:.2e} > tol {tol:.0e}",
            case()
        );
        worst.update(e, case);
    }
    worst.report(&format!("reciprocity, {what}"));
    worst.value
}

/// Reciprocity holds to rounding: the yarn's quadrature break points (masking onsets, highlight,
/// `ψ_s = ±ψ_v`, twist centres) are symmetric in `s` and `v`, so `f(s, v)` and `f(v, s)` sum the
/// same terms (observed ≤ 3e-15 for profile, slope, twist, isotropic and cloth averages).
const RECIPROCITY_TOL: f64 = 1e-12;

/// A random `none`-mode fiber with diffuse albedo.
fn random_none_fiber(rng: &mut Rng) -> Fiber {
    fiber(
        rng.range(1.3, 1.8),
        rng.log_range(-1.7, -0.3),
        rng.range(0.05, 0.5),
        Normalization::None,
    )
}

#[test]
fn profile_is_reciprocal_in_none_mode() {
    let mut rng = Rng(0x5EED_0401);
    for i in 0..12 {
        let f = random_none_fiber(&mut rng);
        let (theta_a, l) = if i == 0 {
            (FRAC_PI_2, 0.0)
        } else {
            (rng.range(0.05, 1.5), rng.log_range(-2.0, 1.5))
        };
        let y = yarn(&f, yarn_params(l, theta_a.min(1.5), 0.0));
        let phi_a = rng.range(0.0, PI);
        assert_reciprocal(
            &format!("profile θa {theta_a}, L {l}, φa {phi_a}, α {}", f.alpha()),
            &mut rng,
            25,
            RECIPROCITY_TOL,
            |s, v| y.profile_brdf(s, v, phi_a, theta_a),
        );
    }
}

#[test]
fn yarn_averages_are_reciprocal_in_none_mode() {
    let mut rng = Rng(0x5EED_0402);
    for i in 0..9 {
        let f = random_none_fiber(&mut rng);
        let mut p = yarn_params(
            rng.log_range(-1.0, 1.3),
            rng.range(0.0, 1.2),
            rng.range(0.2, 1.2),
        );
        p.interreflection = 0.2;
        p.interreflection_albedo = 0.5;
        let what = match i % 3 {
            0 => "slope-averaged",
            1 => {
                p.twist_std = rng.range(0.1, 0.8);
                "twisted"
            }
            _ => {
                p.isotropic = true;
                "isotropic"
            }
        };
        let y = yarn(&f, p);
        let phi = rng.range(0.0, PI);
        let pairs = if i % 3 == 0 { 25 } else { 8 };
        assert_reciprocal(
            &format!("{what} yarn {p:?}, φ {phi}"),
            &mut rng,
            pairs,
            RECIPROCITY_TOL,
            |s, v| {
                if i % 3 == 0 {
                    y.eval_oriented(s, v, phi)
                } else {
                    y.eval(s, v, phi)
                }
            },
        );
    }
}

#[test]
fn cloth_is_reciprocal_in_none_mode() {
    let mut rng = Rng(0x5EED_0403);
    for (i, extra) in ["", "twist_std = 0.3", "isotropic = true"]
        .iter()
        .enumerate()
    {
        let text = format!(
            "[fiber]\neta = 1.55\nroughness = 0.12\ndiffuse = 0.1\nnormalization = \"none\"\n\
             [yarn]\nlateral_length = 3.0\nslope_mean = 0.4\nslope_std = 0.5\n\
             interreflection = 0.2\ninterreflection_albedo = 0.5\n{extra}\n\
             [weave]\nweft_fraction = 0.3\n"
        );
        let model = material(&text).build(WAVELENGTH_NM).unwrap();
        let pairs = if i == 0 { 25 } else { 8 };
        assert_reciprocal(
            &format!("cloth γ = 0.3 {extra:?}"),
            &mut rng,
            pairs,
            RECIPROCITY_TOL,
            |s, v| model.eval(s, v),
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Symmetries
// ---------------------------------------------------------------------------------------------

/// The woven model of a `[yarn]` table (with `extra` lines) and weft fraction `gamma`.
fn cloth_model(roughness: f64, extra: &str, gamma: f64) -> Model {
    material(&format!(
        "[fiber]\neta = 1.6\nroughness = {roughness}\ndiffuse = 0.1\n\
         [yarn]\nlateral_length = 4.0\nslope_mean = 0.5\nslope_std = 0.4\n\
         interreflection = 0.1\ninterreflection_albedo = 0.5\n{extra}\n\
         [weave]\nweft_fraction = {gamma}\n"
    ))
    .build(WAVELENGTH_NM)
    .unwrap()
}

/// Asserts `f(θi, φi, θr, φr) = f(θi, map(φi), θr, map(φr))` over random directions.
fn assert_azimuth_map(
    what: &str,
    rng: &mut Rng,
    pairs: usize,
    tol: f64,
    f: impl Fn(Vec3, Vec3) -> f64,
    g: impl Fn(Vec3, Vec3) -> f64,
    map: impl Fn(f64) -> f64,
) -> f64 {
    let mut worst = Worst::default();
    for _ in 0..pairs {
        let (ti, tr) = (rng.theta(88.0 * DEG), rng.theta(88.0 * DEG));
        let (pi, pr) = (rng.range(0.0, 2.0 * PI), rng.range(0.0, 2.0 * PI));
        let a = f(Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr));
        let b = g(
            Vec3::from_spherical(ti, map(pi)),
            Vec3::from_spherical(tr, map(pr)),
        );
        let e = rel_err(a, b, 1e-12);
        let case = || format!("{what}: θi {ti}, φi {pi}, θr {tr}, φr {pr}");
        assert!(
            e <= tol,
            "{}: {a:.15e} vs mapped {b:.15e}, relative difference {e:.2e} > tol {tol:.0e}",
            case()
        );
        worst.update(e, case);
    }
    worst.report(what);
    worst.value
}

/// A yarn along `x` (`γ = 1`) is symmetric under `y → −y` (`φ → −φ`) and `x → −x` (`φ → π − φ`):
/// the profile is symmetric and the fiber isotropic. The quadrature's break points map onto each
/// other, so the symmetry holds to rounding (observed ≤ 2e-15, with twist too).
#[test]
fn yarn_along_x_is_mirror_symmetric() {
    let mut rng = Rng(0x5EED_0501);
    for (extra, pairs, tol) in [("", 40, 1e-12), ("twist_std = 0.3", 10, 1e-12)] {
        let model = cloth_model(0.1, extra, 1.0);
        let f = |s, v| model.eval(s, v);
        assert_azimuth_map(
            &format!("y → −y {extra:?}"),
            &mut rng,
            pairs,
            tol,
            f,
            f,
            |p| -p,
        );
        assert_azimuth_map(
            &format!("x → −x {extra:?}"),
            &mut rng,
            pairs,
            tol,
            f,
            f,
            |p| PI - p,
        );
    }
}

/// Eq. (23) under the swap `x ↔ y` (`φ → π/2 − φ`): weft and warp trade places, so
/// `f_γ(φi, φr) = f_{1−γ}(π/2 − φi, π/2 − φr)`.
#[test]
fn weave_mix_swaps_weft_and_warp_under_the_diagonal_mirror() {
    let mut rng = Rng(0x5EED_0502);
    let (a, b) = (cloth_model(0.15, "", 0.3), cloth_model(0.15, "", 0.7));
    assert_azimuth_map(
        "x ↔ y, γ 0.3 ↔ 0.7",
        &mut rng,
        30,
        1e-12,
        |s, v| a.eval(s, v),
        |s, v| b.eval(s, v),
        |p| FRAC_PI_2 - p,
    );
}

/// The tolerance of rotation invariance: the azimuth quadrature's panels move with the
/// directions, so invariance holds to its accuracy, ≤ 1e-4 (docs/spec.md §2.4); observed 3.3e-5 at
/// grazing (84°, 86°), ≤ 7e-7 elsewhere.
const ROTATION_TOL: f64 = 1e-4;

/// Isotropic yarns (Eq. (22)) make an isotropic BRDF: invariant under a common rotation of
/// `φi`, `φr`.
#[test]
fn isotropic_yarns_are_rotation_invariant() {
    let mut rng = Rng(0x5EED_0503);
    let silk = preset("silk").build(WAVELENGTH_NM).unwrap();
    let custom = cloth_model(0.05, "isotropic = true", 0.8);
    for (what, model) in [("silk preset", &silk), ("isotropic σh/τ 0.05", &custom)] {
        let f = |s, v| model.eval(s, v);
        for k in 0..3 {
            let delta = rng.range(0.0, 2.0 * PI);
            assert_azimuth_map(
                &format!("{what}, rotation {k} by {delta}"),
                &mut rng,
                6,
                ROTATION_TOL,
                f,
                f,
                |p| p + delta,
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 5. Albedo
// ---------------------------------------------------------------------------------------------

/// `θ_i` and `φ_i` of the albedo checks.
const ALBEDO_THETAS_DEG: [f64; 4] = [0.0, 30.0, 60.0, 80.0];
const ALBEDO_PHIS: [f64; 2] = [0.3, 1.9];

/// Checks `floor ≤ albedo ≤ 1 + slack` at every `(θ_i, φ_i)` of the albedo grid; returns the
/// largest albedo.
fn check_albedo(what: &str, model: &Model, floor: impl Fn(f64) -> f64, slack: f64) -> f64 {
    let mut largest: f64 = 0.0;
    for t in ALBEDO_THETAS_DEG {
        for phi in ALBEDO_PHIS {
            let a = model.albedo(t * DEG, phi);
            let lo = floor(t * DEG);
            assert!(
                a.is_finite() && a <= 1.0 + slack,
                "{what}: albedo at θi {t}°, φi {phi} is {a:.9}, above 1 (+{slack:.0e})"
            );
            assert!(
                a >= lo,
                "{what}: albedo at θi {t}°, φi {phi} is {a:.9}, below the sanity floor {lo:.6}"
            );
            largest = largest.max(a);
            eprintln!("  albedo {what} θi {t} φi {phi}: {a:.6} (floor {lo:.6})");
        }
    }
    eprintln!("albedo {what}: largest {largest:.6}");
    largest
}

/// The slack allowed above 1 for the albedo quadrature (the white-furnace test below shows its
/// error on a flat profile is far smaller).
const ALBEDO_SLACK: f64 = 1e-3;

/// docs/spec.md §6.2: albedo ≤ 1 in `paper` mode for profile-type, yarn and cloth materials; and
/// with unit Fresnel (the white furnace: nothing but masking removes energy) it is still ≤ 1,
/// and exactly 1 for the flat profile. Fibers of `σ_h/τ = 0.1` (narrower lobes: the tests
/// below). The twisted and isotropic presets take about ten minutes on 2 cores, too long for
/// CI: `cargo run --release -p woven --example albedo_bound` checks them.
#[test]
fn albedo_is_at_most_one_in_paper_mode() {
    let profile_type = yarn_params(3.0, 0.8, 0.0);
    let mut yarn_type = yarn_params(2.0, 0.3, 0.6);
    yarn_type.interreflection = 0.2;
    yarn_type.interreflection_albedo = 0.5;
    let flat = yarn_params(5.0, 0.0, 0.0);
    let f = fiber(1.6, 0.1, 0.1, Normalization::Paper);
    let white = f.clone().with_unit_fresnel();
    for (what, params, gamma) in [
        ("profile θa 0.8, L 3", profile_type, 1.0),
        ("yarn L 2, μ 0.3, σ 0.6, ħ 0.2", yarn_type, 0.4),
    ] {
        let m = woven(yarn(&f, params), gamma);
        // Sanity floor, not a bound: masking loses under three quarters of what the flat
        // fiber reflects at these angles (observed ≥ 0.47 of it).
        check_albedo(what, &m, |t| 0.25 * f.albedo(t.cos()), ALBEDO_SLACK);
        let w = woven(yarn(&white, params), gamma);
        // Observed ≥ 0.38 with unit Fresnel.
        check_albedo(&format!("{what}, unit Fresnel"), &w, |_| 0.25, ALBEDO_SLACK);
    }
    // White furnace through the yarn albedo quadrature: a flat profile (θa = 0) with unit
    // Fresnel reflects everything.
    let mut worst = Worst::default();
    for r in [0.1] {
        let w = woven(
            yarn(
                &fiber(1.6, r, 0.1, Normalization::Paper).with_unit_fresnel(),
                flat,
            ),
            0.5,
        );
        for t in ALBEDO_THETAS_DEG {
            for phi in ALBEDO_PHIS {
                let a = w.albedo(t * DEG, phi);
                let what = format!("white furnace, flat profile, σh/τ {r}, θi {t}°, φi {phi}");
                assert_close(a, 1.0, 1e-3, 0.0, &what);
                worst.update((a - 1.0).abs(), || what);
            }
        }
    }
    worst.report("white furnace |albedo − 1|");
    let sateen = preset("polyester-sateen");
    let f = Fiber::new(&sateen.fiber, WAVELENGTH_NM).unwrap();
    let model = sateen.build(WAVELENGTH_NM).unwrap();
    check_albedo(
        "polyester-sateen",
        &model,
        |t| 0.25 * f.albedo(t.cos()),
        ALBEDO_SLACK,
    );
}

/// `∫ f_θ(s, v; φ_a) cos θ_r dω_r` by nested adaptive quadrature (independent of `Model::albedo`'s
/// panels), in the coordinates `v = cos χ e_f + sin χ (cos ω e_u + sin ω z)` around the fiber axis
/// (`dω_r = sin χ dχ dω`): every facet's reflection keeps `v·e_f = −s·e_f`, so the lobe is a ridge
/// at `χ₀ = acos(−s·e_f)`; in `ω` it peaks at the facets' in-plane mirror directions
/// `ω = π/2 − ψ_v`, `ψ_v = 2θ_n − ψ_s`, for the arc top and both laterals.
fn oriented_albedo_adaptive(y: &Yarn, s: Vec3, phi_a: f64, lateral: Option<f64>) -> f64 {
    let e_u = across(phi_a);
    let e_f = Vec3::new(e_u.y, -e_u.x, 0.0);
    let chi0 = (-s.dot(e_f)).clamp(-1.0, 1.0).acos();
    let psi_s = psi(s, phi_a);
    let w = y.fiber().alpha();
    let mut omega_breaks = vec![FRAC_PI_2 + psi_s];
    if let Some(t) = lateral {
        omega_breaks.extend([
            FRAC_PI_2 - (2.0 * t - psi_s),
            FRAC_PI_2 - (-2.0 * t - psi_s),
        ]);
    }
    let chi_breaks: Vec<f64> = [-8.0, -4.0, -2.0, -1.0, 0.0, 1.0, 2.0, 4.0, 8.0]
        .iter()
        .map(|k| chi0 + k * w)
        .collect();
    integrate_split(0.0, PI, &chi_breaks, 1e-6, |chi| {
        let (sc, cc) = chi.sin_cos();
        sc * integrate_split(0.0, PI, &omega_breaks, 1e-6, |om| {
            let (so, co) = om.sin_cos();
            let v = e_f * cc + (e_u * co + Vec3::Z * so) * sc;
            if v.z <= 0.0 {
                return 0.0;
            }
            y.slope_averaged(s, v, phi_a) * v.z
        })
    })
}

/// A narrow lobe (`σ_h/τ = 0.02`) on a profile with laterals: `Model::albedo` is 1.406 for a
/// unit-Fresnel fiber at θi 80°, φi 1.9 — more light out than in — where the adaptive integral
/// gives 0.9826; at θi 30° it is 0.551 for 0.621; a flat profile's white furnace is 1.0019. `albedo.rs` `oriented_albedo` integrates `ω`
/// with one 16-point rule on each side of the arc's mirror direction only, and the laterals'
/// highlights (at `ω = π/2 − (±2θ_a − ψ_s)`, width `~α`) fall between its nodes.
#[test]
fn albedo_of_narrow_lobes_matches_adaptive_quadrature() {
    let f = fiber(1.6, 0.02, 0.1, Normalization::Paper).with_unit_fresnel();
    let y = yarn(&f, yarn_params(3.0, 0.8, 0.0));
    let m = woven(y.clone(), 1.0);
    for (t, phi_i) in [(80.0, 1.9), (30.0, 1.9)] {
        let s = Vec3::from_spherical(t * DEG, phi_i);
        let want = oriented_albedo_adaptive(&y, s, 0.0, Some(0.8));
        let got = m.albedo(t * DEG, phi_i);
        let what = format!("unit-Fresnel profile θa 0.8, L 3, σh/τ 0.02, θi {t}°, φi {phi_i}");
        assert!(
            got <= 1.0 + ALBEDO_SLACK,
            "{what}: albedo {got} > 1 (adaptive {want})"
        );
        assert_close(got, want, 1e-2, 0.0, &what);
    }
}

/// `Model::albedo` against a crude, independent hemisphere quadrature of `Model::eval`:
/// Gauss–Legendre on panels in `cos θ_r` and `φ_r`, `∫∫ f(s, v) cos θ_r d(cos θ_r) dφ_r`.
#[test]
fn albedo_matches_an_independent_hemisphere_quadrature() {
    let text = "[fiber]\neta = 1.6\nroughness = 0.2\ndiffuse = 0.1\n\
                [yarn]\nlateral_length = 3.0\nslope_mean = 0.4\nslope_std = 0.5\n\
                interreflection = 0.2\ninterreflection_albedo = 0.5\n\
                [weave]\nweft_fraction = 0.3\n";
    let model = material(text).build(WAVELENGTH_NM).unwrap();
    let gl = GaussLegendre::new(8);
    for (t, phi_i) in [(40.0, 0.7), (75.0, 2.0)] {
        let s = Vec3::from_spherical(t * DEG, phi_i);
        let (n_mu, n_phi) = (12, 24);
        let mut total = 0.0;
        for i in 0..n_mu {
            let (m0, m1) = (i as f64 / n_mu as f64, (i + 1) as f64 / n_mu as f64);
            total += gl.integrate(m0, m1, |mu| {
                let sin = (1.0 - mu * mu).max(0.0).sqrt();
                let mut ring = 0.0;
                for j in 0..n_phi {
                    let (p0, p1) = (
                        2.0 * PI * j as f64 / n_phi as f64,
                        2.0 * PI * (j + 1) as f64 / n_phi as f64,
                    );
                    ring += gl.integrate(p0, p1, |p| {
                        model.eval(s, Vec3::new(sin * p.cos(), sin * p.sin(), mu))
                    });
                }
                ring * mu
            });
        }
        let got = model.albedo(t * DEG, phi_i);
        eprintln!("albedo at θi {t}°, φi {phi_i}: Model::albedo {got:.6}, grid {total:.6}");
        assert_close(
            got,
            total,
            1e-2,
            0.0,
            &format!("Model::albedo vs hemisphere grid, θi {t}°, φi {phi_i}"),
        );
    }
}

/// `Model::albedo` of a single profile with laterals at `σ_h/τ = 0.1` against the adaptive
/// integral of [`oriented_albedo_adaptive`] (observed agreement 4e-4).
#[test]
fn profile_albedo_matches_adaptive_quadrature() {
    let f = fiber(1.6, 0.1, 0.1, Normalization::Paper).with_unit_fresnel();
    let y = yarn(&f, yarn_params(3.0, 0.8, 0.0));
    let m = woven(y.clone(), 1.0);
    let (t, phi_i) = (80.0, 1.9);
    let s = Vec3::from_spherical(t * DEG, phi_i);
    let want = oriented_albedo_adaptive(&y, s, 0.0, Some(0.8));
    let got = m.albedo(t * DEG, phi_i);
    eprintln!("profile albedo at θi {t}°, φi {phi_i}: Model::albedo {got:.6}, adaptive {want:.6}");
    assert_close(
        got,
        want,
        1e-2,
        0.0,
        &format!("unit-Fresnel profile θa 0.8, L 3, σh/τ 0.1, θi {t}°, φi {phi_i}"),
    );
}

// ---------------------------------------------------------------------------------------------
// 6. Convergence of the yarn averages (docs/spec.md §2.4: ≤ 1e-4 relative)
// ---------------------------------------------------------------------------------------------

/// Relative tolerance of every average (docs/spec.md §2.4); values below `CONVERGENCE_FLOOR` sr⁻¹
/// compare absolutely against `CONVERGENCE_TOL × CONVERGENCE_FLOOR`.
const CONVERGENCE_TOL: f64 = 1e-4;
const CONVERGENCE_FLOOR: f64 = 1e-6;

/// The belt cloth with narrow slope and twist spreads (the `±8σ` windows of `yarn::NARROW_STD`),
/// and silk with a narrow slope spread.
fn narrow_materials() -> Vec<(String, Material)> {
    let mut belt = preset("belt-cloth");
    let y = belt.yarn.as_mut().unwrap();
    (y.slope_std, y.twist_std) = (0.02, 0.03);
    let mut silk = preset("silk");
    silk.yarn.as_mut().unwrap().slope_std = 0.01;
    vec![
        ("belt-cloth, σ 0.02, σ_t 0.03".to_string(), belt),
        ("silk, σ 0.01".to_string(), silk),
    ]
}

/// The presets and the `cloth-*` golden materials.
fn convergence_materials() -> Vec<(String, Material)> {
    let mut out: Vec<(String, Material)> = Material::preset_names()
        .iter()
        .map(|n| (n.to_string(), preset(n)))
        .collect();
    let root = &vector_roots()[0];
    for set in ["cloth-isotropic", "cloth-twisted-twill", "cloth-warp-faced"] {
        let m = Material::from_path(root.join(set).join("material.toml"))
            .unwrap_or_else(|e| panic!("{set}: {e}"));
        out.push((set.to_string(), m));
    }
    out
}

/// Compares the default `Quadrature` with doubled orders for every material of
/// [`convergence_materials`] at `pairs` random direction pairs (polar angles up to `max_theta`,
/// half of them in the plane of incidence); asserts ≤ 1e-4 relative (docs/spec.md §2.4).
fn default_vs_doubled(pairs: usize, seed: u64, max_theta: f64) {
    let q = Quadrature::default();
    let doubled = Quadrature {
        slope_nodes: 2 * q.slope_nodes,
        azimuth_nodes: 2 * q.azimuth_nodes,
        azimuth_nodes_grazing: 2 * q.azimuth_nodes_grazing,
    };
    let mut rng = Rng(seed);
    let mut overall = Worst::default();
    for (name, m) in convergence_materials() {
        let f = Fiber::new(&m.fiber, WAVELENGTH_NM).unwrap();
        let (default, fine) = (build_with(&f, &m, None), build_with(&f, &m, Some(doubled)));
        let mut worst = Worst::default();
        for k in 0..pairs {
            let (ti, tr) = (rng.theta(max_theta), rng.theta(max_theta));
            let pi = rng.range(0.0, 2.0 * PI);
            let pr = if k % 2 == 0 {
                pi + PI
            } else {
                rng.range(0.0, 2.0 * PI)
            };
            let (s, v) = (Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr));
            let (a, b) = (default.eval(s, v), fine.eval(s, v));
            let e = rel_err(a, b, CONVERGENCE_FLOOR);
            let case = || format!("{name}: θi {ti:?}, φi {pi:?}, θr {tr:?}, φr {pr:?}");
            assert!(
                e <= CONVERGENCE_TOL,
                "{}: default {a:.12e}, doubled {b:.12e}, relative difference {e:.2e} > {CONVERGENCE_TOL:.0e}",
                case()
            );
            worst.update(e, case);
            overall.update(e, case);
        }
        worst.report(&format!(
            "default vs doubled quadrature up to {:.0}°, {name}",
            max_theta / DEG
        ));
    }
    overall.report(&format!(
        "default vs doubled quadrature up to {:.0}°, all materials",
        max_theta / DEG
    ));
}

/// docs/spec.md §2.4: the default `Quadrature` agrees with doubled orders to ≤ 1e-4 relative for the
/// presets and the golden cloth materials, at 20 direction pairs each up to 80° (observed:
/// ≤ 1e-5). Beyond 80° see the ignored test below.
#[test]
fn default_quadrature_is_converged() {
    default_vs_doubled(20, 0x5EED_0601, 80.0 * DEG);
}

/// The same up to 88°: the twisted and isotropic averages miss 1e-4 at grazing (belt-cloth
/// 2.7e-4, cloth-isotropic 1.8e-4, silk 1.5e-4 over 150 pairs; e.g. belt-cloth at θi 85.3°,
/// θr 84.7° in the plane of incidence: default 0.780620, converged 0.780516, 1.04e-4 off):
/// the azimuth rule of `Yarn::azimuth_integral` (6 nodes per panel) is too coarse there.
#[test]
fn default_quadrature_is_converged_at_grazing() {
    let m = preset("belt-cloth");
    let f = Fiber::new(&m.fiber, WAVELENGTH_NM).unwrap();
    let (s, v) = (
        Vec3::from_spherical(1.489476677096598, 0.8515724029995233),
        Vec3::from_spherical(1.4793462993817148, 3.9931650565893166),
    );
    let got = build_with(&f, &m, None).eval(s, v);
    // Converged value: slope 48, azimuth 48 nodes per panel; adaptive over the twist gives
    // 0.7805158340.
    let want = build_with(
        &f,
        &m,
        Some(Quadrature {
            slope_nodes: 48,
            azimuth_nodes: 48,
            azimuth_nodes_grazing: 48,
        }),
    )
    .eval(s, v);
    assert_close(
        got,
        want,
        CONVERGENCE_TOL,
        0.0,
        "regression: belt-cloth at 85°",
    );
    default_vs_doubled(40, 0x5EED_0603, 88.0 * DEG);
}

/// `P(θ_a) = c exp(−(θ_a − μ)²/(2σ²)) cos θ_a` on `[0, π/2]` (Eq. (19)), normalized here by
/// adaptive quadrature, independently of the library's `SlopeDistribution`.
fn slope_density(mu: f64, sigma: f64) -> impl Fn(f64) -> f64 {
    let shape = move |t: f64| (-(t - mu) * (t - mu) / (2.0 * sigma * sigma)).exp() * t.cos();
    let z =
        adaptive(0.0, mu, 1e-12, 0.0, 40, shape) + adaptive(mu, FRAC_PI_2, 1e-12, 0.0, 40, shape);
    move |t| shape(t) / z
}

/// `∫ g` over `[a, b]` split at `breaks` (those inside), each part adaptive to `rel_tol`.
fn integrate_split(a: f64, b: f64, breaks: &[f64], rel_tol: f64, g: impl Fn(f64) -> f64) -> f64 {
    let mut edges: Vec<f64> = breaks.iter().copied().filter(|&x| x > a && x < b).collect();
    edges.push(a);
    edges.push(b);
    edges.sort_by(f64::total_cmp);
    edges
        .windows(2)
        .map(|e| adaptive(e[0], e[1], rel_tol, 1e-14, 30, &g))
        .sum()
}

/// docs/spec.md §2.4, §2.6: the slope, twist and isotropic averages (also of narrow spreads) agree with independent adaptive
/// quadratures of the quantity they average (`profile_brdf` over `θ_a`; `eval_oriented` over the
/// fiber azimuth) to ≤ 1e-4 relative — a check doubling the orders cannot make (a panel rule with
/// a missed kink converges slowly, but to the right value).
#[test]
fn yarn_averages_match_independent_adaptive_quadrature() {
    let mut rng = Rng(0x5EED_0602);
    let mut worst = Worst::default();
    for (name, m) in convergence_materials()
        .into_iter()
        .chain(narrow_materials())
    {
        let f = Fiber::new(&m.fiber, WAVELENGTH_NM).unwrap();
        let p = m.yarn.unwrap();
        let y = yarn(&f, p);
        for k in 0..4 {
            let (ti, tr) = (rng.theta(88.0 * DEG), rng.theta(88.0 * DEG));
            let pi = rng.range(0.0, 2.0 * PI);
            let pr = if k % 2 == 0 {
                pi + PI
            } else {
                rng.range(0.0, 2.0 * PI)
            };
            let (s, v) = (Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr));
            let phi = rng.range(0.0, PI);
            let case =
                |what: &str| format!("{name}, {what}: θi {ti}, φi {pi}, θr {tr}, φr {pr}, φ {phi}");
            // Slope average (Eq. (18)) at one fiber azimuth.
            let density = slope_density(p.slope_mean, p.slope_std);
            let onsets = [
                FRAC_PI_2 - psi(s, phi).abs(),
                FRAC_PI_2 - psi(v, phi).abs(),
                p.slope_mean,
            ];
            let top = FRAC_PI_2 * (1.0 - 1e-12);
            let want = integrate_split(0.0, top, &onsets, 1e-9, |t| {
                density(t) * y.profile_brdf(s, v, phi, t)
            });
            let got = y.slope_averaged(s, v, phi);
            let e = rel_err(got, want, CONVERGENCE_FLOOR);
            assert!(
                e <= CONVERGENCE_TOL,
                "{}: slope_averaged {got:.12e}, adaptive {want:.12e}, relative {e:.2e} > {CONVERGENCE_TOL:.0e}",
                case("slope average")
            );
            worst.update(e, || case("slope average"));
            // The twist (Eq. (21)) or isotropic (Eq. (22)) average about the yarn axis φ.
            if y.is_single_orientation() {
                continue;
            }
            let oriented = |phi_a: f64| y.eval_oriented(s, v, phi_a);
            let want = if p.isotropic {
                integrate_split(0.0, PI, &[], 1e-9, oriented) / PI
            } else {
                let st = p.twist_std;
                let w = |d: f64| (-d * d / (2.0 * st * st)).exp();
                let breaks = [-2.0 * st, -st, 0.0, st, 2.0 * st];
                integrate_split(-FRAC_PI_2, FRAC_PI_2, &breaks, 1e-9, |d| {
                    w(d) * oriented(phi + d)
                }) / integrate_split(-FRAC_PI_2, FRAC_PI_2, &breaks, 1e-12, w)
            };
            let got = y.eval(s, v, phi);
            let e = rel_err(got, want, CONVERGENCE_FLOOR);
            let what = if p.isotropic {
                "isotropic average"
            } else {
                "twist average"
            };
            assert!(
                e <= CONVERGENCE_TOL,
                "{}: eval {got:.12e}, adaptive {want:.12e}, relative {e:.2e} > {CONVERGENCE_TOL:.0e}",
                case(what)
            );
            worst.update(e, || case(what));
        }
    }
    worst.report("yarn averages vs adaptive quadrature");
}

// ---------------------------------------------------------------------------------------------
// 7. Non-negativity and finiteness (docs/spec.md §6.1)
// ---------------------------------------------------------------------------------------------

/// A random valid fiber: rough or (a quarter) full model, any roughness, index, diffuse albedo
/// and mode.
fn random_fiber_params(rng: &mut Rng, roughness: (f64, f64)) -> FiberParams {
    let roughness = rng.log_range(roughness.0.log10(), roughness.1.log10());
    let model = if rng.chance(0.25) {
        let r = roughness;
        let sigma_h_um = rng.log_range(-1.3, 0.0);
        FiberModel::Htsg {
            sigma_h_um,
            // τ clamped to its valid range (≤ 100 µm); the ratio then grows slightly.
            tau_um: (sigma_h_um / r).min(100.0),
        }
    } else {
        FiberModel::Rough { roughness }
    };
    FiberParams {
        model,
        eta: Ior::Constant(rng.range(1.0, 2.5)),
        diffuse: if rng.chance(0.2) {
            0.0
        } else {
            rng.range(0.0, 0.99)
        },
        normalization: if rng.chance(0.5) {
            Normalization::None
        } else {
            Normalization::Paper
        },
        body_gloss: 0.0,
        body_roughness: 0.0,
    }
}

/// Random valid yarn parameters, weighted toward the corners (`L = 0`, huge `L`, `μ` = 0 or
/// near π/2, one slope, tiny and huge spreads).
fn random_yarn_params(rng: &mut Rng) -> YarnParams {
    let lateral_length = match rng.uniform() {
        r if r < 0.2 => 0.0,
        r if r < 0.3 => rng.log_range(2.0, 4.0),
        _ => rng.log_range(-3.0, 2.0),
    };
    let slope_std = if rng.chance(0.3) {
        0.0
    } else {
        rng.log_range(-2.0, 0.5)
    };
    let top = if lateral_length > 0.0 && slope_std == 0.0 {
        FRAC_PI_2 - 1e-6
    } else {
        FRAC_PI_2
    };
    let slope_mean = match rng.uniform() {
        r if r < 0.15 => 0.0,
        r if r < 0.3 => top,
        _ => rng.range(0.0, top),
    };
    let (twist_std, isotropic) = match rng.uniform() {
        r if r < 0.4 => (0.0, false),
        r if r < 0.7 => (rng.log_range(-2.0, 0.5), false),
        _ => (0.0, true),
    };
    YarnParams {
        lateral_length,
        slope_mean,
        slope_std,
        interreflection: rng.uniform(),
        interreflection_albedo: rng.uniform(),
        twist_std,
        isotropic,
        ..YarnParams::default()
    }
}

/// Polar angles that stress the formulas: normal, grazing to within `horizon` of π/2, and random.
fn stress_theta(rng: &mut Rng, horizon: f64) -> f64 {
    // 1e-16: the closest a polar angle below π/2 comes to it in double precision.
    let closest = horizon.max(1e-16).log10();
    match rng.next_u64() % 6 {
        0 => 0.0,
        1 => FRAC_PI_2 - horizon,
        2 => FRAC_PI_2 - rng.log_range(closest, -2.0),
        _ => rng.range(0.0, FRAC_PI_2 - horizon),
    }
}

/// Evaluates the cloth, profile, slope-averaged and oriented BRDFs of `materials` random yarns
/// at `pairs` random direction pairs each (polar angles up to `π/2 − horizon`); returns every
/// value that is negative or not finite, described.
fn nonnegative_and_finite(
    materials: usize,
    pairs: usize,
    seed: u64,
    roughness: (f64, f64),
    horizon: f64,
) -> Vec<String> {
    let mut rng = Rng(seed);
    let mut bad = Vec::new();
    for i in 0..materials {
        let fp = random_fiber_params(&mut rng, roughness);
        let yp = random_yarn_params(&mut rng);
        let gamma = rng.uniform();
        let f = Fiber::new(&fp, WAVELENGTH_NM).unwrap_or_else(|e| panic!("{fp:?}: {e}"));
        let y = yarn(&f, yp);
        let model = woven(y.clone(), gamma);
        for _ in 0..pairs {
            let (ti, tr) = (
                stress_theta(&mut rng, horizon),
                stress_theta(&mut rng, horizon),
            );
            let (pi, pr) = (rng.range(0.0, 2.0 * PI), rng.range(0.0, 2.0 * PI));
            let (s, v) = (Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr));
            let phi_a = rng.range(0.0, PI);
            let theta_a = if yp.lateral_length > 0.0 {
                rng.range(0.0, FRAC_PI_2 - 1e-9)
            } else {
                rng.range(0.0, FRAC_PI_2)
            };
            for (what, x) in [
                ("cloth eval", model.eval(s, v)),
                ("profile_brdf", y.profile_brdf(s, v, phi_a, theta_a)),
                ("slope_averaged", y.slope_averaged(s, v, phi_a)),
                ("eval_oriented", y.eval_oriented(s, v, phi_a)),
            ] {
                if !(x.is_finite() && x >= 0.0) {
                    bad.push(format!(
                        "material {i} {fp:?} {yp:?} γ {gamma}: {what} = {x:e} at θi {ti:?}, φi {pi:?}, θr {tr:?}, φr {pr:?}, φa {phi_a:?}, θa {theta_a:?}"
                    ));
                }
            }
            // Below the horizon the BRDF is 0 (docs/spec.md §0).
            let below = Vec3::new(v.x, v.y, -v.z.max(1e-3));
            assert_eq!(
                model.eval(s, below),
                0.0,
                "material {i}: viewer below the surface"
            );
            assert_eq!(
                model.eval(below, v),
                0.0,
                "material {i}: light below the surface"
            );
        }
    }
    bad
}

/// docs/spec.md §6.1 (finiteness): every yarn and cloth BRDF is finite for random valid yarns and
/// directions, including `θ = 0`, grazing and `θ = π/2` exactly (whose cosine is 6e-17 > 0).
/// Non-negativity is the ignored test below: it fails today.
#[test]
fn yarn_and_cloth_brdfs_are_finite() {
    let bad = nonnegative_and_finite(16, 12, 0x5EED_0701, (0.005, 2.0), 0.0);
    let not_finite: Vec<&String> = bad.iter().filter(|b| !b.contains(" = -")).collect();
    assert!(
        not_finite.is_empty(),
        "{} values not finite, e.g.\n{}",
        not_finite.len(),
        not_finite[0]
    );
}

/// docs/spec.md §6.1: `f ≥ 0` for random valid yarns and directions. Fails today, for the reasons of
/// [`profile_brdf_matches_brute_force_for_rough_fibers`], amplified near the horizon:
/// - the arc integral reads the interpolant of the facet lobe `g(θ)`
///   (`CrossSection::sample_g`), which oscillates below 0 where `g` is tiny (tails of the lobe:
///   values like −1e-13 or −4.6e-8 where the brute force gives 1e-26);
/// - `f_p` divides that integral by `P s_z v_z`, so near the horizon the interpolant's absolute
///   error is multiplied by `1/(s_z v_z)`; and `Profile::lit` takes `ψ` as an angle, whose
///   `cos ψ ≈ π/2 − ψ` has only absolute precision 1e-16, so the lit arc width
///   `2 asin √(P cos ψ / 2)` is wrong by O(1) once `s_z ≲ 1e-12` (θ = π/2 exactly: cloth −0.15;
///   θ ≈ 89.8° with a very rough fiber: −0.92; θ within 1e-9 of π/2: −8.6e5).
#[test]
fn yarn_and_cloth_brdfs_are_nonnegative() {
    // Regression: θi = π/2 exactly, a twisted yarn of near-touching cylinders; cloth eval −0.15.
    let fp = FiberParams {
        model: FiberModel::Rough {
            roughness: 0.5344735382600384,
        },
        eta: Ior::Constant(1.6885531440180523),
        diffuse: 0.9250524258154802,
        normalization: Normalization::Paper,
        body_gloss: 0.0,
        body_roughness: 0.0,
    };
    let yp = YarnParams {
        lateral_length: 0.0,
        slope_mean: FRAC_PI_2,
        slope_std: 0.02036830709730344,
        interreflection: 0.2071353742787474,
        interreflection_albedo: 0.3775892176493678,
        twist_std: 0.5401045400417757,
        isotropic: false,
        ..YarnParams::default()
    };
    let m = woven(
        yarn(&Fiber::new(&fp, WAVELENGTH_NM).unwrap(), yp),
        0.3476111141411742,
    );
    let (s, v) = (
        Vec3::from_spherical(FRAC_PI_2, 3.289257778446746),
        Vec3::from_spherical(0.8892970726149731, 2.121062594076373),
    );
    let x = m.eval(s, v);
    // The limit θi → π/2 is ~0.26 (e.g. 0.2600928 at 1e-4 from the horizon).
    assert!(x >= 0.0, "regression θi = π/2: cloth eval {x}");
    // Regression: a very rough full-model fiber at θ ≈ 89.8°; cloth eval −0.918.
    let fp = FiberParams {
        model: FiberModel::Htsg {
            sigma_h_um: 0.6933307164806257,
            tau_um: 0.8147079675559165,
        },
        eta: Ior::Constant(1.1626368959305258),
        diffuse: 0.6459733184799219,
        normalization: Normalization::Paper,
        body_gloss: 0.0,
        body_roughness: 0.0,
    };
    let yp = YarnParams {
        lateral_length: 0.007047398876471274,
        slope_mean: 0.0,
        slope_std: 0.010993531687504162,
        interreflection: 0.18667833372942966,
        interreflection_albedo: 0.37706650092326244,
        twist_std: 0.0,
        isotropic: false,
        ..YarnParams::default()
    };
    let m = woven(
        yarn(&Fiber::new(&fp, WAVELENGTH_NM).unwrap(), yp),
        0.21218045826706766,
    );
    let (s, v) = (
        Vec3::from_spherical(1.567260664901779, 2.76086595079027),
        Vec3::from_spherical(1.5697963267948967, 3.9891283559997084),
    );
    let x = m.eval(s, v);
    assert!(x >= 0.0, "regression θ ≈ 89.8°, htsg: cloth eval {x}");
    // Regression: the tail of a σh/τ = 0.1 lobe on a bare arc; profile −7.2e-9.
    let f = fiber(1.5, 0.1, 0.0, Normalization::None);
    let y = yarn(&f, yarn_params(0.0, 1e-6, 0.0));
    let (s, v) = (
        Vec3::from_spherical(1.14045220428137206, -0.72218600599549387),
        Vec3::from_spherical(1.46628279814291496, 2.98459275492543030),
    );
    let x = y.eval_oriented(s, v, 2.714431203519856);
    assert!(
        x >= 0.0,
        "regression: bare arc, σh/τ 0.1: {x:e} (fiber {:e})",
        f.eval(s, v)
    );
    // The random search.
    let bad = nonnegative_and_finite(60, 30, 0x5EED_0702, (0.005, 2.0), 0.0);
    assert!(
        bad.is_empty(),
        "{} negative or non-finite values, e.g.\n{}",
        bad.len(),
        bad.iter().take(5).cloned().collect::<Vec<_>>().join("\n")
    );
}

// ---------------------------------------------------------------------------------------------
// 8. Presets (docs/spec.md §5) and material round trips
// ---------------------------------------------------------------------------------------------

fn rough_roughness(m: &Material) -> f64 {
    match m.fiber.model {
        FiberModel::Rough { roughness } => roughness,
        other => panic!("{:?}: not the rough model: {other:?}", m.name),
    }
}

/// docs/spec.md §5: every preset parses and builds, and carries the values the paper gives.
#[test]
fn presets_carry_the_papers_values() {
    let names = Material::preset_names();
    assert_eq!(
        names,
        ["polyester-sateen", "belt-cloth", "silk", "filament-satin"]
    );
    assert_eq!(Material::paper_preset_names(), &names[..3]);
    for name in names {
        let m = preset(name);
        assert_eq!(m.name.as_deref(), Some(*name));
        assert_eq!(
            m.fiber.normalization,
            Normalization::Paper,
            "{name}: reproduces the paper"
        );
        let model = m
            .build(WAVELENGTH_NM)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let (s, v) = (
            Vec3::from_spherical(0.6, 0.2),
            Vec3::from_spherical(0.5, 0.2 + PI),
        );
        let x = model.eval(s, v);
        assert!(x.is_finite() && x > 0.0, "{name}: f = {x}");
        // The text of the preset is what Material::preset parses.
        let text = Material::preset_toml(name).unwrap();
        assert_eq!(material(text), m, "{name}");
        assert!(Material::from_preset_or_path(name).unwrap() == m, "{name}");
    }
    assert!(Material::preset("denim").is_err());

    // Polyester sateen (Fig. 8): σh/τ = 0.05, L = 20, μ = 0, σ = 1.2, one orientation,
    // warp-faced (γ = 0: the visible yarn runs along y).
    let sateen = preset("polyester-sateen");
    let y = sateen.yarn.unwrap();
    assert_eq!(rough_roughness(&sateen), 0.05);
    assert_eq!(
        (y.lateral_length, y.slope_mean, y.slope_std),
        (20.0, 0.0, 1.2)
    );
    assert_eq!((y.twist_std, y.isotropic), (0.0, false));
    assert_eq!(sateen.weft_fraction(), 0.0);
    // Belt cloth (Fig. 9): σh/τ = 0.2, twisted fibers (Eq. (21)).
    let belt = preset("belt-cloth");
    let y = belt.yarn.unwrap();
    assert_eq!(rough_roughness(&belt), 0.2);
    assert!(y.twist_std > 0.0 && !y.isotropic, "{y:?}");
    // Silk (Fig. 10): isotropic yarns (Eq. (22)) with a slope deviation (docs/spec.md §2.6).
    let silk = preset("silk");
    let y = silk.yarn.unwrap();
    assert!(
        y.isotropic && y.twist_std == 0.0 && y.slope_std > 0.0,
        "{y:?}"
    );
    // The filament satin (not the paper's): smoother fibres and narrower slopes than the
    // sateen, untwisted, in a warp-faced 5-end satin.
    let satin = preset("filament-satin");
    let y = satin.yarn.unwrap();
    assert!(
        rough_roughness(&satin) < rough_roughness(&sateen),
        "{satin:?}"
    );
    assert!(
        y.slope_std < 0.5 && y.twist_std == 0.0 && !y.isotropic,
        "{y:?}"
    );
    assert_eq!(satin.weft_fraction(), 0.2);
}

/// docs/spec.md §5 on Fig. 8: for the warp-faced sateen, light and sensor in the warp plane (along
/// the visible yarns, `φ = π/2`) see no masking — the yarns' cross-section sees both directions
/// at `ψ = 0` — while in the weft plane (across them, `φ = 0`) masking is strong. Measured as the
/// lit-and-visible fraction of the profile's length, averaged over the preset's slope
/// distribution, in the specular geometry at 70°.
#[test]
fn sateen_masks_across_the_warp_and_not_along_it() {
    let sateen = preset("polyester-sateen");
    let p = sateen.yarn.unwrap();
    assert_eq!(
        sateen.weft_fraction(),
        0.0,
        "warp-faced: the visible yarns run along y"
    );
    // Warp yarns: fibers along y, φ_a = π/2, e_u = −x.
    let phi_a = FRAC_PI_2;
    let density = slope_density(p.slope_mean, p.slope_std);
    let mut fractions = Vec::new();
    for phi in [FRAC_PI_2, 0.0] {
        let s = Vec3::from_spherical(70.0 * DEG, phi);
        let v = Vec3::from_spherical(70.0 * DEG, phi + PI);
        let (ps, pv) = (psi(s, phi_a), psi(v, phi_a));
        let fraction = |theta_a: f64| {
            let profile = Profile::new(theta_a, p.lateral_length).unwrap();
            let lv = profile.lit_and_visible(ps, pv);
            let total: f64 = Piece::ALL.iter().map(|&q| profile.piece_length(q)).sum();
            let seen: f64 = Piece::ALL.iter().map(|&q| lv.length(q)).sum();
            seen / total
        };
        let onsets = [FRAC_PI_2 - ps.abs(), FRAC_PI_2 - pv.abs()];
        let top = FRAC_PI_2 * (1.0 - 1e-12);
        fractions.push(integrate_split(1e-9, top, &onsets, 1e-9, |t| {
            density(t) * fraction(t)
        }));
    }
    let (warp, weft) = (fractions[0], fractions[1]);
    eprintln!("sateen lit-and-visible fraction at 70°: warp plane {warp:.6}, weft plane {weft:.6}");
    assert_close(warp, 1.0, 1e-7, 0.0, "warp plane: everything lit and seen");
    assert!(
        weft < 0.5,
        "weft plane at 70°: lit-and-visible fraction {weft}, want strong masking"
    );
}

/// `to_toml_string` → `from_toml_str` gives the material back, for the presets and for every
/// kind of `[yarn]` and `[weave]` table.
#[test]
fn materials_round_trip_through_toml() {
    let mut texts: Vec<String> = Material::preset_names()
        .iter()
        .map(|n| Material::preset_toml(n).unwrap().to_string())
        .collect();
    let fiber = "[fiber]\nmodel = \"htsg\"\neta = { cauchy_a = 1.55, cauchy_b_nm2 = 4000.0 }\n\
                 sigma_h_um = 0.2\ntau_um = 2.0\ndiffuse = 0.05\nnormalization = \"none\"\n";
    for weave in [
        "",
        "[weave]\nweft_fraction = 0.25\n",
        "[weave]\npattern = \"satin-5\"\n",
        "[weave]\npattern = [[1, 1, 0], [0, 1, 1], [1, 0, 1]]\n",
    ] {
        texts.push(format!(
            "name = \"round trip\"\n{fiber}[yarn]\nlateral_length = 0.0\nslope_mean = 1.5707963267948966\n\
             slope_std = 0.1\ninterreflection = 0.3\ninterreflection_albedo = 0.7\ntwist_std = 0.01\n{weave}"
        ));
    }
    texts.push("[fiber]\neta = 1.5\nroughness = 0.3\n[yarn]\nlateral_length = 1e6\nslope_mean = 0.1\nisotropic = true\n".into());
    for text in texts {
        let m = material(&text);
        let written = m.to_toml_string();
        let back = Material::from_toml_str(&written, "<written>")
            .unwrap_or_else(|e| panic!("{e}\n{written}"));
        assert_eq!(back, m, "round trip of\n{text}\nwritten as\n{written}");
        assert_eq!(back.to_toml_string(), written, "writing is stable");
    }
}

// ---------------------------------------------------------------------------------------------
// 9. Narrow spreads: σ → 0 is the single profile (Eq. (19)), σ_t → 0 the aligned yarn (Eq. (21))
// ---------------------------------------------------------------------------------------------

/// A preset with its slope spread, twist spread (if not isotropic) replaced.
fn preset_with(name: &str, slope_std: f64, twist_std: Option<f64>) -> Model {
    let mut m = preset(name);
    let y = m.yarn.as_mut().unwrap();
    y.slope_std = slope_std;
    if let Some(t) = twist_std {
        y.twist_std = t;
    }
    m.build(WAVELENGTH_NM).unwrap()
}

/// Regression (issue 8: `slope_std`/`twist_std` ≈ 1e-4 gave NaN everywhere, a few 1e-4 hung the
/// build): every spread from 1e-3 down to subnormal evaluates finite, and the relative difference
/// to the σ = 0 model shrinks with σ (quadratically where the BRDF is smooth in the slope or
/// azimuth) down to rounding.
#[test]
fn narrow_spreads_tend_to_their_zero_spread_limit() {
    let sigmas = [1e-3, 1e-4, 1e-6, 1e-12, 1e-300];
    // Worst relative difference allowed at each σ.
    let tols = [1e-3, 1e-5, 1e-9, 1e-13, 1e-13];
    type Family = (&'static str, fn(f64) -> Model);
    let families: [Family; 4] = [
        ("belt-cloth, slope σ", |x| {
            preset_with("belt-cloth", x, None)
        }),
        ("belt-cloth, twist σ_t", |x| {
            preset_with("belt-cloth", 0.5, Some(x))
        }),
        ("belt-cloth, both", |x| {
            preset_with("belt-cloth", x, Some(x))
        }),
        ("silk (isotropic), slope σ", |x| {
            preset_with("silk", x, None)
        }),
    ];
    let mut rng = Rng(0x5EED_0901);
    let pairs: Vec<(Vec3, Vec3)> = (0..24)
        .map(|_| {
            let s = Vec3::from_spherical(rng.theta(88.0 * DEG), rng.range(0.0, 2.0 * PI));
            let v = Vec3::from_spherical(rng.theta(88.0 * DEG), rng.range(0.0, 2.0 * PI));
            (s, v)
        })
        .collect();
    for (name, build) in families {
        let limit = build(0.0);
        let want: Vec<f64> = pairs.iter().map(|&(s, v)| limit.eval(s, v)).collect();
        let mut worst_prev = f64::INFINITY;
        for (&sigma, &tol) in sigmas.iter().zip(&tols) {
            let model = build(sigma);
            let mut worst: f64 = 0.0;
            for (&(s, v), &w) in pairs.iter().zip(&want) {
                let got = model.eval(s, v);
                assert!(
                    got.is_finite() && got >= 0.0,
                    "{name} {sigma:e}: f({}, {}) = {got}",
                    sph(s),
                    sph(v)
                );
                let e = rel_err(got, w, CONVERGENCE_FLOOR);
                assert!(
                    e <= tol,
                    "{name} {sigma:e}: f({}, {}) = {got:.15e}, σ = 0 gives {w:.15e}, relative {e:.2e} > {tol:.0e}",
                    sph(s),
                    sph(v)
                );
                worst = worst.max(e);
            }
            assert!(
                worst <= worst_prev.max(1e-15),
                "{name}: the difference grew from {worst_prev:.2e} to {worst:.2e} at σ {sigma:e}"
            );
            worst_prev = worst;
        }
    }
}

/// The albedo of narrow spreads is finite and tends to the σ = 0 albedo (it used to hang).
#[test]
#[ignore = "slow: two twisted-yarn albedos (~1 min)"]
fn narrow_spread_albedo_tends_to_its_limit() {
    let limit = preset_with("belt-cloth", 0.0, Some(0.0));
    let narrow = preset_with("belt-cloth", 1e-5, Some(1e-5));
    let theta_i = 0.6;
    let (a0, a) = (limit.albedo(theta_i, 0.4), narrow.albedo(theta_i, 0.4));
    assert!(a.is_finite(), "albedo at θi {theta_i}: {a}");
    let e = rel_err(a, a0, 1e-6);
    assert!(
        e < 1e-6,
        "θi {theta_i}: albedo {a:.12e} vs σ = 0: {a0:.12e} ({e:.2e})"
    );
}

// ---------------------------------------------------------------------------------------------
// 10. Masking switched off (the reference of Fig. 8)
// ---------------------------------------------------------------------------------------------

/// `f_θ` with masking between facets off, by brute-force midpoint rules independent of the
/// library's quadrature: facet integral over 8192 cells of `θ ∈ [−π/2, π/2]`, slope integral over
/// 2048 cells of `θ_a ∈ [0, π/2]` (~1e-4 relative for `α ≥ 0.1`).
fn brute_force_unmasked(fiber: &Fiber, p: &YarnParams, s: Vec3, v: Vec3, phi_a: f64) -> f64 {
    const FACET_CELLS: usize = 8192;
    const SLOPE_CELLS: usize = 2048;
    let e_u = across(phi_a);
    let g = |theta: f64| -> f64 {
        let a = e_u * theta.sin() + Vec3::Z * theta.cos();
        let (sa, va) = (s.dot(a), v.dot(a));
        if sa <= 0.0 || va <= 0.0 {
            0.0
        } else {
            fiber.eval_with_normal(s, v, a) * sa * va
        }
    };
    // Running integral of g at the cell edges.
    let h = PI / FACET_CELLS as f64;
    let mut running = vec![0.0];
    let mut sum = 0.0;
    for k in 0..FACET_CELLS {
        sum += g(-FRAC_PI_2 + (k as f64 + 0.5) * h) * h;
        running.push(sum);
    }
    let integral_to = |theta: f64| -> f64 {
        let x = ((theta + FRAC_PI_2) / h).clamp(0.0, FACET_CELLS as f64);
        let k = (x.floor() as usize).min(FACET_CELLS - 1);
        running[k] + (running[k + 1] - running[k]) * (x - k as f64)
    };
    let l = p.lateral_length;
    let profile = |theta_a: f64| -> f64 {
        let period = 2.0 * (l * theta_a.cos() + theta_a.sin());
        if period < 1e-12 {
            return fiber.eval(s, v);
        }
        let facets = integral_to(theta_a) - integral_to(-theta_a) + l * (g(theta_a) + g(-theta_a));
        facets / (period * s.z * v.z)
    };
    if p.slope_std == 0.0 {
        return profile(p.slope_mean);
    }
    let density = slope_density(p.slope_mean, p.slope_std);
    let dh = FRAC_PI_2 / SLOPE_CELLS as f64;
    (0..SLOPE_CELLS)
        .map(|j| {
            let t = (j as f64 + 0.5) * dh;
            density(t) * profile(t) * dh
        })
        .sum()
}

/// `Yarn::slope_averaged_unmasked` (Eq. (17) with every facing facet counted, averaged by
/// Eq. (18)) agrees with the brute force, is never below the masked model, and equals it where
/// nothing is masked (light and viewer in the plane along the fibers, `ψ = 0`).
#[test]
fn unmasked_slope_average_matches_brute_force_and_bounds_the_model() {
    let mut rng = Rng(0x5EED_1001);
    for name in ["polyester-sateen", "belt-cloth"] {
        let m = preset(name);
        let f = Fiber::new(&m.fiber, WAVELENGTH_NM).unwrap();
        let mut p = m.yarn.unwrap();
        p.twist_std = 0.0;
        let y = yarn(&f, p);
        for _ in 0..6 {
            let s = Vec3::from_spherical(rng.range(0.0, 80.0 * DEG), rng.range(0.0, 2.0 * PI));
            let v = Vec3::from_spherical(rng.range(0.0, 80.0 * DEG), rng.range(0.0, 2.0 * PI));
            let phi = rng.range(0.0, PI);
            let got = y.slope_averaged_unmasked(s, v, phi);
            let want = brute_force_unmasked(&f, &p, s, v, phi);
            let e = rel_err(got, want, 1e-4);
            assert!(
                e < 2e-3,
                "{name}: unmasked {got:.8e}, brute force {want:.8e} ({e:.1e})"
            );
            let masked = y.slope_averaged(s, v, phi);
            assert!(
                masked <= got * (1.0 + 1e-9),
                "{name}: masked {masked} > unmasked {got}"
            );
        }
        // ψ_s = ψ_v = 0: both directions in the plane (e_f, z).
        let phi: f64 = 0.3;
        let e_f = Vec3::new(phi.cos(), phi.sin(), 0.0);
        let (s, v) = (
            (e_f * 0.6 + Vec3::Z * 0.8).normalize(),
            (e_f * -0.3 + Vec3::Z).normalize(),
        );
        let (open, masked) = (
            y.slope_averaged_unmasked(s, v, phi),
            y.slope_averaged(s, v, phi),
        );
        assert!(
            rel_err(masked, open, 1e-9) < 1e-9,
            "{name}: ψ = 0 masked {masked} vs unmasked {open}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 11. One test per composing equation: (20) interreflection, (23) weave mix
// ---------------------------------------------------------------------------------------------

/// Eq. (20): the yarn BRDF is affine in `ħ`, `f(ħ) = (1 − ħ) f(0) + ħ ρ/π`, for aligned, twisted
/// and isotropic yarns alike (`ħ = 1` is the Lambertian `ρ/π` exactly), and its albedo is
/// `(1 − ħ) A(0) + ħ ρ`.
#[test]
fn eq20_interreflection_is_the_affine_mix_with_a_lambertian() {
    let mut rng = Rng(0x5EED_1101);
    for name in ["polyester-sateen", "belt-cloth", "silk"] {
        let m = preset(name);
        let f = Fiber::new(&m.fiber, WAVELENGTH_NM).unwrap();
        let p = m.yarn.unwrap();
        let with = |hbar: f64| {
            yarn(
                &f,
                YarnParams {
                    interreflection: hbar,
                    interreflection_albedo: 0.6,
                    ..p
                },
            )
        };
        let (y0, y1, yh) = (with(0.0), with(1.0), with(0.3));
        for _ in 0..3 {
            let s = Vec3::from_spherical(rng.range(0.0, 80.0 * DEG), rng.range(0.0, 2.0 * PI));
            let v = Vec3::from_spherical(rng.range(0.0, 80.0 * DEG), rng.range(0.0, 2.0 * PI));
            let phi = rng.range(0.0, PI);
            let f0 = y0.eval(s, v, phi);
            assert_eq!(y1.eval(s, v, phi), 0.6 * FRAC_1_PI, "{name}: ħ = 1");
            let want = 0.7 * f0 + 0.3 * 0.6 * FRAC_1_PI;
            let got = yh.eval(s, v, phi);
            assert!(rel_err(got, want, 1e-12) < 1e-12, "{name}: {got} vs {want}");
        }
        let a = yh.interreflection_mix_albedo(0.25, 1.0);
        assert!(
            (a - (0.7 * 0.25 + 0.3 * 0.6)).abs() < 1e-15,
            "{name}: albedo mix {a}"
        );
    }
}

/// Eq. (23): the cloth BRDF is `γ f_yarn(φ_y = 0) + (1 − γ) f_yarn(φ_y = π/2)`, computed here
/// from two separate yarn evaluations (the model shares one pass over fiber azimuths).
#[test]
fn eq23_cloth_is_the_weighted_sum_of_weft_and_warp_yarns() {
    let mut rng = Rng(0x5EED_1102);
    for name in ["polyester-sateen", "belt-cloth", "silk"] {
        let m = preset(name);
        let model = m.build(WAVELENGTH_NM).unwrap();
        let (y, axes) = model.structure().yarns().unwrap();
        let gamma = m.weft_fraction();
        assert_eq!(axes, [(0.0, gamma), (FRAC_PI_2, 1.0 - gamma)]);
        for _ in 0..4 {
            let s = Vec3::from_spherical(rng.range(0.0, 85.0 * DEG), rng.range(0.0, 2.0 * PI));
            let v = Vec3::from_spherical(rng.range(0.0, 85.0 * DEG), rng.range(0.0, 2.0 * PI));
            let want = gamma * y.eval(s, v, 0.0) + (1.0 - gamma) * y.eval(s, v, FRAC_PI_2);
            let got = model.eval(s, v);
            assert!(
                rel_err(got, want, 1e-9) < 1e-12,
                "{name}: f {got:.15e} vs γ-mix {want:.15e} at {} {}",
                sph(s),
                sph(v)
            );
        }
    }
}
