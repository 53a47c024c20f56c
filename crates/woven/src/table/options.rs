//! Grid resolution and build settings of a [`Table`](super::Table), and the limits a table file
//! holds.

use super::Symmetry;
use crate::error::{Error, Result};
use crate::Model;

/// Grid resolution and build settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableOptions {
    /// Nodes in `θ_i`.
    pub n_theta: usize,
    /// Last `θ_i` node, degrees.
    pub theta_max_deg: f64,
    /// Nodes in `φ_i` over `[0, π/2]` (ignored for isotropic materials).
    pub n_phi: usize,
    /// Nodes per half-vector axis (anisotropic materials).
    pub n_h: usize,
    /// Nodes per half-vector axis for isotropic materials (one `φ_i` slice, so finer is cheap).
    pub n_h_isotropic: usize,
    /// Fiber azimuths per period when averaging twisted or isotropic yarns.
    pub azimuth_nodes: usize,
    /// Worker threads (0: all available cores).
    pub threads: usize,
    /// Also tabulate `∂f/∂ρ0`, so that [`Table::eval_dyed`](super::Table::eval_dyed) serves any
    /// dye (twice the values, about twice the build time).
    pub colour: bool,
    /// Keep the exact model for the pairs no grid holds (a single-orientation yarn's near-forward
    /// pairs and half vectors near the horizon: [`FORWARD_EXACT`](super::FORWARD_EXACT),
    /// [`GRAZING_HALF_EXACT`](super::GRAZING_HALF_EXACT)) and evaluate them with it. Off, the
    /// table interpolates everywhere: some 2 % of uniform pairs, each an exact evaluation
    /// (~25 µs for the sateen) instead of a look-up, which a renderer's tables skip.
    pub exact_regions: bool,
    /// Average the yarn over a round crown of this half-angle, degrees, in
    /// `[0, MAX_CROWN_DEG]`: the resolved yarn of a woven relief
    /// ([`Table::crowned_with`](super::Table::crowned_with), docs/model.md §8). 0 (the
    /// default): the yarn as the paper has it.
    pub crown_deg: f64,
}

/// The largest [`TableOptions::crown_deg`].
pub const MAX_CROWN_DEG: f64 = 60.0;

impl Default for TableOptions {
    fn default() -> Self {
        TableOptions {
            n_theta: 40,
            theta_max_deg: 89.9,
            n_phi: 19,
            n_h: 81,
            n_h_isotropic: 161,
            azimuth_nodes: 180,
            threads: 0,
            colour: false,
            exact_regions: true,
            crown_deg: 0.0,
        }
    }
}

/// Fibers whose half-vector lobe (the Beckmann `α = 2σ_h/τ`) is at least this wide get the default
/// `n_h` ([`TableOptions::for_model`]): roughness 0.05 and up, every preset.
pub const N_H_WIDE_LOBE: f64 = 0.1;
/// Fibers with a lobe this narrow or narrower (roughness 0.02) get [`N_H_SMOOTH`] nodes.
pub const N_H_NARROW_LOBE: f64 = 0.04;
/// Polar nodes of a renderer's tables ([`TableOptions::for_render`]).
pub const N_THETA_RENDER: usize = 20;
/// Azimuth nodes of a renderer's tables ([`TableOptions::for_render`]).
pub const N_PHI_RENDER: usize = 8;
/// Polar nodes of isotropic materials' tables ([`TableOptions::for_model`]).
pub const N_THETA_ISOTROPIC: usize = 60;

/// `n_h` for the smoothest fibers: the most a mirror table holds under 64 MiB (30 × 19 × 121²
/// values and their sampling densities, 63 MiB).
pub const N_H_SMOOTH: usize = 121;

