//! The full physical-optics fiber model: He et al.'s directional-diffuse series (paper Eqs. (9),
//! (11)–(13); docs/spec.md §1.4).

use crate::math::special::ln_gamma;

/// The series `Σ_{m≥1} gᵐ e^{−g} / (m! · m) · exp(−K/m)` of Eq. (9)'s `D`, without its prefactor.
///
/// `g ≥ 0` is the effective roughness and `K = k²|w_xy|²τ²/4 ≥ 0`. Summed in log space around the
/// *largest* term `m*` (where `ln(g/m) + K/m² ≈ 0`, which lies above `g` once `K > 0`), outward
/// until the end terms fall below `1e-12` of the peak. Stable for `g` from `1e-4` to `1e4` and
/// beyond. Returns 0 for `g = 0`.
pub fn series(g: f64, k_big: f64) -> f64 {
    if g <= 0.0 {
        return 0.0;
    }
    let ln_g = g.ln();
    // log of the m-th term.
    let term = |m: f64| m * ln_g - g - ln_gamma(m + 1.0) - m.ln() - k_big / m;
    // The terms are unimodal in m (the log is concave for m ≥ 1). The peak is below
    // max(e·g, √K) + 2: past both, ln(g/m) ≤ −1 and K/m² ≤ 1 make every step downhill.
    let mut lo = 1.0f64;
    let mut hi = (std::f64::consts::E * g).max(k_big.sqrt()).ceil() + 2.0;
    while hi - lo > 2.0 {
        let m1 = (lo + (hi - lo) / 3.0).floor();
        let m2 = (hi - (hi - lo) / 3.0).ceil();
        if term(m1) < term(m2) {
            lo = m1 + 1.0;
        } else {
            hi = m2 - 1.0;
        }
        if hi < lo {
            hi = lo;
        }
    }
    let mut peak = lo;
    let mut t_peak = term(lo);
    let mut m = lo + 1.0;
    while m <= hi {
        let t = term(m);
        if t > t_peak {
            t_peak = t;
            peak = m;
        }
        m += 1.0;
    }
    // Sum outward from the peak with the recurrence of the log term.
    let cutoff = (1e-12f64).ln();
    let mut sum = 1.0;
    // Upward: t(m+1) − t(m) = ln g − ln(m+1) − ln((m+1)/m) − K/(m+1) + K/m.
    let mut t = t_peak;
    let mut m = peak;
    loop {
        let m1 = m + 1.0;
        t += ln_g - m1.ln() - (m1 / m).ln() - k_big / m1 + k_big / m;
        m = m1;
        let r = t - t_peak;
        if r < cutoff {
            break;
        }
        sum += r.exp();
    }
    let mut t = t_peak;
    let mut m = peak;
    while m > 1.0 {
        let m0 = m - 1.0;
        t -= ln_g - m.ln() - (m / m0).ln() - k_big / m + k_big / m0;
        m = m0;
        let r = t - t_peak;
        if r < cutoff {
            break;
        }
        sum += r.exp();
    }
    t_peak.exp() * sum
}

#[cfg(test)]
mod tests {
    use super::*;

    fn naive(g: f64, k: f64) -> f64 {
        // Direct summation with explicit factorials (only for small g).
        let mut s = 0.0;
        let mut fact = 1.0;
        for m in 1..200 {
            let mf = m as f64;
            fact *= mf;
            s += g.powi(m) * (-g).exp() / (fact * mf) * (-k / mf).exp();
        }
        s
    }

    #[test]
    fn agrees_with_naive_summation_for_moderate_g() {
        for g in [1e-4, 0.01, 0.5, 3.0, 20.0] {
            for k in [0.0, 0.3, 5.0, 80.0] {
                let a = series(g, k);
                let b = naive(g, k);
                assert!(
                    (a - b).abs() <= 1e-11 * b.abs().max(1e-300),
                    "g {g} K {k}: {a} vs {b}"
                );
            }
        }
    }

    #[test]
    fn large_g_without_k_tends_to_one_over_g() {
        // Σ gᵐe^{−g}/(m!·m) = E[1/m] of a Poisson(g) (m ≥ 1) ≈ 1/g (1 + 1/g + …).
        for g in [1e2, 1e3, 1e4] {
            let s = series(g, 0.0);
            assert!(
                (s * g - 1.0 - 1.0 / g).abs() < 3.0 / (g * g),
                "g {g}: {}",
                s * g
            );
        }
    }

    #[test]
    fn finite_and_positive_over_the_range() {
        for g in [1e-4, 1e-2, 1.0, 1e2, 1e4] {
            for k in [0.0, 1.0, 1e2, 1e4, 1e6] {
                let s = series(g, k);
                assert!(s.is_finite() && s >= 0.0, "g {g} K {k}: {s}");
            }
        }
    }
}
