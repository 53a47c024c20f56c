//! A table's arrays and grid as they are, for code that repeats its look-up and sampling
//! elsewhere (the Mitsuba plugin's Dr.Jit code, `crates/woven-py`), and the interpolation alone.
//!
//! Everything [`Table::eval`](super::Table::eval) (outside the exact near-forward region,
//! [`FORWARD_EXACT`](super::FORWARD_EXACT)), [`Table::eval_dyed`](super::Table::eval_dyed),
//! [`Bsdf::pdf`](crate::bsdf::Bsdf::pdf) and [`Table::sample_direction`](super::Table::sample_direction)
//! read is here; `eval.rs`, `grid.rs` and `sampler.rs` define how they read it.

use super::grid::Axis;
use super::{Albedos, Symmetry, Table};
use crate::math::Vec3;

/// A borrowed view of a [`Table`]'s arrays and grid ([`Table::raw`]).
#[derive(Clone, Copy, Debug)]
pub struct Raw<'a> {
    /// The symmetry the table folds queries with.
    pub symmetry: Symmetry,
    /// The polar axis of the axis direction (graded, [`Axis::node`]).
    pub theta: Axis,
    /// The azimuth axis of the axis direction on `[0, π/2]` (one node for isotropic tables).
    pub phi: Axis,
    /// The warped half-vector slope axis `t ∈ [−1, 1]` (`p = tan(K t|t|)`).
    pub t: Axis,
    /// `K` of the slope warp `p = tan(K t|t|)` ([`super::grid::slope_of_t`]).
    pub slope_scale: f64,
    /// `f` at every node ([`Table::values`]).
    pub values: &'a [f32],
    /// `∂f/∂ρ0` at every node, laid out as `values`, for dyeable tables.
    pub body: Option<&'a [f32]>,
    /// `∂f/∂ρ` of dyeable tables (`ħ/π`).
    pub per_interreflection: f64,
    /// The albedos `values` hold, for dyeable tables.
    pub own: Option<Albedos>,
    /// What `∂f/∂ρ` is multiplied by at every node, laid out as `values`, for dyeable tables
    /// averaged over a crown ([`Table::crowned_with`](super::Table::crowned_with)) or a float
    /// ([`Table::tilted`](super::Table::tilted)); `None`: 1.
    pub crown: Option<&'a [f32]>,
    /// Per incidence node (`iθ·n_φ + iφ`): the CDF over the `n_h − 1` rows, `n_h` entries.
    pub marginal: &'a [f32],
    /// Per incidence node and row: the CDF over the row's cells, `n_h` entries.
    pub conditional: &'a [f32],
    /// The node weight floor `ε` ([`super::HORIZON_WEIGHT`]).
    pub horizon_weight: f64,
    /// The other direction's polar angle, degrees, from which azimuth interpolation starts
    /// turning the pair, and from which it turns it rigidly.
    pub turn_deg: (f64, f64),
    /// Whether near-forward pairs are evaluated by the exact model
    /// ([`FORWARD_EXACT`](super::FORWARD_EXACT)): code that only interpolates matches
    /// [`Table::eval_interpolated`] there, not [`Table::eval`].
    pub forward_exact: bool,
}

impl Table {
    /// The table's arrays and grid.
    pub fn raw(&self) -> Raw<'_> {
        let (marginal, conditional) = self.sampler.cdfs();
        Raw {
            symmetry: self.symmetry,
            theta: self.theta,
            phi: self.phi,
            t: self.t,
            slope_scale: super::grid::K,
            values: &self.values,
            body: self.colour.as_ref().map(|c| c.body.as_slice()),
            per_interreflection: self.colour.as_ref().map_or(0.0, |c| c.per_interreflection),
            own: self.colour.as_ref().map(|c| c.own),
            crown: self.colour.as_ref().and_then(|c| c.crown.as_deref()),
            marginal,
            conditional,
            horizon_weight: super::HORIZON_WEIGHT,
            turn_deg: (super::eval::TURN_FROM_DEG, super::eval::TURN_FULL_DEG),
            forward_exact: self.exact.is_some(),
        }
    }

    /// [`eval`](Self::eval) by interpolation everywhere, the exact near-forward region
    /// ([`FORWARD_EXACT`](super::FORWARD_EXACT)) included; the same as `eval` outside it.
    pub fn eval_interpolated(&self, s: Vec3, v: Vec3) -> f64 {
        self.eval_arrays(s, v, [&self.values])[0].max(0.0)
    }
}
