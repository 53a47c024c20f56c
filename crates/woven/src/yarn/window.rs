//! Narrow Gaussian windows: the slope distribution (Eq. (19)) and the twist density (Eq. (21))
//! integrated in their standardized variable `x = (t − μ)/σ`.
//!
//! A spread `σ` below [`NARROW_STD`] puts all but `erfc(8/√2) ≈ 1.2e-15` of a Gaussian's mass
//! within `±8σ` of its centre, a window that fits inside the slope range `[0, π/2]` and one twist
//! period. Integrating over `x ∈ [−8, 8]` on fixed panels then costs the same for every `σ`
//! (no panel count grows as `1/σ`), the weights `exp(−x²/2)` never underflow or divide by `σ²`,
//! and as `σ → 0` every node collapses onto the centre, so the average tends to the integrand's
//! value there — the `σ = 0` model — continuously.

use crate::math::special::exp_neg;
use std::f64::consts::PI;

/// Spreads (radians) below which a slope or twist distribution is integrated over its `±8σ`
/// window in `x`: `16σ < π/2`, so the window fits in the slope range and in one twist period.
pub const NARROW_STD: f64 = PI / 32.0;

/// Half-width of the window, in standard deviations: the Gaussian's mass beyond is
/// `erfc(8/√2) ≈ 1.2e-15`, below double-precision rounding of the sum.
pub const HALF_WIDTH: f64 = 8.0;

/// Fixed panel edges in `x`: panels 1.25 wide where the weight `exp(−x²/2)` has its mass, wider
/// ones in the tails (6 Gauss–Legendre nodes integrate `exp(−x²/2)` on them to ~1e-10 of its
/// total).
const X_EDGES: [f64; 11] = [-8.0, -6.0, -4.0, -2.5, -1.25, 0.0, 1.25, 2.5, 4.0, 6.0, 8.0];

/// Fixed panel edges for rules of [`HIGH_ORDER`] nodes or more, which integrate `exp(−x²/2)` on
/// these wider panels as well.
const X_EDGES_HIGH_ORDER: [f64; 5] = [-8.0, -3.0, 0.0, 3.0, 8.0];

/// Rules with at least this many nodes per panel use [`X_EDGES_HIGH_ORDER`].
pub const HIGH_ORDER: usize = 12;

/// The panel edges over `[lo, hi] ⊂ [−8, 8]` in `x` for a rule of `nodes` nodes per panel: the
/// fixed edges, plus `extra` breaks of the integrand (already in `x`; those outside are
/// dropped). Sorted, without duplicates.
pub fn edges(lo: f64, hi: f64, nodes: usize, extra: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let fixed: &[f64] = if nodes >= HIGH_ORDER {
        &X_EDGES_HIGH_ORDER
    } else {
        &X_EDGES
    };
    let mut e: Vec<f64> = fixed
        .iter()
        .copied()
        .chain(extra)
        .filter(|x| x.is_finite() && *x > lo && *x < hi)
        .collect();
    e.push(lo);
    e.push(hi);
    e.sort_by(f64::total_cmp);
    e.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    e
}

/// The standard normal shape `exp(−x²/2)` (unnormalized).
#[inline]
pub fn shape(x: f64) -> f64 {
    exp_neg(0.5 * x * x)
}
