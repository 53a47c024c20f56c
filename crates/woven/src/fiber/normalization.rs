//! The normalization `β(θ_i)` of Eq. (15), made precise by docs/spec.md §1.5, tabulated once per
//! lobe (`BetaTable::shared`).

use super::{smith_s1, Fiber, FiberModel};
use crate::math::hemisphere::reflected_hemisphere_integral;
use crate::math::interp::MonotoneCubic;
use crate::math::quadrature::GaussLegendre;
use crate::math::Vec3;
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::{Arc, Mutex, OnceLock};

/// Number of table nodes, uniform in `t = (cos θ_i)^{1/3}` on `[0, 1]`.
///
/// The cube root crowds nodes toward grazing incidence, where `β` changes over a range of
/// `cos θ_i` as small as `α` (the Smith term's scale `a = cot θ / α`) — for a smooth full-model
/// fiber by a factor of ~90 below `cos θ_i = 0.03`.
pub const BETA_NODES: usize = 384;

/// `ln β(cos θ_i)` sampled at `BETA_NODES` nodes uniform in `(cos θ_i)^{1/3}` and interpolated
/// by a monotone cubic. Interpolation error ≤ 1e-4 relative over `(0, 1]` for every supported
/// roughness (tested against direct evaluation between the nodes).
#[derive(Clone, Debug)]
pub struct BetaTable {
    interp: MonotoneCubic,
}

/// What `β` depends on, each number by its bits: the shape of the lobe and the `1 − ρ0` it is
/// scaled by ([`beta_direct`] takes `F = 1`). `Fiber::new` asks for `ρ0 = 0` (ζ = 1, which it
/// scales by each fiber's own ζ), so fibers that differ in `η`, `ρ0` or the body share a table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct BetaKey {
    diffuse: u64,
    lobe: Lobe,
}

/// The lobe's part of a [`BetaKey`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Lobe {
    Rough {
        alpha: u64,
    },
    Htsg {
        alpha: u64,
        k: u64,
        sigma_h: u64,
        tau: u64,
        lambda_nm: u64,
    },
}

impl BetaKey {
    fn of(fiber: &Fiber) -> BetaKey {
        let lobe = match fiber.params.model {
            FiberModel::Rough { .. } => Lobe::Rough {
                alpha: fiber.alpha.to_bits(),
            },
            FiberModel::Htsg { .. } => Lobe::Htsg {
                alpha: fiber.alpha.to_bits(),
                k: fiber.k.to_bits(),
                sigma_h: fiber.sigma_h.to_bits(),
                tau: fiber.tau.to_bits(),
                lambda_nm: fiber.lambda_nm.to_bits(),
            },
        };
        BetaKey {
            diffuse: fiber.params.diffuse.to_bits(),
            lobe,
        }
    }
}

/// How many tables [`BetaTable::shared`] keeps: enough for every fiber of a scene (the
/// showcase has six distinct lobes, asked for 38 times), few enough that a fit trying
/// thousands of roughnesses holds well under a megabyte of them.
const SHARED_TABLES: usize = 64;

impl BetaTable {
    /// [`build`](Self::build)'s table for `fiber`, built once per process for every fiber of the
    /// same lobe and `ρ0` (what the table is a function of: `BetaKey`). A scene builds each
    /// material's fiber several times (its tables, its model, its tilted yarns), and a build is
    /// 25–75 ms on two cores.
    pub fn shared(fiber: &Fiber) -> Arc<BetaTable> {
        static TABLES: OnceLock<Mutex<HashMap<BetaKey, Arc<BetaTable>>>> = OnceLock::new();
        let tables = TABLES.get_or_init(Default::default);
        let key = BetaKey::of(fiber);
        // A poisoned lock only means another thread panicked mid-insert: the map is still whole.
        let lock = || tables.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = lock().get(&key) {
            return Arc::clone(t);
        }
        // Built outside the lock, so builds of different lobes run side by side (two threads
        // asking for the same new lobe at once both build it, and the same table is kept).
        let table = Arc::new(BetaTable::build(fiber));
        let mut map = lock();
        if map.len() >= SHARED_TABLES {
            map.clear();
        }
        Arc::clone(map.entry(key).or_insert(table))
    }

