//! The data behind the paper's figures, computed from the model and kept apart from drawing so
//! that tests can check what each figure claims. Figures 8–10 (the cloth presets on the virtual
//! goniometer) are in [`cloth`]; the BRDF over the view hemisphere (`woven plot hemisphere`) in
//! [`hemisphere`].
//!
//! Figures 3–5 of the paper (docs/spec.md §5) show planar fiber surfaces (the rough limit, Eq. (16'),
//! docs/spec.md §1.3) with `σ_h/τ = 0.05` unless varied, as the reflected radiance against the view
//! direction in a vertical plane through the normal. The paper gives neither the refractive index
//! nor the diffuse albedo: we take `η = 1.6` (polyester), `ρ0 = 0` and the `paper`
//! normalization, and every figure says so.
//!
//! The plotted quantity is `L/I0 = f · cos θi` (sr⁻¹): the radiance reflected toward the viewer
//! for a beam of unit irradiance normal to itself — what the paper's radiance formulas give and
//! what a goniometer with a fixed lamp records. The paper's claims hold for it as for `f` alone
//! (the tests below check them on the curves as drawn).

use crate::fiber::{FiberParams, Normalization};
use crate::material::Material;
use crate::{Model, Result, Vec3};
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, FRAC_PI_4, FRAC_PI_6, PI};

pub mod cloth;
pub mod hemisphere;
pub mod words;

/// Refractive index assumed for the paper's fiber surfaces (polyester; the paper gives none).
pub const ETA: f64 = 1.6;
/// Diffuse albedo `ρ0` assumed for the paper's fiber surfaces (the paper gives none).
pub const DIFFUSE: f64 = 0.0;
/// Roughness `σ_h/τ` of Figs. 3 and 5.
pub const ROUGHNESS: f64 = 0.05;
/// Wavelength of the figures, nm (only the Fresnel term would change with it).
pub const WAVELENGTH_NM: f64 = 550.0;
/// Step of the view-angle grid, degrees: the narrowest lobe (`σ_h/τ = 0.05`) is ~10° wide.
pub const VIEW_STEP_DEG: f64 = 0.25;

/// The figures this module can compute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FigureId {
    /// Fig. 3: incidence θi = π/6, π/4, π/3.
    Fig3,
    /// Fig. 4: roughness σh/τ from 0.5 to 0.05 at θi = π/4.
    Fig4,
    /// Fig. 5: viewer azimuth φr − φi = π, 15π/16, 11π/12 at θi = π/4.
    Fig5,
    /// Fig. 8: polyester sateen on the virtual goniometer.
    Fig8,
    /// Fig. 9: belt cloth on the virtual goniometer.
    Fig9,
    /// Fig. 10: silk on the virtual goniometer.
    Fig10,
}

/// How the y axis should be scaled to show what a figure is about.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum YScale {
    /// Linear from 0.
    Linear,
    /// Logarithmic, values below `floor` drawn at the floor.
    Log {
        /// The bottom of the axis.
        floor: f64,
    },
}

/// Where a figure's legend goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LegendCorner {
    /// The upper left corner of the plot.
    UpperLeft,
    /// The upper right corner of the plot.
    UpperRight,
}

/// One curve: its legend label and its `(x, y)` points.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text naming the curve's parameter.
    pub label: String,
    /// The points, `x` increasing.
    pub points: Vec<(f64, f64)>,
    /// The colour's index in the palette; `None`: the curve's position in the figure.
    pub color: Option<usize>,
    /// A comparison curve: drawn dashed, left out of the y range (and cut where it leaves it).
    pub reference: bool,
    /// Line width relative to the figure's (wider lines under narrower ones keep coinciding
    /// curves visible).
    pub width: f64,
}

impl Series {
    /// A model curve, coloured by its position.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.into(),
            points,
            color: None,
            reference: false,
            width: 1.0,
        }
    }
}

#[cfg(test)]
impl Series {
    /// The `y` values, in order.
    pub fn ys(&self) -> Vec<f64> {
        self.points.iter().map(|p| p.1).collect()
    }

    /// The point with the largest `y`.
    pub fn peak(&self) -> (f64, f64) {
        self.points
            .iter()
            .copied()
            .fold((f64::NAN, f64::NEG_INFINITY), |best, p| {
                if p.1 > best.1 {
                    p
                } else {
                    best
                }
            })
    }

