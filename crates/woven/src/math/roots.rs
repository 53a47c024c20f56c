//! Roots of monotone functions on a bracket: Newton's steps, kept inside the bracket by
//! bisection (the geometry's ray–surface hits and shadow ends; `yarn::float`).

/// The root of `f` on `[lo, hi]`, where `f` is monotone with `f(lo)` and `f(hi)` of opposite
/// signs (or one of them 0); `f_df` returns `(f(x), f′(x))`. Each step is Newton's where it lands
/// strictly inside the current bracket, else the bracket's midpoint; it stops when the bracket is
/// narrower than `tol` or `f` is exactly 0, after at most 100 steps. Without a sign change the
/// nearer end (by `|f|`) is returned.
///
/// ```
/// use woven::math::roots::monotone_root;
/// let x = monotone_root(|x| (x * x - 2.0, 2.0 * x), 0.0, 2.0, 1e-14);
/// assert!((x - 2f64.sqrt()).abs() < 1e-14);
/// ```
pub fn monotone_root(mut f_df: impl FnMut(f64) -> (f64, f64), lo: f64, hi: f64, tol: f64) -> f64 {
    let (f_lo, _) = f_df(lo);
    let (f_hi, _) = f_df(hi);
    if f_lo == 0.0 {
        return lo;
    }
    if f_hi == 0.0 {
        return hi;
    }
    if f_lo.signum() == f_hi.signum() || f_lo.is_nan() || f_hi.is_nan() {
        return if f_lo.abs() <= f_hi.abs() { lo } else { hi };
    }
    // Orient so that f < 0 at a and f > 0 at b.
    let (mut a, mut b) = if f_lo < 0.0 { (lo, hi) } else { (hi, lo) };
    let mut x = 0.5 * (a + b);
    for _ in 0..100 {
        let (fx, dfx) = f_df(x);
        if fx == 0.0 {
            return x;
        }
        if fx < 0.0 {
            a = x;
        } else {
            b = x;
        }
        if (b - a).abs() <= tol {
            return 0.5 * (a + b);
        }
        let newton = x - fx / dfx;
        let (l, h) = if a < b { (a, b) } else { (b, a) };
        x = if newton > l && newton < h && newton.is_finite() {
            newton
        } else {
            0.5 * (a + b)
        };
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_roots_of_increasing_and_decreasing_functions() {
        let up = monotone_root(|x: f64| (x.powi(3) - 0.3, 3.0 * x * x), 0.0, 1.0, 1e-15);
        assert!((up - 0.3f64.cbrt()).abs() < 1e-14, "{up}");
        let down = monotone_root(|x: f64| ((-x).exp() - 0.5, -(-x).exp()), 0.0, 5.0, 1e-15);
        assert!((down - 2f64.ln()).abs() < 1e-14, "{down}");
    }

    #[test]
    fn a_flat_derivative_falls_back_to_bisection() {
        // f′ = 0 at the start: Newton's first step would leave the bracket.
        let x = monotone_root(|x: f64| (x * x - 0.25, 0.0), 0.0, 1.0, 1e-13);
        assert!((x - 0.5).abs() < 1e-12, "{x}");
    }

    #[test]
    fn without_a_sign_change_the_nearer_end() {
        assert_eq!(monotone_root(|x| (x + 1.0, 1.0), 0.0, 1.0, 1e-12), 0.0);
        assert_eq!(monotone_root(|x| (x - 3.0, 1.0), 0.0, 1.0, 1e-12), 1.0);
        assert_eq!(monotone_root(|x| (x - 1.0, 1.0), 0.0, 1.0, 1e-12), 1.0);
    }
}
