//! Special functions: `erfc` and the scaled `erfcx` on the range the Smith term needs
//! (piecewise polynomials fitted here), `libm` elsewhere.

/// `erfcx(x) = exp(x²) erfc(x)`. On `[0, ERFCX_MAX)`: one polynomial of degree 15 per piece of
/// width ½, in `u = x − centre`, evaluated by Estrin's scheme (a short dependency chain, unlike
/// Horner or Clenshaw). The coefficients are the piece's Chebyshev interpolant at 40 nodes,
/// computed in 50-digit arithmetic (mpmath, `scripts/fit_erfcx.py`) and converted to powers of
/// `u`; relative error below 1e-15 (tested against `libm`).
///
/// Outside `[0, ERFCX_MAX)` it falls back to `libm` (`exp(x²)` overflows beyond `x ≈ 26.6`).
#[inline]
pub fn erfcx(x: f64) -> f64 {
    if (0.0..ERFCX_MAX).contains(&x) {
        // x < 6, so the index is at most 11.
        let (centre, c) = &ERFCX_POLY[(2.0 * x) as usize];
        estrin16(c, x - centre)
    } else {
        libm::erfc(x) * (x * x).exp()
    }
}

/// The upper end of the polynomial range of [`erfcx`]: the Smith term saturates at `a = 6`.
pub const ERFCX_MAX: f64 = 6.0;

/// `Σ_{j<16} c_j u^j` by Estrin's scheme.
#[inline]
fn estrin16(c: &[f64; 16], u: f64) -> f64 {
    let u2 = u * u;
    let u4 = u2 * u2;
    let u8 = u4 * u4;
    let p = |k: usize| c[2 * k] + c[2 * k + 1] * u;
    let q0 = p(0) + p(1) * u2;
    let q1 = p(2) + p(3) * u2;
    let q2 = p(4) + p(5) * u2;
    let q3 = p(6) + p(7) * u2;
    (q0 + q1 * u4) + (q2 + q3 * u4) * u8
}

/// `e^{−x}`: `(-x).exp()`, but 0 at once where that is 0 (`x` > 745.2, past the smallest
/// subnormal). The platform's `exp` takes a slow error-reporting path for every result that
/// underflows, 10 % of a denoised render when far-off weights and lobes asked it.
#[inline]
pub fn exp_neg(x: f64) -> f64 {
    if x > EXP_NEG_ZERO {
        0.0
    } else {
        (-x).exp()
    }
}

/// `(sin x, cos x)`, as the `libm` crate computes them (the kernels of FreeBSD's and musl's
/// libm, within an ulp). The platform's `sincos` saves and restores the rounding mode on every
/// call, a tenth of a diffuse furnace's render, where every bounce draws an angle; this one
/// inlines into its caller.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// Beyond this `x`, `e^{−x}` rounds to 0 in `f64` (`ln 2⁻¹⁰⁷⁵` = −745.133…).
const EXP_NEG_ZERO: f64 = 745.2;

/// `exp(−x²)` to full precision: `x²` is split exactly into `hi + lo` (Dekker's product, no FMA
/// needed), so that the rounding of `x²` (relative 1e-16, absolute `x²·1e-16`) does not enter
/// the exponent.
#[inline]
pub fn exp_neg_sq(x: f64) -> f64 {
    // Veltkamp split of x into 26-bit halves: xh² + 2 xh xl + xl² = x² exactly.
    let c = 134_217_729.0 * x; // 2^27 + 1
    let xh = c - (c - x);
    let xl = x - xh;
    let hi = x * x;
    let lo = ((xh * xh - hi) + 2.0 * xh * xl) + xl * xl;
    (-hi).exp() * (1.0 - lo)
}

/// The complementary error function `erfc(x) = 1 − erf(x)`, accurate in its tail.
///
/// On `[0, 6)` (every Smith-term evaluation) it is `exp(−x²) erfcx(x)` from [`erfcx`]'s polynomials —
/// one call to the platform `exp` where `libm`'s `erfc` makes two of its own; elsewhere `libm`.
#[inline]
pub fn erfc(x: f64) -> f64 {
    if (0.0..ERFCX_MAX).contains(&x) {
        exp_neg_sq(x) * erfcx(x)
    } else {
        libm::erfc(x)
    }
}