impl TableOptions {
    /// The default options, with the half-vector grid refined for smooth fibers: `n_h` grows
    /// linearly in `1/w` (`w` the fiber's half-vector lobe width: `α = 2σ_h/τ`, or the
    /// diffraction width `2/(kτ)` where the full model's is wider) from 81 at `w ≥ 0.1`
    /// (roughness 0.05) to 121 at `w ≤ 0.04` (roughness 0.02).
    ///
    /// The yarn ridges are as narrow as the fiber lobe, and bilinear interpolation across them
    /// needs a few nodes per lobe width: a sateen at roughness 0.02 has a 99th-percentile error
    /// of 3.9 % with 81 nodes, 3.0 % with 101 and 2.0 % with 121 (RMS 0.93, 0.64, 0.50 %), at
    /// (121/81)² ≈ 2.2× the build time. The presets (roughness ≥ 0.05) keep 81.
    ///
    /// Isotropic materials (one azimuth slice, so nodes are cheap) get [`N_THETA_ISOTROPIC`]
    /// polar nodes: the weighted mean's bias grows with the polar spacing squared, and a broad
    /// lobe keeps `f cos θ_i cos θ_r` near its peak down to grazing angles, where 40 nodes leave
    /// 1.1 % of the peak on a rough flat fiber.
    pub fn for_model(model: &Model) -> TableOptions {
        let w = model.fiber().lobe_width(1.0);
        let (n0, n1) = (TableOptions::default().n_h as f64, N_H_SMOOTH as f64);
        let x =
            ((N_H_WIDE_LOBE / w - 1.0) / (N_H_WIDE_LOBE / N_H_NARROW_LOBE - 1.0)).clamp(0.0, 1.0);
        // Odd, so the axes t = 0 (the ridges) stay nodes.
        let n_h = ((n0 - 1.0 + x * (n1 - n0)) / 2.0).round() as usize * 2 + 1;
        let n_theta = match Symmetry::of(model) {
            Symmetry::Isotropic => N_THETA_ISOTROPIC,
            Symmetry::Mirror => TableOptions::default().n_theta,
        };
        TableOptions {
            n_theta,
            n_h: n_h.clamp(n0 as usize, N_H_SMOOTH),
            ..TableOptions::default()
        }
    }

    /// The grid a renderer builds on first use ([`colour`](Self::colour) on, no
    /// [`exact_regions`](Self::exact_regions)): coarser than [`for_model`](Self::for_model), so
    /// a preset builds in seconds. Measured on the presets' yarns (`Material::yarn_family`,
    /// seed 11, 400 pairs a band): 1.0–1.6 % cosine-weighted RMS up to 80° (p99 2.6–6.7 %),
    /// 3.8–4.9 % in 80°–89°, within 0.8–2.6 % of the peak of `f cos θ_i cos θ_r` up to 80° and
    /// 2.1–5.9 % in 80°–89°; 5.3 / 8.7 / 7.4 s per preset (sateen / belt / silk) on 2 cores.
    pub fn for_render(model: &Model) -> TableOptions {
        let accurate = TableOptions::for_model(model);
        TableOptions {
            n_theta: N_THETA_RENDER,
            n_phi: N_PHI_RENDER,
            // The same share of the accurate half-vector grid (81 → 41), odd.
            n_h: (accurate.n_h / 4) * 2 + 1,
            n_h_isotropic: (accurate.n_h_isotropic * 3 / 16) * 2 + 1,
            azimuth_nodes: 60,
            colour: true,
            // Exact evaluations cost a render more than all its look-ups together (~2 % of
            // pairs at ~250× a look-up); the Mitsuba plugin, which cannot call the exact model,
            // interpolates there too.
            exact_regions: false,
            ..accurate
        }
    }

    /// Checks the options.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the option.
    pub fn validate(&self) -> Result<()> {
        let int = |name: &str, x: usize, lo: usize, hi: usize| {
            if (lo..=hi).contains(&x) {
                Ok(())
            } else {
                Err(Error::invalid(
                    name,
                    x,
                    format!("an integer in [{lo}, {hi}]"),
                ))
            }
        };
        int("n_theta", self.n_theta, 2, 1024)?;
        int("n_phi", self.n_phi, 2, 1024)?;
        int("n_h", self.n_h, 3, 4097)?;
        int("n_h_isotropic", self.n_h_isotropic, 3, 4097)?;
        int("azimuth_nodes", self.azimuth_nodes, 8, 100_000)?;
        crate::error::check_range("theta_max_deg", self.theta_max_deg, 1.0, 89.9)?;
        crate::error::check_range("crown_deg", self.crown_deg, 0.0, MAX_CROWN_DEG)?;
        Ok(())
    }
}

/// The most values a table file holds (both halves, see [`super::Table::values`]): `Table::load`
/// refuses larger files, so a build that would exceed it is refused first.
pub const MAX_VALUES: u64 = 1 << 28;

