//! A yarn's table averaged over a round crown: the BRDF of a resolved yarn across its width
//! (docs/model.md §8, "The relief").
//!
//! Across its width a resolved yarn's top is an arc of half-angle `α`, and side by side the
//! yarns' crowns are a row of touching arcs: the paper's profile (docs/model.md §2.1) with
//! `θ_a = α` and no laterals, one level up. Where its normal leans by `θ` the surface is rolled
//! about the yarn's axis (`x`) by `θ`. Per unit of cloth, the crowned yarn's BRDF is the mean
//! over the period `P = 2 sin α` of the rolled facets' BRDF over the part of the arc both lit
//! from `s` and seen from `v` (the profile's exact intervals for the projected angles
//! `ψ = atan2(d_y, d_z)`, docs/model.md §2.2):
//!
//! ```text
//! f_c(s, v) = (1/P) ∫ f(R_θ s, R_θ v) cos θ′s cos θ′v / (cos θs cos θv) dθ   over lit ∩ seen
//! ```
//!
//! (`R_θ` the roll into the facet's frame), by [`CROWN_NODES`]-point Gauss–Legendre. Shadows of
//! the relief's hills and of the crossing yarns are not in it: the relief's ratio carries them. The crown keeps the woven symmetries (mirrors in `x` and `y`), not
//! isotropy: an isotropic yarn's crowned table has the mirror grid.
//!
//! The average is linear in `f`, so a dyeable table stays dyeable: `∂f/∂ρ0` is the same average
//! of the base's, and the interreflection term `ħρ/π`, constant in the base, becomes
//! `ħρ/π · g(s, v)`, `g` the average of 1, a third node array.

use super::build::fill;
use super::grid::Axis;
use super::{Colour, Half, Table, TableOptions};
use crate::math::quadrature::GaussLegendre;
use crate::math::Vec3;
use crate::progress::{Progress, Silent};
use crate::yarn::profile::Profile;
use std::f64::consts::FRAC_PI_2;

/// Gauss–Legendre nodes across the crown.
pub const CROWN_NODES: usize = 12;

/// `d` in the frame of the crown's facet rolled by `(sin r, cos r)` about `x` (its normal
/// leaning toward `+y`).
#[inline]
pub(crate) fn rolled(d: Vec3, (s, c): (f64, f64)) -> Vec3 {
    Vec3::new(d.x, c * d.y - s * d.z, s * d.y + c * d.z)
}

/// `f_c(s, v)` (module docs) of the `K` values `f(s′, v′)` gives in a facet's frame, with `g`
/// (the same average of 1).
#[inline]
fn average<const K: usize>(
    crown: &Crown,
    s: Vec3,
    v: Vec3,
    f: impl Fn(Vec3, Vec3) -> [f64; K],
) -> ([f64; K], f64) {
    let mut sum = [0.0; K];
    let mut g = 0.0;
    if s.z <= 0.0 || v.z <= 0.0 {
        return (sum, g);
    }
    let Some(profile) = crown.profile else {
        return (f(s, v), 1.0);
    };
    let both = profile.lit_and_visible(s.y.atan2(s.z), v.y.atan2(v.z));
    let Some((lo, hi)) = both.arc else {
        return (sum, g);
    };
    // Per unit of projected width (the period, 2 sin α), over the arc's angle.
    let scale = 0.5 * (hi - lo) / (crown.period * s.z * v.z);
    for (&x, &w) in crown.rule.nodes().iter().zip(crown.rule.weights()) {
        let sc = (0.5 * (lo + hi) + 0.5 * (hi - lo) * x).sin_cos();
        let (ts, tv) = (rolled(s, sc), rolled(v, sc));
        if ts.z <= 0.0 || tv.z <= 0.0 {
            continue;
        }
        let k = w * scale * ts.z * tv.z;
        for (acc, x) in sum.iter_mut().zip(f(ts, tv)) {
            *acc += k * x;
        }
        g += k;
    }
    (sum, g)
}

/// A crown: its cross-section, a row of touching arcs, and the rule across it.
struct Crown {
    /// `None` for no crown (half-angle 0): the base itself.
    profile: Option<Profile>,
    period: f64,
    rule: GaussLegendre,
}

