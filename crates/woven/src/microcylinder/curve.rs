//! A thread's tangent curve (paper §5, Table II): the tangent's tilt along the thread, sampled
//! uniformly along its length, and its quadrature.
//!
//! Control points `α_0 … α_{n−1}` (radians) with segment lengths `ℓ_0 … ℓ_{n−2}`: along segment
//! `k` the tilt runs linearly from `α_k` to `α_{k+1}` over a length `ℓ_k`; `ℓ_k = 0` is a jump and
//! contributes nothing. A thread's average over its tangents (the paper's `(1/N_j) Σ_t`, with
//! tangents sampled uniformly along the thread) is the length-weighted integral
//! `(1/L) Σ_k ∫_0^{ℓ_k} h(α(s)) ds`, `L = Σ ℓ_k`. It is integrated by composite Gauss–Legendre on
//! each nonzero segment (docs/microcylinder.md §5 gives the rule's convergence); a constant
//! segment is exact with one node.

use crate::error::{Error, Result};
use crate::math::quadrature::GaussLegendre;
use std::f64::consts::FRAC_PI_2;

/// The longest a thread's curve may be, in control points (a guard against runaway input).
pub const MAX_CONTROL_POINTS: usize = 1024;

/// A thread's tangent curve: validated control points and segment lengths.
#[derive(Clone, Debug, PartialEq)]
pub struct TangentCurve {
    offsets: Vec<f64>,
    lengths: Vec<f64>,
}

/// One node of a curve's quadrature: a tilt and its weight (the weights of a curve sum to 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveNode {
    /// The tangent's tilt `α`, radians.
    pub alpha: f64,
    /// The node's share of the thread's length.
    pub weight: f64,
}

/// How a curve is integrated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CurveRule {
    /// Composite Gauss–Legendre: each varying segment is cut into panels no wider (in tilt) than
    /// `panel_width` radians, each integrated with `nodes` points; a constant segment, one node.
    Gauss {
        /// Points per panel (≥ 1).
        nodes: usize,
        /// The widest a panel may be, radians (> 0).
        panel_width: f64,
    },
    /// The brute-force reference: `n` points at the midpoints of `n` equal steps of the
    /// thread's total length (jumps skipped).
    Midpoint {
        /// Points along the whole thread (≥ 1).
        n: usize,
    },
}

impl TangentCurve {
    /// A curve from control points `offsets_rad` (radians, each in `[−π/2, π/2]`) and the
    /// `offsets_rad.len() − 1` segment `lengths` between them (each finite and ≥ 0, at least
    /// one > 0). A single control point is a straight thread: pass no lengths.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `tangent_offsets` or `tangent_lengths` (with the index
    /// of the offending entry), its value and the valid range.
    ///
    /// ```
    /// use woven::microcylinder::TangentCurve;
    /// let d = std::f64::consts::PI / 180.0;
    /// assert!(TangentCurve::new(&[-25.0 * d, 25.0 * d], &[1.0]).is_ok());
    /// assert!(TangentCurve::new(&[-25.0 * d, 25.0 * d], &[1.0, 2.0]).is_err());
    /// ```
    pub fn new(offsets_rad: &[f64], lengths: &[f64]) -> Result<TangentCurve> {
        let n = offsets_rad.len();
        if n == 0 || n > MAX_CONTROL_POINTS {
            return Err(Error::invalid(
                "tangent_offsets",
                format!("{n} control points"),
                format!("1 to {MAX_CONTROL_POINTS} control points"),
            ));
        }
        for (k, &a) in offsets_rad.iter().enumerate() {
            if !(a.is_finite() && a.abs() <= FRAC_PI_2 + 1e-12) {
                return Err(Error::invalid(
                    format!("tangent_offsets[{k}]"),
                    a,
                    "an angle in [−π/2, π/2] radians ([−90°, 90°])",
                ));
            }
        }
        let (offsets, lengths) = if n == 1 {
            if !lengths.is_empty() {
                return Err(Error::invalid(
                    "tangent_lengths",
                    format!("{lengths:?}"),
                    "no lengths for a single control point",
                ));
            }
            (vec![offsets_rad[0]; 2], vec![1.0])
        } else {
            if lengths.len() != n - 1 {
                return Err(Error::invalid(
                    "tangent_lengths",
                    format!("{} lengths", lengths.len()),
                    format!("{} lengths, one per segment between {n} offsets", n - 1),
                ));
            }
            for (k, &l) in lengths.iter().enumerate() {
                if !(l.is_finite() && (0.0..=1e6).contains(&l)) {
                    return Err(Error::invalid(
                        format!("tangent_lengths[{k}]"),
                        l,
                        "a length in [0, 1e6] (0 marks a jump)",
                    ));
                }
            }
            if lengths.iter().all(|&l| l == 0.0) {
                return Err(Error::invalid(
                    "tangent_lengths",
                    format!("{lengths:?}"),
                    "at least one segment of nonzero length",
                ));
            }
            (offsets_rad.to_vec(), lengths.to_vec())
        };
        Ok(TangentCurve { offsets, lengths })
    }