    /// Builds the table for `fiber` (its normalization mode is ignored: this is the `paper` β).
    pub fn build(fiber: &Fiber) -> Self {
        // Nodes are independent: spread them over the cores (interleaved, so each thread gets a
        // mix of cheap and expensive incidences).
        let threads = std::thread::available_parallelism()
            .map_or(1, |n| n.get())
            .min(8);
        let mut values = vec![0.0; BETA_NODES];
        std::thread::scope(|scope| {
            let handles: Vec<_> = (0..threads)
                .map(|j| {
                    scope.spawn(move || {
                        (j..BETA_NODES)
                            .step_by(threads)
                            .map(|k| {
                                let t = k as f64 / (BETA_NODES - 1) as f64;
                                (k, beta_direct(fiber, t * t * t).ln())
                            })
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            for h in handles {
                for (k, v) in h.join().expect("β worker panicked") {
                    values[k] = v;
                }
            }
        });
        BetaTable {
            interp: MonotoneCubic::new(0.0, 1.0, values),
        }
    }

    /// `β` at `cos_theta_i` (clamped to `[0, 1]`).
    #[inline]
    pub fn eval(&self, cos_theta_i: f64) -> f64 {
        self.interp
            .eval(crate::math::special::cbrt(cos_theta_i.max(0.0)))
            .exp()
    }
}

/// `β(θ_i) = (1 − ρ0) / (∫ Ω₁ cos θ_r dω_r [+ e^{−g} S1²])`, computed directly (docs/spec.md §1.5).
///
/// `Ω₁` is the fiber's lobe with `β = 1`, `F = 1`, `ρ0 = 0`. At `cos θ_i = 0` the limit is taken
/// at `cos θ_i = 1e-7` (β is finite there: `S1(θ_i)/cos θ_i → √π/α`).
pub fn beta_direct(fiber: &Fiber, cos_theta_i: f64) -> f64 {
    let ci = cos_theta_i.clamp(1e-7, 1.0);
    let single = match fiber.params.model {
        FiberModel::Rough { .. } => rough_single_scattering(fiber.alpha, ci),
        FiberModel::Htsg { .. } => single_scattering_adaptive(fiber, ci, 1e-7),
    };
    let mut white = fiber.clone();
    white.unit_fresnel = true;
    white.beta = None;
    (1.0 - fiber.params.diffuse) / (single + white.specular_unnormalized(ci))
}

/// `∫ Ω₁ cos θ_r dω_r` by adaptive half-vector quadrature of the fiber's own lobe: slow, general,
/// the reference for the fast rough-model path.
pub fn single_scattering_adaptive(fiber: &Fiber, cos_theta_i: f64, rel_tol: f64) -> f64 {
    let mut white = fiber.clone();
    white.unit_fresnel = true;
    white.beta = None;
    let ci = cos_theta_i;
    reflected_hemisphere_integral(ci, white.lobe_width(ci), rel_tol, |s, v, _| {
        white.lobe(s, v, Vec3::Z, ci, v.z)
    })
}

/// `∫ Ω₁ cos θ_r dω_r` for the rough model, `Ω₁ = D_B S / (4 cos θ_i cos θ_r)`.
///
/// In half-vector coordinates with `r = tan θ_h / α`, `D_B cos θ_h dω_h = 2r e^{−r²} dr dφ_h / (2π)`
/// and `dω_r = 4 (s·h) dω_h`, so the integral is
/// `(1/2π) ∫ dφ_h ∫_0^{r_max(φ_h)} 2r e^{−r²} S1(θ_i) S1(θ_r) (s·h) / (cos θ_i cos θ_h) dr`:
/// an integrand analytic in `r` on a domain whose edge `r_max(φ_h) = tan θ_max(φ_h)/α` follows from
/// `θ_max` (see [`crate::math::hemisphere`]). Gauss–Legendre in `r` (cut at `r = 6.5`, where
/// `e^{−r²} < 5e-19`), with breaks where `S1(θ_r)` has its knee, and on `φ_h` panels graded
/// geometrically around the edge's switch at `π/2`. Agrees with the adaptive reference to ~1e-7.
pub fn rough_single_scattering(alpha: f64, cos_theta_i: f64) -> f64 {
    const R_CUT: f64 = 6.5;
    static RULES: OnceLock<(GaussLegendre, GaussLegendre)> = OnceLock::new();
    let (gl_r, gl_phi) = RULES.get_or_init(|| (GaussLegendre::new(20), GaussLegendre::new(16)));
    let ci = cos_theta_i;
    let si = (1.0 - ci * ci).max(0.0).sqrt();
    let s = Vec3::new(si, 0.0, ci);
    let s1_i_over_ci = smith_s1(ci, alpha) / ci;
    // r of a half-vector polar angle, capped at R_CUT.
    let r_of = |theta_h: f64| -> f64 {
        if theta_h >= FRAC_PI_2 {
            R_CUT
        } else {
            (theta_h.max(0.0).tan() / alpha).min(R_CUT)
        }
    };
    let inner = |phi: f64| -> f64 {
        let (sp, cp) = phi.sin_cos();
        // v_z = R cos(2θ_h − δ): positive for θ_h < (δ + π/2)/2.
        let (b, a) = (si * cp, ci);
        let big_r = (a * a + b * b).sqrt();
        let delta = b.atan2(a);
        let r_max = r_of(0.5 * (FRAC_PI_2 + delta));
        if r_max <= 0.0 {
            return 0.0;
        }
        // Breaks: where S1(θ_r) has its knee (v_z = 2α and α/2), and at θ_h = π/8, π/4, 3π/8 —
        // for large α the angle θ_h = atan(α r) turns over a range 1/α of r.
        let mut breaks = [f64::INFINITY; 5];
        for (k, vz) in [2.0 * alpha, 0.5 * alpha].into_iter().enumerate() {
            if vz < big_r {
                breaks[k] = r_of(0.5 * (delta + (vz / big_r).acos()));
            }
        }
        for (k, t) in [0.125, 0.25, 0.375].into_iter().enumerate() {
            breaks[2 + k] = r_of(t * PI);
        }
        breaks.sort_by(f64::total_cmp);
        let mut edges = [0.0; 7];
        let mut n = 1;
        for r in breaks {
            if r > edges[n - 1] && r < r_max {
                edges[n] = r;
                n += 1;
            }
        }
        edges[n] = r_max;
        let mut sum = 0.0;
        for e in edges[..=n].windows(2) {
            sum += gl_r.integrate(e[0], e[1], |r| {
                let t = alpha * r;
                let c = 1.0 / (1.0 + t * t).sqrt();
                let st = t * c;
                let h = Vec3::new(st * cp, st * sp, c);
                let sh = s.dot(h);
                let vz = 2.0 * sh * c - ci;
                if vz <= 0.0 {
                    return 0.0;
                }
                2.0 * r * (-r * r).exp() * s1_i_over_ci * smith_s1(vz, alpha) * sh / c
            });
        }
        sum
    };
    // φ_h ∈ [0, π], doubled (the integrand is even in φ_h). At grazing the edge r_max switches
    // around π/2 over a width w ~ cot θ_i and relaxes algebraically (~w/|φ − π/2|): panels graded
    // geometrically from w/2 out to the ends.
    let w = (ci / si.max(1e-300)).max(1e-9);
    let mut edges = vec![0.0, PI];
    let mut d = 0.5 * w;
    while d < FRAC_PI_2 {
        edges.push(FRAC_PI_2 - d);
        edges.push(FRAC_PI_2 + d);
        d *= 4.0;
    }
    edges.push(FRAC_PI_2);
    edges.sort_by(f64::total_cmp);
    let mut total = 0.0;
    for e in edges.windows(2) {
        total += gl_phi.integrate(e[0], e[1], inner);
    }
    2.0 * total / (2.0 * PI)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fiber::{FiberParams, Normalization};

    /// What a β table is keyed by: fibers that differ in `η` or the body alone have one key,
    /// while a different roughness, `ρ0`, or (for the full model) wavelength each make another;
    /// `Fiber::new` gives fibers differing in `ρ0` the same table; and a shared table is a fresh
    /// build's, `ρ0` included.
    #[test]
    fn beta_tables_are_keyed_by_lobe() {
        let rough = |eta: f64, roughness: f64, diffuse: f64| {
            Fiber::new(&FiberParams::rough(eta, roughness, diffuse), 550.0).unwrap()
        };
        let key = |f: &Fiber| BetaKey::of(f);
        assert_eq!(key(&rough(1.5, 0.1234, 0.0)), key(&rough(1.7, 0.1234, 0.0)));
        assert_ne!(key(&rough(1.5, 0.1234, 0.0)), key(&rough(1.5, 0.1235, 0.0)));
        assert_ne!(key(&rough(1.5, 0.1234, 0.0)), key(&rough(1.5, 0.1234, 0.3)));
        let htsg = |lambda: f64| {
            let p = FiberParams {
                model: FiberModel::Htsg {
                    sigma_h_um: 0.15,
                    tau_um: 1.5,
                },
                ..FiberParams::rough(1.5, 0.1, 0.0)
            };
            Fiber::new(&p.with_normalization(Normalization::None), lambda).unwrap()
        };
        assert_ne!(key(&htsg(500.0)), key(&htsg(600.0)));
        assert_eq!(key(&htsg(500.0)), key(&htsg(500.0)));
        // Two fibers of one lobe, ρ0 0 and 0.3: one β for ζ = 1, to the bit.
        let (a, b) = (rough(1.5, 0.1234, 0.0), rough(1.7, 0.1234, 0.3));
        let (ta, tb) = (a.beta.as_deref().unwrap(), b.beta.as_deref().unwrap());
        // A fiber with ρ0 > 0 asked directly gets its own table, scaled by 1 − ρ0.
        let dyed = BetaTable::shared(&b);
        let fresh = BetaTable::build(&b);
        for k in 0..=100 {
            let ci = k as f64 / 100.0;
            assert_eq!(ta.eval(ci).to_bits(), tb.eval(ci).to_bits(), "cos θi {ci}");
            assert_eq!(
                dyed.eval(ci).to_bits(),
                fresh.eval(ci).to_bits(),
                "cos θi {ci}"
            );
            assert!(
                (dyed.eval(ci) / ta.eval(ci) - 0.7).abs() < 1e-3,
                "cos θi {ci}"
            );
        }
    }

    #[test]
    fn fast_rough_path_agrees_with_adaptive_reference() {
        for roughness in [0.005, 0.02, 0.1, 0.5, 2.0] {
            let f = Fiber::new(
                &FiberParams::rough(1.5, roughness, 0.0).with_normalization(Normalization::None),
                550.0,
            )
            .unwrap();
            for ci in [1e-4, 0.02, 0.4, 1.0] {
                let fast = rough_single_scattering(f.alpha, ci);
                let slow = single_scattering_adaptive(&f, ci, 1e-8);
                assert!(
                    ((fast - slow) / slow).abs() < 1e-7,
                    "roughness {roughness} cos θi {ci}: fast {fast} adaptive {slow}"
                );
            }
        }
    }

    #[test]
    fn table_interpolates_within_1e4_between_nodes() {
        for roughness in [0.005, 0.03, 0.2, 1.0] {
            let f = Fiber::new(&FiberParams::rough(1.5, roughness, 0.1), 550.0).unwrap();
            let n = (BETA_NODES - 1) as f64;
            for k in 0..BETA_NODES - 1 {
                // Midpoints in t = (cos θi)^⅓ are where interpolation is worst.
                let t = (k as f64 + 0.5) / n;
                let ci = t * t * t;
                let direct = beta_direct(&f, ci);
                let table = f.beta(ci);
                assert!(
                    ((table - direct) / direct).abs() < 1e-4,
                    "roughness {roughness}, cos θi {ci}: table {table} direct {direct}"
                );
            }
        }
    }
}