impl Crown {
    fn new(half_angle: f64) -> Crown {
        let profile = (half_angle > 1e-9)
            .then(|| Profile::new(half_angle, 0.0).expect("a crown's half-angle is in (0, π/2)"));
        Crown {
            profile,
            period: profile.map_or(0.0, |p| p.period()),
            rule: GaussLegendre::new(CROWN_NODES),
        }
    }
}

impl Table {
    /// This table (of a yarn as the paper has it) averaged over the crown of
    /// `options.crown_deg`, on `options`' grid: what [`Table::build`] gives for those options,
    /// without evaluating the model again. `progress` is asked between rows whether to stop.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) for invalid options, a
    /// `crown_deg` of 0, or a table that is crowned already;
    /// [`Error::Cancelled`](crate::Error::Cancelled) when `progress` asked to stop.
    pub fn crowned_with(
        &self,
        options: &TableOptions,
        progress: &dyn Progress,
    ) -> crate::Result<Table> {
        options.validate()?;
        if options.crown_deg <= 0.0 {
            return Err(crate::Error::invalid(
                "crown_deg",
                options.crown_deg,
                format!("a half-angle in (0, {}]", super::options::MAX_CROWN_DEG),
            ));
        }
        if self.crown_deg > 0.0 {
            return Err(crate::Error::invalid(
                "table",
                format!("a table crowned at {}°", self.crown_deg),
                "a table of a yarn without a crown",
            ));
        }
        self.crowned_until(options.crown_deg, options, progress)
    }

    /// This table averaged over a round crown of half-angle `crown_deg` (degrees, in
    /// `(0, MAX_CROWN_DEG]`): the resolved yarn's BRDF (module docs), on the mirror grid of
    /// `options` (this table's polar axis, `n_phi` azimuths, `n_h` half-vector nodes). Dyeable
    /// when this table is. [`Table::build`] calls it when [`TableOptions::crown_deg`] is set.
    pub(crate) fn crowned(&self, crown_deg: f64, options: &TableOptions) -> Table {
        match self.crowned_until(crown_deg, options, crate::progress::NONE) {
            Ok(table) => table,
            Err(_) => unreachable!("a progress that never asks to stop"),
        }
    }

    /// As [`crowned`](Self::crowned), asking `progress` between rows whether to stop (its
    /// updates are not sent: the crown is a last step after the plain table's build, whose bar
    /// has ended).
    ///
    /// # Errors
    /// [`Error::Cancelled`](crate::Error::Cancelled) when `progress` asked to stop.
    pub(crate) fn crowned_until(
        &self,
        crown_deg: f64,
        options: &TableOptions,
        progress: &dyn Progress,
    ) -> crate::Result<Table> {
        let crown = Crown::new(crown_deg.to_radians());
        let phi = Axis::uniform(0.0, FRAC_PI_2, options.n_phi);
        let (theta, t) = (self.theta, Axis::uniform(-1.0, 1.0, options.n_h));
        let quiet = Silent(progress);
        let (values, colour) = match &self.colour {
            Some(colour) => {
                let base = [self.values.as_slice(), colour.body.as_slice()];
                let [values, body, g] = fill::<3, _>(theta, phi, t, &quiet, |half, a| {
                    let crown = &crown;
                    move |o| {
                        let (s, v) = Half::join(half, a, o);
                        let ([f, body], g) =
                            average(crown, s, v, |ts, tv| self.eval_arrays(ts, tv, base));
                        [f.max(0.0), body, g]
                    }
                })?;
                let colour = Colour {
                    body,
                    crown: Some(g),
                    ..colour.clone()
                };
                (values, Some(colour))
            }
            None => {
                let [values] = fill::<1, _>(theta, phi, t, &quiet, |half, a| {
                    let crown = &crown;
                    move |o| {
                        let (s, v) = Half::join(half, a, o);
                        let ([f], _) = average(crown, s, v, |ts, tv| [self.eval(ts, tv)]);
                        [f]
                    }
                })?;
                (values, None)
            }
        };
        Ok(self.derived((theta, phi, t), values, colour, crown_deg))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::table::{Albedos, TableOptions};

    const OPTIONS: TableOptions = TableOptions {
        n_theta: 24,
        theta_max_deg: 89.9,
        n_phi: 12,
        n_h: 61,
        n_h_isotropic: 61,
        azimuth_nodes: 180,
        threads: 0,
        colour: true,
        exact_regions: false,
        crown_deg: 0.0,
    };

    /// The silk's plain table on [`OPTIONS`]' grid, built once for the module's tests.
    fn silk() -> &'static Table {
        static SILK: std::sync::OnceLock<Table> = std::sync::OnceLock::new();
        SILK.get_or_init(|| {
            let m = Material::preset("silk").unwrap().yarn_family();
            Table::build(&m.build(550.0).unwrap(), &m, &OPTIONS, &|_, _| {}).unwrap()
        })
    }

