//! The profile BRDF (paper Eq. (17); docs/spec.md §2.3) and its average over lateral slopes
//! (Eqs. (18)–(19); docs/spec.md §2.4) for one fiber orientation and one pair of directions.
//!
//! Every facet of a cross-section — a point of the arc at angle `θ`, or a lateral of slope `±θ_a`
//! — has the normal `a(θ) = sin θ e_u + cos θ z`, and the fiber BRDF there weighted by both
//! cosines, `g(θ) = f_fiber(s, v; a(θ)) (s·a)(v·a)`, depends on `θ` alone, not on the profile.
//! So `g` is sampled once per `(s, v, φ_a)` on panels that resolve its highlight (at
//! `θ* = atan2(h·e_u, h·z)`, `h = s + v`, of width `≈ α ρ`, `ρ` the in-plane length of `ĥ`) and
//! each profile only integrates that interpolant over its lit-and-visible arc interval; the
//! laterals evaluate `g(±θ_a)` directly.

use super::profile::{PieceIntervals, Profile};
use super::slope::{x_window, SlopeDistribution};
use super::window;
use crate::fiber::{Fiber, FiberFrame};
use crate::math::lanes::Lanes;
use crate::math::legendre::PiecewiseLegendre;
use crate::math::quadrature::{panel_edges, GaussLegendre};
use crate::math::Vec3;
use std::f64::consts::FRAC_PI_2;

/// A facet quantity in the two parts the fiber BRDF is affine in
/// ([`Fiber::eval_parts_with_normal`]): `[normalized lobe, Lambertian 1/π]`; the value is
/// `ζ·parts[0] + ρ0·parts[1]` ([`Fiber::lobe_weight`], `ρ0` the fiber's diffuse albedo).
pub type FiberParts = [f64; 2];

/// The cross-section of fibers of azimuth `φ_a`, seen by one pair of directions.
#[derive(Debug)]
pub struct CrossSection<'a> {
    fiber: &'a Fiber,
    s: Vec3,
    v: Vec3,
    frame: FiberFrame,
    /// Projected angles `ψ = atan2(d·e_u, d·z)` (docs/spec.md §2.2).
    psi_s: f64,
    psi_v: f64,
    /// Highlight angle `θ*` and its width in `θ`.
    theta_peak: f64,
    peak_width: f64,
    /// Width of the sampling panels near the highlight, in highlight widths.
    panel_widths: f64,
    /// The sampling panels of `g` (also used by the exact arc integral of a single profile).
    edges: Vec<f64>,
    g: PiecewiseLegendre<FiberParts>,
    masking: Masking,
}

/// Which facets of a profile count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Masking {
    /// The exact lit-and-visible sets of Eq. (17) (docs/spec.md §2.2–§2.3): the model.
    Exact,
    /// No facet hides another: every facet facing both directions counts. Not the model — a
    /// reference that measures how much masking and shadowing the model applies (Fig. 8).
    Off,
}

/// Widest sampling panel of the facet lobe, radians (10 nodes resolve any smooth lobe on it to
/// ~1e-9).
const MAX_PANEL: f64 = 0.15;

/// Panel width (in highlight widths) for a single profile: golden-value accuracy (~1e-8).
pub const FINE_PANELS: f64 = 1.5;
/// Panel width for slope averages, whose own quadrature error (~1e-6) dominates anyway.
pub const COARSE_PANELS: f64 = 2.5;

impl<'a> CrossSection<'a> {
    /// Prepares the cross-section of fibers along `e_f = (cos φ_a, sin φ_a, 0)` for light from `s`
    /// and a viewer at `v` (both with positive `z`), sampling the facet lobe on panels
    /// `panel_widths` highlight widths wide (`FINE_PANELS` or `COARSE_PANELS`).
    pub fn new(fiber: &'a Fiber, s: Vec3, v: Vec3, phi_a: f64, panel_widths: f64) -> Self {
        let frame = FiberFrame::new(phi_a);
        let psi_s = frame.projected_angle(s);
        let psi_v = frame.projected_angle(v);
        let h = s + v;
        let (hu, hw) = (h.dot(frame.e_u), h.z);
        let theta_peak = hu.atan2(hw);
        let rho = (hu * hu + hw * hw).sqrt() / h.length();
        let peak_width = (rho * fiber.lobe_width(0.0)).max(1e-6);
        let mut cs = CrossSection {
            fiber,
            s,
            v,
            frame,
            psi_s,
            psi_v,
            theta_peak,
            peak_width,
            panel_widths,
            edges: Vec::new(),
            g: PiecewiseLegendre::default(),
            masking: Masking::Exact,
        };
        cs.sample_g();
        cs
    }