/// The cube root of `x ≥ 0` (normal or 0), to about an ulp: an exponent-thirds first guess (6 %),
/// two Halley steps (1e-12) and a Newton step: faster than `f64::cbrt` (which is
/// correctly rounded); the β look-up takes one per fiber evaluation. Subnormal, negative, huge
/// (beyond 1e300, where `y³` would overflow) and non-finite `x` go to `f64::cbrt`.
#[inline]
pub fn cbrt(x: f64) -> f64 {
    if !(f64::MIN_POSITIVE..=1e300).contains(&x) {
        return x.cbrt();
    }
    // A third of the bit pattern (exponent and mantissa together), rebased so that cbrt(1) = 1.
    let mut y = f64::from_bits(x.to_bits() / 3 + 0x2AA0_0000_0000_0000);
    for _ in 0..2 {
        let y3 = y * y * y;
        y *= (y3 + 2.0 * x) / (2.0 * y3 + x);
    }
    y - (y * y * y - x) / (3.0 * y * y)
}

/// `ln Γ(x)` for `x > 0`.
#[inline]
pub fn ln_gamma(x: f64) -> f64 {
    libm::lgamma(x)
}

/// `1/√π`.
pub const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// The pieces of [`erfcx`]: `(centre, coefficients of u^0 … u^15)` for `x ∈ [k/2, (k+1)/2)`
/// (generated, see [`erfcx`]).
#[rustfmt::skip]
#[allow(clippy::excessive_precision, clippy::unreadable_literal)]
const ERFCX_POLY: [(f64, [f64; 16]); 12] = [
    (0.25, [
        0.7703465477309968,
        -0.7432058932300142,
        0.5845450744234932,
        -0.398046416416094,
        0.24251673515970434,
        -0.1349668930504431,
        0.06959167063627528,
        -0.03359113582850151,
        0.01529847142390321,
        -0.006614781645179487,
        0.0027289635972356104,
        -0.0010786475677868371,
        0.0004097248513090857,
        -0.00015012218722462503,
        5.4734103496172964e-05,
        -1.878194972125948e-05,
    ]),
    (0.75, [
        0.5069376502931449,
        -0.3679726916557954,
        0.2309581315512983,
        -0.1298360619948811,
        0.06679054252756655,
        -0.03189726203968045,
        0.014289198666213606,
        -0.006051532297346526,
        0.0024376373433093548,
        -0.0009385120541241955,
        0.0003467512577216077,
        -0.00012335459745194577,
        4.2361257382811824e-05,
        -1.4084644652547417e-05,
        4.653761695170804e-06,
        -1.4588569600525426e-06,
    ]),
    (1.25, [
        0.3678229164523611,
        -0.20882187596460985,
        0.1067955714965988,
        -0.05021827439590757,
        0.022011364250856973,
        -0.009081627632934334,
        0.0035531099032542215,
        -0.001325782929696142,
        0.00047397030874083123,
        -0.0001629600086998011,
        5.4054112241720964e-05,
        -1.7344097054186362e-05,
        5.394669053199937e-06,
        -1.6303827889818303e-06,
        4.893365658571783e-07,
        -1.4031503579739768e-07,
    ]),
    (1.75, [
        0.2849722347374364,
        -0.1309763455144852,
        0.05576363008708727,
        -0.022259995241388327,
        0.008404319207328828,
        -0.0030209746514251266,
        0.0010392045224475804,
        -0.0003435333534715252,
        0.00010950528830284965,
        -3.375535519700516e-05,
        1.0086688983512686e-05,
        -2.92793985037239e-06,
        8.270256710674787e-07,
        -2.2773201328521628e-07,
        6.226430615564444e-08,
        -1.636256527032342e-08,
    ]),
    (2.25, [
        0.23108725873039188,
        -0.08848650280874916,
        0.03199262741070626,
        -0.011002060756440047,
        0.003618995354358076,
        -0.0011437284836537463,
        0.00034853542204605107,
        -0.00010272108115752662,
        2.935324733931567e-05,
        -8.150283236730207e-06,
        2.2030227313111913e-06,
        -5.806336126225102e-07,
        1.4941923382055445e-07,
        -3.7597864531353846e-08,
        9.394670330633001e-09,
        -2.2680367600959174e-09,
    ]),
    (2.75, [
        0.1936620962790687,
        -0.06323763756063484,
        0.019758592987322864,
        -0.005934337896997976,
        0.0017195818852892139,
        -0.00048219508498105473,
        0.00013118180053048792,
        -3.4698609577832546e-05,
        8.940156044713146e-06,
        -2.2473734315287922e-06,
        5.519759291100959e-07,
        -1.3262546949768857e-07,
        3.1207281398572845e-08,
        -7.199476139883742e-09,
        1.6498405143158622e-09,
        -3.669135743760937e-10,
    ]),
    (3.25, [
        0.16633534842682188,
        -0.047199402321170376,
        0.012937290883018157,
        -0.003435471300907574,
        0.0008860045775342716,
        -0.00022238256956847629,
        5.442040881224984e-05,
        -1.3004640265343539e-05,
        3.038831986929573e-06,
        -6.952080678604188e-07,
        1.5588117175580268e-07,
        -3.428988095652311e-08,
        7.40616028465765e-09,
        -1.5720314139710644e-09,
        3.3159285561009584e-10,
        -6.813646966177181e-11,
    ]),
    (3.75, [
        0.14558972127503855,
        -0.03645625753272353,
        0.008878755527325298,
        -0.00210728287016911,
        0.00048822238209556744,
        -0.00011057957492429284,
        2.451632537649145e-05,
        -5.32667278927372e-06,
        1.1353256040732286e-06,
        -2.3760039410619327e-07,
        4.886482883761854e-08,
        -9.883146202271013e-09,
        1.96710362813955e-09,
        -3.855627264809809e-10,
        7.513431970233354e-11,
        -1.4309354206297522e-11,
    ]),
    (4.25, [
        0.12934527478598792,
        -0.028944331414615332,
        0.006331866273872749,
        -0.0013559331671040983,
        0.00028457515684016577,
        -5.8595500213357555e-05,
        1.1848093644465745e-05,
        -2.3546006355371618e-06,
        4.602602358351754e-07,
        -8.855436291427012e-08,
        1.6780839476057628e-08,
        -3.1337817140299225e-09,
        5.770296636857011e-10,
        -1.0481895816870134e-10,
        1.8939145734437868e-11,
        -3.3536712551761276e-12,
    ]),
    (4.75, [
        0.11630270721024731,
        -0.02350344859816315,
        0.00466132636897234,
        -0.0009080988970296905,
        0.000173928304040655,
        -3.277578113463171e-05,
        6.081114550384878e-06,
        -1.11156772008687e-06,
        2.0029196998750259e-07,
        -3.5595747247565025e-08,
        6.2424343020913194e-09,
        -1.0807609868588968e-09,
        1.8479967988863075e-10,
        -3.1221709715145623e-11,
        5.249139587114141e-12,
        -8.669318186979033e-13,
    ]),
    (5.25, [
        0.1056127354688918,
        -0.01944544467214865,
        0.003524150940111397,
        -0.0006291014910425433,
        0.00011068405606902238,
        -1.9204078672070307e-05,
        3.287547680217781e-06,
        -5.555581002648853e-07,
        9.271691345531437e-08,
        -1.528762324785227e-08,
        2.491378330973765e-09,
        -4.014340593808068e-10,
        6.397397129215466e-11,
        -1.0086869475150386e-11,
        1.5833280067369205e-12,
        -2.446405346781608e-13,
    ]),
    (5.75, [
        0.09669877816971392,
        -0.016343218143802483,
        0.002725273842849635,
        -0.00044859569827805586,
        7.292428887540691e-05,
        -1.1712414897786438e-05,
        1.8593010710449731e-06,
        -2.9183821122225305e-07,
        4.530783912883336e-08,
        -6.9595858285891415e-09,
        1.0580441372690879e-09,
        -1.5924220659994113e-10,
        2.3733302924022028e-11,
        -3.503670742905684e-12,
        5.151348101545931e-13,
        -7.468172001125174e-14,
    ]),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// `exp_neg(x)` is `(-x).exp()` to the bit everywhere: below its cut it calls it, and above
    /// the cut the platform's `exp` gives 0 too (a cut a little lower would return 0 for
    /// subnormal results and fail here).
    #[test]
    fn exp_neg_is_exp_to_the_bit() {
        let mut xs: Vec<f64> = (-2000..=16_000).map(|k| k as f64 * 0.05).collect();
        xs.extend([
            745.13,
            745.1332191019411,
            745.2,
            745.3,
            1e300,
            f64::INFINITY,
        ]);
        xs.extend([-0.0, 1e-300, f64::NEG_INFINITY]);
        for x in xs {
            assert_eq!(exp_neg(x).to_bits(), (-x).exp().to_bits(), "x = {x}");
        }
        assert!(exp_neg(f64::NAN).is_nan());
        assert!(
            exp_neg(745.0) > 0.0,
            "the cut must leave the subnormal results"
        );
    }

    /// `sin_cos` against the platform's, over the angles a draw makes (`[0, 2π]`) and far
    /// beyond: within an ulp (both equal to the bit for over 90 % of the angles), and the same special
    /// values.
    #[test]
    fn sin_cos_is_the_platforms_within_an_ulp() {
        let ulps = |a: f64, b: f64| (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
        let mut rng = crate::math::rng::SplitMix(5);
        let mut same = 0;
        for k in 0..200_000 {
            let x = if k % 2 == 0 {
                rng.range(0.0, 2.0 * std::f64::consts::PI)
            } else {
                rng.log_range(-8.0, 6.0) * if k % 4 == 1 { -1.0 } else { 1.0 }
            };
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            let (ds, dc) = (ulps(s, s0), ulps(c, c0));
            // Near a zero of sin or cos an ulp of the argument's reduction is many of the
            // value's: there, compare absolutely.
            assert!(ds <= 1 || (s - s0).abs() < 1e-16, "sin({x}) = {s} vs {s0}");
            assert!(dc <= 1 || (c - c0).abs() < 1e-16, "cos({x}) = {c} vs {c0}");
            same += usize::from(ds == 0 && dc == 0);
        }
        assert!(same > 180_000, "{same} of 200 000 equal to the bit");
        for x in [0.0, -0.0] {
            let (s, c) = sin_cos(x);
            assert_eq!((s.to_bits(), c), (x.to_bits(), 1.0));
        }
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (s, c) = sin_cos(x);
            assert!(s.is_nan() && c.is_nan(), "{x}");
        }
    }

    /// The polynomials against `libm` over the fitted range, densely, and at the piece edges: a few
    /// ulp relative.
    #[test]
    fn erfc_and_erfcx_match_libm() {
        let mut worst: f64 = 0.0;
        for k in 0..=60_000 {
            let x = k as f64 * 1e-4;
            let want = libm::erfc(x);
            let got = erfc(x);
            worst = worst.max(((got - want) / want).abs());
            let want_x = want * (x * x).exp();
            let rel = ((erfcx(x) - want_x) / want_x).abs();
            // exp(x²) in f64 carries x²·1e-16 of its own rounding; allow for it.
            assert!(
                rel < 2e-15 + x * x * 2.3e-16,
                "erfcx({x}): {} vs {want_x}",
                erfcx(x)
            );
        }
        assert!(
            worst < 2e-15,
            "worst relative error of erfc on [0, 6]: {worst:e}"
        );
        // Hand values (Abramowitz & Stegun, Table 7.1): erfc(0) = 1, erfc(1) = 0.157299207050285.
        assert_eq!(erfc(0.0), 1.0);
        assert!((erfc(1.0) - 0.157_299_207_050_285_1).abs() < 3e-17);
        // Outside the polynomials' range: libm.
        for x in [-3.0, -0.1, 6.0, 7.5, 30.0] {
            assert_eq!(erfc(x), libm::erfc(x), "erfc({x})");
        }
    }

    #[test]
    fn cbrt_is_within_an_ulp_or_two() {
        let mut rng = crate::math::rng::SplitMix(3);
        for k in 0..200_000 {
            let x = if k % 2 == 0 {
                rng.uniform()
            } else {
                rng.log_range(-300.0, 300.0)
            };
            let (got, want) = (cbrt(x), x.cbrt());
            assert!(
                (got - want).abs() <= 2.5e-16 * want,
                "cbrt({x}) = {got}, want {want}"
            );
        }
        for x in [0.0, 1.0, 8.0, 1e-310, 1e300, f64::MAX] {
            assert!(
                (cbrt(x) - x.cbrt()).abs() <= 2.5e-16 * x.cbrt(),
                "cbrt({x})"
            );
        }
        assert_eq!(cbrt(f64::INFINITY), f64::INFINITY);
        assert!(cbrt(f64::NAN).is_nan());
    }

    #[test]
    fn exp_neg_sq_is_exact_to_rounding() {
        for x in [0.0, 0.3, 1.7, 4.2, 5.999, 10.0] {
            let got = exp_neg_sq(x);
            let want = (-(x * x)).exp();
            assert!(((got - want) / want).abs() < 1e-14, "{x}: {got} vs {want}");
        }
    }
}