    /// `y` at the grid point nearest `x`.
    pub fn at(&self, x: f64) -> f64 {
        self.points
            .iter()
            .min_by(|a, b| (a.0 - x).abs().total_cmp(&(b.0 - x).abs()))
            .map_or(f64::NAN, |p| p.1)
    }
}

/// A figure's data and its words.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Title line.
    pub title: String,
    /// Caption lines under the plot: the setting and what was assumed.
    pub caption: Vec<String>,
    /// x-axis label, with unit.
    pub x_label: String,
    /// y-axis label, with unit.
    pub y_label: String,
    /// Default y scale.
    pub y_scale: YScale,
    /// The x axis range.
    pub x_range: (f64, f64),
    /// About how many x tick labels to draw.
    pub x_ticks: usize,
    /// Where the legend goes.
    pub legend: LegendCorner,
    /// The curves, in legend order.
    pub series: Vec<Series>,
}

/// The x-axis label shared by Figs. 3–5.
const VIEW_ANGLE_LABEL: &str =
    "view angle θr (degrees); negative: on the light's side, positive: on the specular side";
/// The y-axis label shared by Figs. 3–5.
const RADIANCE_LABEL: &str = "reflected radiance for unit irradiance, L/I0 = f·cos θi (sr⁻¹)";

/// Computes a figure's data.
pub fn figure(id: FigureId) -> Result<Figure> {
    match id {
        FigureId::Fig3 => fig3(),
        FigureId::Fig4 => fig4(),
        FigureId::Fig5 => fig5(),
        FigureId::Fig8 | FigureId::Fig9 | FigureId::Fig10 => {
            cloth::figure(id, cloth::DRAW_TILT_STEP_DEG)
        }
    }
}

/// Fig. 3: reflection against view direction for θi = π/6, π/4, π/3 (`σ_h/τ = 0.05`).
/// The paper: the reflected intensity rises with θi (Fresnel and geometry).
pub fn fig3() -> Result<Figure> {
    let model = planar_model(ROUGHNESS)?;
    let series = [(FRAC_PI_6, "π/6"), (FRAC_PI_4, "π/4"), (FRAC_PI_3, "π/3")]
        .iter()
        .map(|&(theta_i, name)| {
            Series::new(
                format!("θi = {name} ({:.0}°)", theta_i.to_degrees()),
                plane_curve(&model, theta_i, PI),
            )
        })
        .collect();
    Ok(Figure {
        title: "Fig. 3 — reflection against view direction for three angles of incidence".into(),
        caption: caption(&format!("σh/τ = {ROUGHNESS}, in the plane of incidence")),
        x_label: VIEW_ANGLE_LABEL.into(),
        y_label: RADIANCE_LABEL.into(),
        y_scale: YScale::Linear,
        x_range: (-90.0, 90.0),
        x_ticks: 13,
        legend: LegendCorner::UpperLeft,
        series,
    })
}

/// The roughness values of Fig. 4, in the paper's order.
pub const FIG4_ROUGHNESS: [f64; 7] = [0.5, 0.4, 0.3, 0.2, 0.15, 0.1, 0.05];