    /// The same cross-section with masking between facets `masking` (the default: exact).
    pub fn with_masking(mut self, masking: Masking) -> Self {
        self.masking = masking;
        self
    }

    /// The parts of `profile` that count: lit and visible ([`Masking::Exact`]), or all of it
    /// ([`Masking::Off`]; facets facing away from either direction have `g = 0` anyway).
    fn visible(&self, profile: &Profile) -> PieceIntervals {
        match self.masking {
            Masking::Exact => profile.lit_and_visible(self.psi_s, self.psi_v),
            Masking::Off => {
                let l = profile.lateral_length;
                PieceIntervals {
                    arc: Some((-profile.theta_a, profile.theta_a)),
                    right: Some((0.0, l)),
                    left: Some((0.0, l)),
                }
            }
        }
    }

    /// `g(θ) = f_fiber(s, v; a(θ)) (s·a)(v·a)` in its two parts ([`FiberParts`]), 0 where either
    /// cosine is not positive.
    #[inline]
    fn g_direct(&self, theta: f64) -> FiberParts {
        let a = self.frame.facet_normal(theta);
        let (sa, va) = (self.s.dot(a), self.v.dot(a));
        if sa <= 0.0 || va <= 0.0 {
            return [0.0, 0.0];
        }
        self.fiber
            .eval_parts_with_normal(self.s, self.v, a)
            .scale(sa * va)
    }

    /// The fiber BRDF at the macro normal in its two parts: the flat limit of every profile.
    #[inline]
    fn flat(&self) -> FiberParts {
        self.fiber
            .eval_parts_with_normal(self.s, self.v, crate::math::Vec3::Z)
    }

    /// The value of `parts` for this fiber: `ζ·parts[0] + ρ0·parts[1]`.
    #[inline]
    pub fn combine(&self, parts: FiberParts) -> f64 {
        self.fiber.combine_parts(parts)
    }

    /// The facing range of `θ` (both cosines positive), within `[−π/2, π/2]`.
    fn facing_range(&self) -> (f64, f64) {
        let lo = (self.psi_s.max(self.psi_v) - FRAC_PI_2).max(-FRAC_PI_2);
        let hi = (self.psi_s.min(self.psi_v) + FRAC_PI_2).min(FRAC_PI_2);
        (lo, hi)
    }

    /// The widest sampling panel: [`MAX_PANEL`] for a single profile; for slope averages
    /// (`COARSE_PANELS`) up to twice that where the lobe is wide enough (`1.5 α`) for 10 nodes to
    /// stay far below the averages' own error.
    fn max_panel(&self) -> f64 {
        if self.panel_widths == COARSE_PANELS {
            (1.5 * self.fiber.lobe_width(0.0)).clamp(MAX_PANEL, 2.0 * MAX_PANEL)
        } else {
            MAX_PANEL
        }
    }

    fn sample_g(&mut self) {
        let (lo, hi) = self.facing_range();
        let (c, w) = (self.theta_peak, self.peak_width);
        // Panels of `panel` widths within ~6 widths of the highlight, then doubling outward.
        let panel = self.panel_widths;
        let n = (6.0 / panel).ceil() as i32;
        let mut edges: Vec<f64> = vec![lo, hi];
        for k in -n..=n {
            edges.push(c + panel * k as f64 * w);
        }
        let mut d = 2.0 * panel * n as f64 * w;
        while d < 4.0 {
            edges.push(c - d);
            edges.push(c + d);
            d *= 2.0;
        }
        // The lobe vanishes at the ends of the facing range through the cosines and the Smith
        // terms, which turn sharply there: grade panels toward both ends.
        for d in [0.005, 0.02, 0.06] {
            edges.push(lo + d);
            edges.push(hi - d);
        }
        // No panel wider than MAX_PANEL: a wide lobe (rough fibers) is not one polynomial.
        panel_edges(&mut edges, lo, hi, self.max_panel());
        let mut g = std::mem::take(&mut self.g);
        g.resample(&edges, |t| self.g_direct(t));
        self.g = g;
        self.edges = edges;
    }

    /// The macro BRDF `f_p` of one profile (Eq. (17) with exact masking; docs/spec.md §2.3).
    ///
    /// `f_p = [∫_arc g dθ + g(θ_a) ℓ_right + g(−θ_a) ℓ_left] / (P s_z v_z)` over the lit-and-visible
    /// sets, `ℓ` their lengths. A profile of zero period (`θ_a = 0`, `L = 0`) is its flat limit,
    /// the fiber BRDF at normal `z`.
    pub fn profile_brdf(&self, profile: &Profile) -> f64 {
        self.combine(self.profile_brdf_parts(profile))
    }