/// The grid `(n_theta, n_phi, n_h)` a table of `symmetry` has with `options`.
pub fn grid_of(symmetry: Symmetry, options: &TableOptions) -> (usize, usize, usize) {
    // A crown breaks isotropy: a crowned table has the mirror grid.
    let symmetry = if options.crown_deg > 0.0 {
        Symmetry::Mirror
    } else {
        symmetry
    };
    match symmetry {
        Symmetry::Isotropic => (options.n_theta, 1, options.n_h_isotropic),
        Symmetry::Mirror => (options.n_theta, options.n_phi, options.n_h),
    }
}

/// The values a table of `symmetry` holds with `options`: two halves of `n_theta · n_phi · n_h²`,
/// twice that with [`colour`](TableOptions::colour).
pub fn value_count(symmetry: Symmetry, options: &TableOptions) -> u64 {
    let (n_theta, n_phi, n_h) = grid_of(symmetry, options);
    let parts = match (options.colour, options.crown_deg > 0.0) {
        (false, _) => 1,
        (true, false) => 2,
        (true, true) => 3,
    };
    parts * 2 * (n_theta * n_phi) as u64 * (n_h * n_h) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(toml: &str) -> TableOptions {
        let m = crate::material::Material::from_toml_str(toml, "test").unwrap();
        TableOptions::for_model(&m.build(550.0).unwrap())
    }

    #[test]
    fn smooth_fibers_get_finer_half_vector_grids() {
        let n_h = |roughness: f64| {
            let sateen = crate::material::Material::preset("polyester-sateen")
                .unwrap()
                .to_toml_string()
                .replace("roughness = 0.05", &format!("roughness = {roughness}"));
            options(&sateen).n_h
        };
        assert_eq!(n_h(0.3), 81);
        assert_eq!(n_h(0.05), 81);
        assert_eq!(n_h(0.02), N_H_SMOOTH);
        assert_eq!(n_h(0.005), N_H_SMOOTH);
        let mid = n_h(0.03);
        assert!(mid > 81 && mid < N_H_SMOOTH && mid % 2 == 1, "{mid}");
        let mut prev = 0;
        for k in 0..=12 {
            let n = n_h(0.01 + 0.005 * (k * k) as f64);
            assert!(n % 2 == 1, "n_h {n} is even");
            assert!(prev == 0 || n <= prev, "n_h not decreasing with roughness");
            prev = n;
        }
    }

    #[test]
    fn render_grids_are_coarser_dyeable_and_valid() {
        for name in crate::material::Material::preset_names() {
            let m = crate::material::Material::preset(name).unwrap();
            let model = m.build(550.0).unwrap();
            let (r, a) = (
                TableOptions::for_render(&model),
                TableOptions::for_model(&model),
            );
            assert!(r.colour && r.validate().is_ok(), "{name}");
            assert!(r.n_h % 2 == 1 && r.n_h_isotropic % 2 == 1, "{name}: {r:?}");
            assert!(
                value_count(Symmetry::of(&model), &r) * 4 < value_count(Symmetry::of(&model), &a)
            );
            // The paper's presets share one render grid; smoother fibres (the filament satin's)
            // get a finer half-vector grid, as at full resolution.
            if crate::material::Material::paper_preset_names().contains(name) {
                assert_eq!((r.n_h, r.n_h_isotropic), (41, 61), "{name}");
            } else {
                assert!(r.n_h >= 41 && r.n_h_isotropic >= 61, "{name}: {r:?}");
            }
        }
    }

    #[test]
    fn isotropic_materials_get_more_polar_nodes_and_the_rest_is_default() {
        let flat = options("[fiber]\neta = 1.5\nroughness = 0.3\ndiffuse = 0.1\n");
        assert_eq!(
            flat,
            TableOptions {
                n_theta: N_THETA_ISOTROPIC,
                ..TableOptions::default()
            }
        );
        let silk = crate::material::Material::preset("silk").unwrap();
        let silk = TableOptions::for_model(&silk.build(550.0).unwrap());
        assert_eq!(silk.n_theta, N_THETA_ISOTROPIC);
        let belt = crate::material::Material::preset("belt-cloth").unwrap();
        let belt = TableOptions::for_model(&belt.build(550.0).unwrap());
        assert_eq!(belt, TableOptions::default());
        assert!(silk.validate().is_ok() && belt.validate().is_ok());
    }
}