    /// No crown is the base table; a crown is the mean of the base's rolled look-ups, at any
    /// dye, over 200 uniform pairs (within the interpolation of the crowned grid).
    #[test]
    fn a_crowned_table_is_its_base_rolled_and_averaged() {
        let base = silk();
        let flat = base.crowned(0.0, &OPTIONS);
        let crowned = base.crowned(30.0, &OPTIONS);
        assert_eq!((flat.crown_deg(), crowned.crown_deg()), (0.0, 30.0));
        let dyes = [
            Albedos::of(&Material::preset("silk").unwrap()),
            Albedos {
                diffuse: 0.05,
                interreflection: 0.01,
            },
        ];
        let (mut worst_flat, mut worst_crown, mut scale) = (0.0f64, 0.0f64, 0.0f64);
        for (s, v) in crate::table::report::uniform_pairs(200, 11) {
            let b = base.eval_dyed(s, v, &dyes);
            let f = flat.eval_dyed(s, v, &dyes);
            let c = crowned.eval_dyed(s, v, &dyes);
            let crown = Crown::new(30f64.to_radians());
            let (want, _) = average(&crown, s, v, |ts, tv| base.eval_dyed(ts, tv, &dyes));
            for k in 0..2 {
                scale = scale.max(b[k]);
                worst_flat = worst_flat.max((f[k] - b[k]).abs());
                worst_crown = worst_crown.max((c[k] - want[k]).abs());
            }
        }
        eprintln!("flat {worst_flat:.5} crowned {worst_crown:.5} of {scale:.4}");
        // Re-tabulated on the same grid, a table reads back within its interpolation error
        // (measured: 1.1 % of the largest value for the silk, 0.6 % for the belt cloth); the
        // crown's masking onsets add some near the horizon (4.2 %, 3.4 %).
        assert!(worst_flat <= 0.015 * scale, "flat {worst_flat} of {scale}");
        assert!(
            worst_crown <= 0.05 * scale,
            "crowned {worst_crown} of {scale}"
        );
    }

    /// A crowned table is what the crown stage of `Table::build` gives from its base, and a
    /// `.wtab` file keeps it exactly: its crown, and the interreflection factor it dyes with.
    #[test]
    fn a_crowned_table_is_built_once_and_saved_whole() {
        let base = silk();
        let options = TableOptions {
            crown_deg: 30.0,
            ..OPTIONS
        };
        let derived = base.crowned_with(&options, crate::progress::NONE).unwrap();
        let read = Table::from_bytes(&derived.to_bytes(), "test").unwrap();
        assert_eq!(read.crown_deg(), 30.0);
        let dyes = [Albedos {
            diffuse: 0.2,
            interreflection: 0.3,
        }];
        for (s, v) in crate::table::report::uniform_pairs(50, 3) {
            assert_eq!(derived.eval_dyed(s, v, &dyes), read.eval_dyed(s, v, &dyes));
        }
        // Not twice, and not without a crown.
        assert!(derived
            .crowned_with(&options, crate::progress::NONE)
            .is_err());
        assert!(base.crowned_with(&OPTIONS, crate::progress::NONE).is_err());
    }
}