/// Fig. 4: reflection against view direction for `σ_h/τ` from 0.5 to 0.05 (θi = π/4).
/// The paper: rougher surfaces reflect more back toward the light. The smooth surfaces' peaks
/// are 100× the rough ones' wings, so the y axis is logarithmic.
pub fn fig4() -> Result<Figure> {
    let series = FIG4_ROUGHNESS
        .par_iter()
        .map(|&roughness| {
            let model = planar_model(roughness)?;
            Ok(Series::new(
                format!("σh/τ = {roughness}"),
                plane_curve(&model, FRAC_PI_4, PI),
            ))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Figure {
        title: "Fig. 4 — reflection against view direction for seven roughnesses (θi = π/4)".into(),
        caption: caption("θi = π/4, in the plane of incidence"),
        x_label: VIEW_ANGLE_LABEL.into(),
        y_label: RADIANCE_LABEL.into(),
        y_scale: YScale::Log { floor: 1e-4 },
        x_range: (-90.0, 90.0),
        x_ticks: 13,
        legend: LegendCorner::UpperLeft,
        series,
    })
}

/// Fig. 5: reflection against view direction for viewer azimuths `φr − φi = π, 15π/16, 11π/12`
/// (θi = π/4, `σ_h/τ = 0.05`). The viewer moves in the vertical plane at that azimuth; negative
/// angles are the opposite half of the same plane. The paper: reflection falls as the azimuth
/// leaves π.
pub fn fig5() -> Result<Figure> {
    let model = planar_model(ROUGHNESS)?;
    let series = [
        (PI, "π"),
        (15.0 * PI / 16.0, "15π/16"),
        (11.0 * PI / 12.0, "11π/12"),
    ]
    .iter()
    .map(|&(delta_phi, name)| {
        Series::new(
            format!("φr − φi = {name} ({:.2}°)", delta_phi.to_degrees()),
            plane_curve(&model, FRAC_PI_4, delta_phi),
        )
    })
    .collect();
    Ok(Figure {
        title: "Fig. 5 — reflection against view direction for three viewer azimuths (θi = π/4)"
            .into(),
        caption: caption(&format!(
            "σh/τ = {ROUGHNESS}, θi = π/4, viewer in the vertical plane at azimuth φr − φi"
        )),
        x_label: "view angle θr (degrees) in the plane at azimuth φr − φi; negative: opposite half of that plane"
            .into(),
        y_label: RADIANCE_LABEL.into(),
        y_scale: YScale::Linear,
        x_range: (-90.0, 90.0),
        x_ticks: 13,
        legend: LegendCorner::UpperLeft,
        series,
    })
}

fn caption(what: &str) -> Vec<String> {
    vec![
        format!("Planar fiber surface, rough limit Eq. (16'), {what}, λ = {WAVELENGTH_NM} nm."),
        format!("Assumed (the paper gives neither): η = {ETA} (polyester), ρ0 = {DIFFUSE}; normalization \"paper\" (β of Eq. (15))."),
    ]
}

/// The planar fiber surface of Figs. 3–5 with roughness `σ_h/τ`.
pub fn planar_model(roughness: f64) -> Result<Model> {
    let fiber =
        FiberParams::rough(ETA, roughness, DIFFUSE).with_normalization(Normalization::Paper);
    Material::flat(fiber).build(WAVELENGTH_NM)
}

/// The view angles of the figures, degrees: from −90 to 90 in steps of [`VIEW_STEP_DEG`], less
/// the horizon itself, where the viewer sees no surface (the BRDF is 0 there by definition, while
/// its limit toward the horizon is not: drawing it would add a false vertical drop).
pub fn view_angles_deg() -> impl Iterator<Item = f64> {
    let n = (180.0 / VIEW_STEP_DEG).round() as usize;
    (1..n).map(|k| -90.0 + k as f64 * VIEW_STEP_DEG)
}

/// `L/I0 = f cos θi` along a vertical plane of view directions: light at `(θi, φi = 0)`; a
/// signed view angle `x ≥ 0` is the viewer at `(θr = x, φr = delta_phi)`, `x < 0` the viewer at
/// `(θr = −x, φr = delta_phi − π)`. With `delta_phi = π` this is the plane of incidence, positive
/// angles on the specular side.
pub fn plane_curve(model: &Model, theta_i: f64, delta_phi: f64) -> Vec<(f64, f64)> {
    let s = Vec3::from_spherical(theta_i, 0.0);
    view_angles_deg()
        .map(|x_deg| {
            let theta_r = x_deg.abs().to_radians();
            let phi_r = if x_deg >= 0.0 {
                delta_phi
            } else {
                delta_phi - PI
            };
            // At the horizon the viewer sees no surface; cos(π/2) is not exactly 0 in f64.
            let f = if theta_r >= FRAC_PI_2 {
                0.0
            } else {
                model.eval(s, Vec3::from_spherical(theta_r, phi_r))
            };
            (x_deg, f * theta_i.cos())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_curves(fig: &Figure) {
        for s in &fig.series {
            assert_eq!(s.points.len(), 719, "{}", s.label);
            assert_eq!(s.points[0].0, -89.75);
            assert_eq!(s.points[359].0, 0.0);
            assert!(
                s.points.iter().all(|p| p.1.is_finite() && p.1 >= 0.0),
                "{}",
                s.label
            );
        }
    }

    #[test]
    fn fig3_reflection_rises_with_incidence() {
        let fig = fig3().unwrap();
        check_curves(&fig);
        let peaks: Vec<(f64, f64)> = fig.series.iter().map(Series::peak).collect();
        // Each peak sits on the specular side near the mirror direction θr = θi, pushed a little
        // further out by the 1/cos θr of the microfacet BRDF (the off-specular peak).
        for (peak, mirror) in peaks.iter().zip([30.0, 45.0, 60.0]) {
            assert!(
                peak.0 >= mirror && peak.0 <= mirror + 5.0,
                "peak at {}°, mirror direction {mirror}°",
                peak.0
            );
        }
        for w in peaks.windows(2) {
            assert!(w[1].1 > 1.1 * w[0].1, "peaks {} then {}", w[0].1, w[1].1);
        }
        // Not only the peaks: the whole specular lobe is brighter at larger θi.
        let area = |s: &Series| s.points.iter().map(|p| p.1).sum::<f64>();
        for w in fig.series.windows(2) {
            assert!(area(&w[1]) > area(&w[0]));
        }
    }

    #[test]
    fn fig4_rougher_surfaces_reflect_more_toward_the_light() {
        let fig = fig4().unwrap();
        check_curves(&fig);
        // Series are ordered from roughest (0.5) to smoothest (0.05).
        // Toward the light: at the light's own direction (−45°) and 15° from it.
        for x in [-45.0, -30.0] {
            let values: Vec<f64> = fig.series.iter().map(|s| s.at(x)).collect();
            for (k, w) in values.windows(2).enumerate() {
                assert!(
                    w[0] > w[1],
                    "at {x}°: {} gives {} but {} gives {}",
                    fig.series[k].label,
                    w[0],
                    fig.series[k + 1].label,
                    w[1]
                );
            }
        }
        // ... while the smoothest surface has by far the highest specular peak. (Not monotone in
        // between: a wider lobe peaks further from the normal, where 1/cos θr and Fresnel grow,
        // so σh/τ = 0.2 peaks a little above 0.15.)
        let peaks: Vec<f64> = fig.series.iter().map(|s| s.peak().1).collect();
        let smoothest = peaks[peaks.len() - 1];
        assert!(
            peaks[..peaks.len() - 1]
                .iter()
                .all(|&p| p < 0.5 * smoothest),
            "{peaks:?}"
        );
        assert!(peaks[1..].iter().all(|&p| p > peaks[0]), "{peaks:?}");
        // The log axis floor hides nothing of the rough curves on the light's side.
        let YScale::Log { floor } = fig.y_scale else {
            panic!("fig4 is drawn on a log axis")
        };
        assert!(fig.series[0].at(-45.0) > 10.0 * floor);
    }

    #[test]
    fn fig5_reflection_falls_as_azimuth_leaves_pi() {
        let fig = fig5().unwrap();
        check_curves(&fig);
        let peaks: Vec<f64> = fig.series.iter().map(|s| s.peak().1).collect();
        assert!(
            peaks.windows(2).all(|w| w[1] < 0.9 * w[0]),
            "peaks {peaks:?} should fall as φr − φi leaves π"
        );
        // In the plane of incidence the curve is Fig. 3's θi = π/4 curve.
        let fig3 = fig3().unwrap();
        assert_eq!(fig.series[0].points, fig3.series[1].points);
    }

    #[test]
    fn plane_curve_sign_convention() {
        // x > 0 at φr − φi = π is the specular side: the mirror direction is bright, the light's
        // own direction (x = −45°) dark for a smooth surface.
        let model = planar_model(ROUGHNESS).unwrap();
        let curve = Series::new(String::new(), plane_curve(&model, FRAC_PI_4, PI));
        assert!(curve.at(45.0) > 1e6 * curve.at(-45.0));
        let s = Vec3::from_spherical(FRAC_PI_4, 0.0);
        let v = Vec3::from_spherical(FRAC_PI_4, PI);
        assert_eq!(curve.at(45.0), model.eval(s, v) * FRAC_PI_4.cos());
    }
}
