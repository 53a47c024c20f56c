//! The cloth: two threads' tangent curves, the shading model and its normalization (paper §5,
//! Eqs. (9) and (14)), as a BRDF in the cloth frame (docs/microcylinder.md §4).

use super::curve::{CurveNode, CurveRule};
use super::frame::{PairAngles, TangentFrame};
use super::masking::{masking, reweight};
use super::scattering::{scattering, ScatteringParams};
use super::thread::Thread;
use crate::color::Rgb;
use crate::math::Vec3;

/// Gauss–Legendre points per panel of a varying segment of a tangent curve.
pub const GAUSS_NODES_PER_PANEL: usize = 6;

/// The widest panel of a varying segment, in units of the thread's `γ_s`: the surface lobe is a
/// Gaussian of width `γ_s` in `θ_h`, and `|dθ_h/dα| ≤ 1`, so a panel spans at most two standard
/// deviations of it (docs/microcylinder.md §5: relative error below 1e-4 at every preset).
pub const PANEL_WIDTH_OVER_GAMMA_S: f64 = 2.0;

/// The default quadrature of a thread's curve (docs/microcylinder.md §5).
pub fn default_rule(thread: &Thread) -> CurveRule {
    CurveRule::Gauss {
        nodes: GAUSS_NODES_PER_PANEL,
        panel_width: PANEL_WIDTH_OVER_GAMMA_S * thread.gamma_s,
    }
}

/// A thread made ready to evaluate: its tangent frames and their weights (summing to 1).
#[derive(Clone, Debug)]
pub(crate) struct PreparedThread {
    pub params: ScatteringParams,
    pub coverage: f64,
    pub frames: Vec<TangentFrame>,
    pub weights: Vec<f64>,
    /// The running sums of `weights` (for picking a tangent by length).
    pub cdf: Vec<f64>,
}

impl PreparedThread {
    pub fn new(index: usize, thread: &Thread, rule: CurveRule) -> PreparedThread {
        let nodes: Vec<CurveNode> = thread.tangents.nodes(rule);
        let frames = nodes
            .iter()
            .map(|n| TangentFrame::new(index, n.alpha))
            .collect();
        let weights: Vec<f64> = nodes.iter().map(|n| n.weight).collect();
        let mut acc = 0.0;
        let cdf = weights
            .iter()
            .map(|w| {
                acc += w;
                acc
            })
            .collect();
        PreparedThread {
            params: thread.scattering_params(),
            coverage: thread.coverage,
            frames,
            weights,
            cdf,
        }
    }

    /// One thread's share of the shading model: `(S, P̄)` with
    /// `S = ⟨f_s(t, ω_i, ω_r) M(t, ω_i, ω_r) P(t, ω_i, ω_r) cos θ_i⟩_t` and
    /// `P̄ = ⟨P(t, ω_i, ω_r)⟩_t`, `⟨·⟩_t` the length-weighted average over the thread's tangents
    /// (the paper's `(1/N_j) Σ_t`).
    ///
    /// Implements the thread radiance `L_r,j` of Eq. (9) of the paper (the integrand, with
    /// shadowing–masking and reweighting) and one thread's term of `Q` in Eq. (14).
    #[inline]
    pub fn sums(&self, wi: Vec3, wo: Vec3) -> (Rgb, f64) {
        let mut s = Rgb::BLACK;
        let mut pbar = 0.0;
        for (frame, &w) in self.frames.iter().zip(&self.weights) {
            let i = frame.angles(wi);
            let r = frame.angles(wo);
            let p = reweight(&i, &r);
            pbar += w * p;
            // M = 0 where either direction faces away from n_t (M(t, ω) = max(cos φ, 0) = 0).
            if p == 0.0 || i.cos_n <= 0.0 || r.cos_n <= 0.0 {
                continue; // hidden or shadowed tangent: no radiance, f_s not needed
            }
            let pair = PairAngles::new(&i, &r);
            let m = masking(&i, &r, pair.phi_d);
            s += scattering(&self.params, &i, &r, &pair) * (w * m * p * i.cos_theta);
        }
        (s, pbar)
    }
}

/// The shading model's BRDF without the energy guard: with `S_j`, `P̄_j` of each thread
/// ([`PreparedThread::sums`]) and the gap `g = 1 − a_1 − a_2`,
/// `f(ω_i, ω_r) = (a_1 S_1 + a_2 S_2) / (Q cos θ_i)`, `Q = a_1 P̄_1 + a_2 P̄_2 + g cos θ_r`,
/// `cos θ_i`, `cos θ_r` the cloth-normal cosines.
///
/// Implements Eqs. (9) and (14) of the paper, read as the outgoing radiance
/// `L_r(ω_r) = ∫ L_i(ω_i) (a_1 S_1 + a_2 S_2)/Q dω_i`, whose BRDF divides by `cos θ_i`
/// (docs/microcylinder.md §4 gives the reading and its reasons). 0 below the horizon.
pub(crate) fn shading_model(threads: &[PreparedThread; 2], gap: f64, wi: Vec3, wo: Vec3) -> Rgb {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return Rgb::BLACK;
    }
    let (s1, p1) = threads[0].sums(wi, wo);
    let (s2, p2) = threads[1].sums(wi, wo);
    let (a1, a2) = (threads[0].coverage, threads[1].coverage);
    let q = a1 * p1 + a2 * p2 + gap * wo.z;
    if q <= 0.0 {
        return Rgb::BLACK; // no thread seen and no gap: nothing reflects toward ω_r
    }
    (s1 * a1 + s2 * a2) * (1.0 / (q * wi.z))
}