    /// [`profile_brdf`](Self::profile_brdf) in its two parts ([`FiberParts`]).
    pub fn profile_brdf_parts(&self, profile: &Profile) -> FiberParts {
        let period = profile.period();
        // Below this the profile is flat to double precision: use the limit.
        if period < 1e-12 {
            return self.flat();
        }
        let lv = self.visible(profile);
        let sum = self.profile_sum(
            profile,
            &lv,
            |lo, hi| self.arc_integral_exact(lo, hi),
            |t| self.g_direct(t),
        );
        sum.scale(1.0 / (period * self.s.z * self.v.z))
    }

    /// `∫_arc g dθ` over `[lo, hi]` with the exact facet lobe: the sampling panels' Gauss–Legendre
    /// rule on their intersections with the interval (a single profile's accuracy, ~1e-10).
    fn arc_integral_exact(&self, lo: f64, hi: f64) -> FiberParts {
        let rule = crate::math::legendre::panel_rule();
        let mut sum = FiberParts::ZERO;
        for e in self.edges.windows(2) {
            let (a, b) = (e[0].max(lo), e[1].min(hi));
            if b > a {
                sum = sum.add(rule.integrate(a, b, |t| self.g_direct(t)));
            }
        }
        sum
    }

    /// `∫_arc g + g(θ_a) ℓ_right + g(−θ_a) ℓ_left` over the given intervals; `arc` integrates
    /// `g` over an arc interval and `lateral_g` gives `g` at a lateral's normal angle (exact, or
    /// from the interpolant).
    #[inline]
    fn profile_sum(
        &self,
        profile: &Profile,
        lv: &PieceIntervals,
        arc: impl Fn(f64, f64) -> FiberParts,
        lateral_g: impl Fn(f64) -> FiberParts,
    ) -> FiberParts {
        let mut sum = FiberParts::ZERO;
        if let Some((lo, hi)) = lv.arc {
            sum = sum.add(arc(lo, hi));
        }
        let len = |iv: Option<(f64, f64)>| iv.map_or(0.0, |(a, b)| b - a);
        let (lr, ll) = (len(lv.right), len(lv.left));
        if lr > 0.0 {
            sum = sum.add(lateral_g(profile.theta_a).scale(lr));
        }
        if ll > 0.0 {
            sum = sum.add(lateral_g(-profile.theta_a).scale(ll));
        }
        sum
    }

    /// The slope-averaged BRDF `f_θ = ∫ P(θ_a) f_p(θ_a) dθ_a` (Eq. (18); docs/spec.md §2.4) for
    /// laterals of length `lateral_length`, with `nodes` Gauss–Legendre nodes per panel.
    ///
    /// The panels split the integral where the integrand breaks or peaks (docs/spec.md §2.4): at the
    /// masking onsets `θ_a = π/2 − |ψ_s|`, `π/2 − |ψ_v|`, around the lateral highlight
    /// `θ_a = |θ*|` (width `≈ αρ`), and around the mean slope when the distribution is narrow.
    /// The lateral facets read `g` from the interpolant, so a node costs no fiber evaluation.
    /// In the two parts the fiber BRDF is affine in ([`FiberParts`]; [`combine`](Self::combine)
    /// gives the value).
    pub fn slope_average(
        &self,
        slopes: &SlopeDistribution,
        lateral_length: f64,
        nodes: &GaussLegendre,
    ) -> FiberParts {
        if let Some(mu) = slopes.single() {
            return self.profile_brdf_parts(&Profile {
                theta_a: mu,
                lateral_length,
            });
        }
        // θ_a = π/2 is allowed only with L = 0; its weight (∝ cos θ_a) vanishes anyway.
        let top = if lateral_length > 0.0 {
            FRAC_PI_2 * (1.0 - 1e-12)
        } else {
            FRAC_PI_2
        };
        let mut breaks: Vec<f64> = Vec::with_capacity(24);
        breaks.push(FRAC_PI_2 - self.psi_s.abs());
        breaks.push(FRAC_PI_2 - self.psi_v.abs());
        let (c, w) = (self.theta_peak.abs(), self.peak_width);
        for k in [-6.0, -3.0, -1.5, 0.0, 1.5, 3.0, 6.0] {
            breaks.push(c + k * w);
        }
        let (mu, sigma) = (slopes.mean(), slopes.std());
        if sigma < window::NARROW_STD {
            return self.narrow_slope_average(mu, sigma, lateral_length, top, &breaks, nodes);
        }
        if sigma < 0.3 {
            for k in [-6.0, -3.0, -1.5, 0.0, 1.5, 3.0, 6.0] {
                breaks.push(mu + k * sigma);
            }
        }
        panel_edges(&mut breaks, 0.0, top, 0.25 * top);
        let sz_vz = self.s.z * self.v.z;
        let flat = self.flat();
        let integrand = |theta_a: f64| -> FiberParts {
            let profile = Profile {
                theta_a,
                lateral_length,
            };
            let period = profile.period();
            if period < 1e-12 {
                return flat.scale(slopes.density(theta_a));
            }
            let lv = self.visible(&profile);
            // The interpolant of a non-negative lobe can dip below 0 in its far tails: clamp
            // (each part is non-negative).
            let sum = self.profile_sum(
                &profile,
                &lv,
                |lo, hi| self.g.integral(lo, hi).clamp_non_negative(),
                |t| self.g.value(t).clamp_non_negative(),
            );
            sum.scale(slopes.density(theta_a) / (period * sz_vz))
        };
        let mut total = FiberParts::ZERO;
        for b in breaks.windows(2) {
            total = total.add(nodes.integrate(b[0], b[1], integrand));
        }
        total
    }