    /// The control points, radians (a straight thread's one point is stored twice).
    pub fn offsets(&self) -> &[f64] {
        &self.offsets
    }

    /// The segment lengths (`offsets().len() − 1` of them; 0 is a jump).
    pub fn lengths(&self) -> &[f64] {
        &self.lengths
    }

    /// The thread's total length `L = Σ ℓ_k`.
    pub fn total_length(&self) -> f64 {
        self.lengths.iter().sum()
    }

    /// The tilt at arc length `s ∈ [0, L]` along the thread (jumps skipped).
    pub fn alpha_at(&self, s: f64) -> f64 {
        let mut start = 0.0;
        for (k, &l) in self.lengths.iter().enumerate() {
            if l > 0.0 && s <= start + l {
                let f = ((s - start) / l).clamp(0.0, 1.0);
                return self.offsets[k] + f * (self.offsets[k + 1] - self.offsets[k]);
            }
            start += l;
        }
        // s past the end (rounding): the last nonzero segment's end.
        let k = self.lengths.iter().rposition(|&l| l > 0.0).unwrap_or(0);
        self.offsets[k + 1]
    }

    /// The quadrature nodes of the length-weighted average over the curve by `rule`; the
    /// weights sum to 1.
    pub fn nodes(&self, rule: CurveRule) -> Vec<CurveNode> {
        let total = self.total_length();
        let mut out = Vec::new();
        match rule {
            CurveRule::Gauss { nodes, panel_width } => {
                debug_assert!(nodes >= 1 && panel_width > 0.0);
                let gl = GaussLegendre::new(nodes.max(1));
                for (k, &l) in self.lengths.iter().enumerate() {
                    if l == 0.0 {
                        continue; // a jump: no thread between these control points
                    }
                    let (a0, a1) = (self.offsets[k], self.offsets[k + 1]);
                    if a0 == a1 {
                        // A constant tilt: the integrand is constant along the segment.
                        out.push(CurveNode {
                            alpha: a0,
                            weight: l / total,
                        });
                        continue;
                    }
                    let panels = ((a1 - a0).abs() / panel_width).ceil().max(1.0) as usize;
                    for p in 0..panels {
                        let (f0, f1) = (p as f64 / panels as f64, (p + 1) as f64 / panels as f64);
                        for (x, w) in gl.nodes().iter().zip(gl.weights()) {
                            // Node on [f0, f1] of the segment's fraction; weight w/2 of its length.
                            let f = f0 + (f1 - f0) * 0.5 * (x + 1.0);
                            out.push(CurveNode {
                                alpha: a0 + f * (a1 - a0),
                                weight: l / total * (f1 - f0) * 0.5 * w,
                            });
                        }
                    }
                }
            }
            CurveRule::Midpoint { n } => {
                let n = n.max(1);
                for j in 0..n {
                    out.push(CurveNode {
                        alpha: self.alpha_at((j as f64 + 0.5) / n as f64 * total),
                        weight: 1.0 / n as f64,
                    });
                }
            }
        }
        out
    }
}
