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
use super::{Colour, Half, Symmetry, Table};
use crate::math::quadrature::GaussLegendre;
use crate::math::Vec3;
use crate::yarn::profile::Profile;
use std::f64::consts::FRAC_PI_2;

/// Gauss–Legendre nodes across the crown.
pub const CROWN_NODES: usize = 12;

/// Azimuth nodes of a crowned table whose base is isotropic (one azimuth).
pub const ISOTROPIC_BASE_PHI: usize = 8;

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
    /// This table averaged over a round crown of half-angle `half_angle` (radians, in
    /// `[0, π/2)`): the resolved yarn's BRDF (module docs), on this table's grid (an isotropic
    /// table's on [`ISOTROPIC_BASE_PHI`] azimuths). Dyeable when this table is. The result is for
    /// rendering only: it is not saved (its interreflection term is a node array no file holds).
    pub fn crowned(&self, half_angle: f64) -> Table {
        let crown = Crown::new(half_angle);
        let phi = match self.symmetry {
            Symmetry::Isotropic => Axis::uniform(0.0, FRAC_PI_2, ISOTROPIC_BASE_PHI),
            Symmetry::Mirror => self.phi,
        };
        let (theta, t) = (self.theta, self.t);
        let quiet = |_: usize, _: usize| {};
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
                });
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
                });
                (values, None)
            }
        };
        Table::assemble(
            Symmetry::Mirror,
            theta,
            phi,
            t,
            values,
            self.provenance.clone(),
            self.wavelength_nm,
            None,
            colour,
            None,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::table::{Albedos, TableOptions};

    fn table(name: &str) -> Table {
        let m = Material::preset(name).unwrap().yarn_family();
        let options = TableOptions {
            n_theta: 24,
            n_phi: 12,
            n_h: 61,
            colour: true,
            exact_regions: false,
            ..TableOptions::default()
        };
        Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}).unwrap()
    }

    /// No crown is the base table; a crown is the mean of the base's rolled look-ups, at any
    /// dye (within the interpolation of the crowned grid).
    #[test]
    fn a_crowned_table_is_its_base_rolled_and_averaged() {
        let base = table("belt-cloth");
        let flat = base.crowned(0.0);
        let crowned = base.crowned(30f64.to_radians());
        let dyes = [
            Albedos::of(&Material::preset("belt-cloth").unwrap()),
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
            if (c[0] - want[0]).abs() > 0.015 {
                eprintln!(
                    "s {s:?} v {v:?}: base {:.4} crowned {:.4} want {:.4} flat {:.4}",
                    b[0], c[0], want[0], f[0]
                );
            }
            for k in 0..2 {
                scale = scale.max(b[k]);
                worst_flat = worst_flat.max((f[k] - b[k]).abs());
                worst_crown = worst_crown.max((c[k] - want[k]).abs());
            }
        }
        eprintln!("flat {worst_flat:.5} crowned {worst_crown:.5} of {scale:.4}");
        assert!(worst_flat <= 0.03 * scale, "flat {worst_flat} of {scale}");
        assert!(
            worst_crown <= 0.03 * scale,
            "crowned {worst_crown} of {scale}"
        );
    }
}