    /// [`slope_average`](Self::slope_average) for a narrow distribution (`σ <`
    /// [`window::NARROW_STD`]): over the `±8σ` window of `x = (θ_a − μ)/σ`, with weights
    /// `exp(−x²/2) cos θ_a` normalized by their own sum, so that the cost does not depend on `σ`
    /// and the result tends to the single profile `f_p(μ)` as `σ → 0`.
    ///
    /// Each profile reads the exact facet lobe: the laterals `g(±θ_a)` directly, the arc as the
    /// exact integral over the arc interval of the reference slope (the mean, or the window's
    /// end nearest it) corrected by the interpolant over the difference of the intervals — a
    /// correction that vanishes with `σ`, so at `σ → 0` every term is the single profile's.
    fn narrow_slope_average(
        &self,
        mu: f64,
        sigma: f64,
        lateral_length: f64,
        top: f64,
        breaks: &[f64],
        nodes: &GaussLegendre,
    ) -> FiberParts {
        let (lo, hi) = x_window(mu, sigma, top);
        if hi <= lo {
            // μ lies above the largest slope by more than 8σ: all the mass is at `top`.
            return self.profile_brdf_parts(&Profile {
                theta_a: top,
                lateral_length,
            });
        }
        // The reference slope: μ, or the end of the window nearest it.
        let reference = Profile {
            theta_a: mu + sigma * 0.0_f64.clamp(lo, hi),
            lateral_length,
        };
        let ref_arc = self.visible(&reference).arc;
        let ref_arc_integral = ref_arc.map(|(a, b)| self.arc_integral_exact(a, b));
        let arc = |a: f64, b: f64| match (ref_arc, ref_arc_integral) {
            // The interpolant's corrections can overshoot a vanishing lobe: clamp at 0.
            (Some((a0, b0)), Some(i0)) => {
                // Signed: ∫_{b0}^{b} g − ∫_{a0}^{a} g from the interpolant.
                let signed =
                    |x: f64, y: f64| self.g.cumulative(x).add(self.g.cumulative(y).scale(-1.0));
                i0.add(signed(b, b0))
                    .add(signed(a, a0).scale(-1.0))
                    .clamp_non_negative()
            }
            _ => self.arc_integral_exact(a, b),
        };
        let flat = self.flat();
        let f_p = |theta_a: f64| -> FiberParts {
            let profile = Profile {
                theta_a,
                lateral_length,
            };
            let period = profile.period();
            if period < 1e-12 {
                return flat;
            }
            let lv = self.visible(&profile);
            // As `profile_brdf` computes it, so that σ → 0 gives its value to rounding.
            self.profile_sum(&profile, &lv, arc, |t| self.g_direct(t))
                .scale(1.0 / (period * self.s.z * self.v.z))
        };
        let extra = breaks.iter().map(|&b| (b - mu) / sigma);
        let edges = window::edges(lo, hi, nodes.nodes().len(), extra);
        let (mut num, mut den) = (FiberParts::ZERO, 0.0);
        for e in edges.windows(2) {
            num = num.add(nodes.integrate(e[0], e[1], |x| {
                let theta_a = mu + sigma * x;
                f_p(theta_a).scale(window::shape(x) * theta_a.cos())
            }));
            den += nodes.integrate(e[0], e[1], |x| window::shape(x) * (mu + sigma * x).cos());
        }
        num.scale(1.0 / den)
    }
}
