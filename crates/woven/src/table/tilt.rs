//! A yarn's table averaged over a tilted float: a whole float's BRDF in one look-up.
//!
//! At cloth level a tilted yarn shades with its whole float's BRDF, the mean over the facets
//! both lit and seen along the float ([`FloatProfile::average`], [`TILT_NODES`] Gauss–Legendre
//! nodes a straight piece): evaluated from the yarn's table, that is one look-up a node, 16 an
//! evaluation for the two families. The mean depends on `(s, v)` alone, so it tabulates: this
//! module builds it on the yarn table's own grid (the mirror grid: the float tilts about the
//! yarn's `y`, which keeps both mirrors), from the yarn's table and without the model, as the
//! crowned table is built ([`crown`](super::crown)).
//!
//! The average is linear in the table's parts, so a dyeable table stays dyeable: `∂f/∂ρ0` is
//! the same average of the base's, and the interreflection term (constant in a plain base,
//! `g(s, v)` in a crowned one) becomes the average of the base's factor, a third node array.
//!
//! [`TILT_NODES`]: crate::yarn::float::TILT_NODES

use super::build::fill_uncancelled;
use super::cache::{fnv1a, FNV_BASIS};
use super::grid::Axis;
use super::{Colour, Half, Table, N_PHI_RENDER, N_THETA_RENDER};
use crate::yarn::float::{FloatProfile, TILT_NODES};
use std::f64::consts::FRAC_PI_2;
use std::ops::{AddAssign, Mul};
use std::path::Path;

/// The coarsest grid a tilted table takes, `(n_θ, n_φ, n_h)`: the renderer's on the presets
/// ([`TableOptions::for_render`](super::TableOptions::for_render)) with twice its azimuths. A
/// coarser base is read at these nodes: the float's average moves with the tilt, so a coarse
/// base's own nodes would miss where its lit and seen part starts and ends. On the sateen's
/// render table, tilted 25°, the float's table is within 5.2 % of the mean it tabulates at the
/// 99th percentile up to 80° (7.9 % with the renderer's 8 azimuths), 2.2 % of the peak of
/// `f cos θi cos θo` (3.6 %), and 11 % of that peak in 80°–89°, where the lit part's ends move
/// fastest (the test below).
pub const TILTED_MIN_GRID: (usize, usize, usize) = (N_THETA_RENDER, 2 * N_PHI_RENDER, 41);

/// What a tilted table's build computes beyond its inputs (part of a stored table's key).
const REVISION: u32 = 1;

/// `K` parts summed together by [`FloatProfile::average`].
#[derive(Clone, Copy, Debug)]
struct Parts<const K: usize>([f64; K]);

impl<const K: usize> Default for Parts<K> {
    fn default() -> Self {
        Parts([0.0; K])
    }
}

impl<const K: usize> AddAssign for Parts<K> {
    fn add_assign(&mut self, o: Self) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }
}

impl<const K: usize> Mul<f64> for Parts<K> {
    type Output = Self;
    fn mul(self, k: f64) -> Self {
        Parts(self.0.map(|x| x * k))
    }
}

impl Table {
    /// This table (a yarn's, plain or crowned) averaged over the whole float of `float`: the
    /// float's BRDF [`FloatProfile::average`] gives from this table's look-ups, tabulated on the
    /// mirror grid of this table's polar range and nodes, at least [`TILTED_MIN_GRID`]'s. Dyeable
    /// when this table is; interpolated only (a table's exact regions are not consulted: the
    /// renderer's tables have none).
    pub fn tilted(&self, float: &FloatProfile) -> Table {
        let (theta, phi, t) = self.tilted_grid();
        let (values, colour) = match &self.colour {
            Some(colour) => {
                let ones;
                let g = match &colour.crown {
                    Some(g) => g.as_slice(),
                    None => {
                        ones = vec![1.0f32; self.values.len()];
                        ones.as_slice()
                    }
                };
                let base = [self.values.as_slice(), colour.body.as_slice(), g];
                let [values, body, g] = fill_uncancelled::<3, _>(theta, phi, t, |half, a| {
                    move |o| {
                        let (s, v) = Half::join(half, a, o);
                        let Parts([f, body, g]) =
                            float.average(s, v, |ts, tv| Parts(self.eval_arrays(ts, tv, base)));
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
                let [values] = fill_uncancelled::<1, _>(theta, phi, t, |half, a| {
                    move |o| {
                        let (s, v) = Half::join(half, a, o);
                        [float.average(s, v, |ts, tv| self.eval(ts, tv))]
                    }
                });
                (values, None)
            }
        };
        self.derived((theta, phi, t), values, colour, self.crown_deg)
    }

    /// The polar, azimuth and half-vector axes of this table's [`tilted`](Self::tilted) tables.
    fn tilted_grid(&self) -> (Axis, Axis, Axis) {
        let (n_theta, n_phi, n_h) = self.dims();
        let (min_theta, min_phi, min_h) = TILTED_MIN_GRID;
        let theta = Axis {
            n: n_theta.max(min_theta),
            ..self.theta
        };
        let phi = Axis::uniform(0.0, FRAC_PI_2, n_phi.max(min_phi));
        (theta, phi, Axis::uniform(-1.0, 1.0, n_h.max(min_h)))
    }

    /// [`tilted`](Self::tilted), read from `dir` when it was built there before (a file named
    /// by a hash of this table's arrays, `float` and the grid), else built and stored there.
    /// `note` hears why a stored file was not used, or why a built one could not be stored (the
    /// table is returned either way).
    pub fn tilted_in(&self, float: &FloatProfile, dir: &Path, note: &dyn Fn(&str)) -> Table {
        let path = dir.join(format!("tilted-{}.wtab", self.tilted_key(float)));
        if path.exists() {
            let (theta, phi, t) = self.tilted_grid();
            match Table::load(&path) {
                Ok(table)
                    if table.dims() == (theta.n, phi.n, t.n)
                        && table.is_dyeable() == self.is_dyeable() =>
                {
                    return table
                }
                Ok(_) => note(&format!(
                    "not using {} (another grid): rebuilding it",
                    path.display()
                )),
                Err(e) => note(&format!(
                    "not using {} ({e}): rebuilding it",
                    path.display()
                )),
            }
        }
        let table = self.tilted(float);
        let stored = std::fs::create_dir_all(dir)
            .map_err(|e| e.to_string())
            .and_then(|()| table.save(&path).map_err(|e| e.to_string()));
        if let Err(e) = stored {
            note(&format!("a tilted float's table could not be cached ({e})"));
        }
        table
    }

    /// The cache key of this table's [`tilted`](Self::tilted) table on `float`: an FNV-1a hash
    /// of this table's arrays and grid, the float, the tilted grid and the build's constants.
    fn tilted_key(&self, float: &FloatProfile) -> String {
        let mut h = FNV_BASIS;
        let colour = self.colour.as_ref();
        let body = colour.map_or(&[][..], |c| c.body.as_slice());
        let crown = colour.and_then(|c| c.crown.as_deref()).unwrap_or_default();
        for x in self.values.iter().chain(body).chain(crown) {
            h = fnv1a(h, &x.to_le_bytes());
        }
        let text = format!(
            "{float:?}|{:?}|{:?}|{:?}|{:?}|{TILTED_MIN_GRID:?}|{TILT_NODES}|{REVISION}|{:?}",
            self.theta,
            self.phi,
            self.t,
            self.symmetry,
            colour.map(|c| (c.own, c.per_interreflection)),
        );
        format!("{:016x}", fnv1a(h, text.as_bytes()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::math::rng::SplitMix;
    use crate::math::Vec3;
    use crate::table::{Albedos, TableOptions};

    /// Pairs with both polar angles in `[0, 80°]`, or one in `[80°, 89°]` and the other
    /// in `[0, 89°]`, uniform in solid angle.
    fn pair(rng: &mut SplitMix, grazing: bool) -> (Vec3, Vec3) {
        let mut polar = |lo: f64, hi: f64| {
            let (a, b) = (lo.to_radians().cos(), hi.to_radians().cos());
            let c = a + (b - a) * rng.uniform();
            Vec3::from_spherical(c.acos(), 2.0 * std::f64::consts::PI * rng.uniform())
        };
        match grazing {
            false => (polar(0.0, 80.0), polar(0.0, 80.0)),
            true => {
                let (a, b) = (polar(80.0, 89.0), polar(0.0, 89.0));
                if rng.uniform() < 0.5 {
                    (a, b)
                } else {
                    (b, a)
                }
            }
        }
    }

    /// The tilted table against the mean it tabulates (the float's average of the yarn table's
    /// look-ups, 8 nodes a piece), dyed two ways, on the renderer's grid, in the bands the
    /// renderer's tables state their error in ([`TableOptions::for_render`]): the relative
    /// error's median and 99th percentile up to 80°, and the largest error in
    /// `f cos θi cos θo` as a share of its peak up to 80° and in 80°–89°. This is the
    /// interpolation's error alone, which the grid bounds.
    #[test]
    fn a_tilted_table_is_the_float_average_of_its_base() {
        let m = Material::preset("polyester-sateen").unwrap().yarn_family();
        let model = m.build(550.0).unwrap();
        let options = TableOptions::for_render(&model);
        let base = Table::build(&model, &m, &options, &|_, _| {}).unwrap();
        let float = FloatProfile::new(25f64.to_radians());
        let clock = std::time::Instant::now();
        let tilted = base.tilted(&float);
        println!("tilted in {:.2} s", clock.elapsed().as_secs_f64());
        assert_eq!(
            tilted.dims(),
            TILTED_MIN_GRID,
            "the floor is above the renderer's grid"
        );
        let own = Albedos::of(&m);
        let red = Albedos {
            diffuse: 0.7,
            interreflection: 0.4,
        };
        let mut rng = SplitMix(41);
        let mut of_peak = [0.0f64; 2];
        let mut rel = Vec::new();
        for grazing in [false, true] {
            let (mut peak, mut worst) = (0.0f64, 0.0f64);
            for _ in 0..4000 {
                let (s, v) = pair(&mut rng, grazing);
                for albedos in [own, red] {
                    let want = float.average(s, v, |a, b| base.eval_dyed(a, b, &[albedos])[0]);
                    let got = tilted.eval_dyed(s, v, &[albedos])[0];
                    peak = peak.max(want * s.z * v.z);
                    worst = worst.max((got - want).abs() * s.z * v.z);
                    if !grazing {
                        rel.push((got - want).abs() / want.max(1e-3));
                    }
                }
            }
            of_peak[usize::from(grazing)] = worst / peak;
        }
        rel.sort_by(f64::total_cmp);
        let (median, p99) = (rel[rel.len() / 2], rel[rel.len() * 99 / 100]);
        println!(
            "tilted vs the 8-node mean up to 80°: median {:.2} %, p99 {:.2} %, worst {:.2} % of \
             the peak of f cos cos; in 80°–89° worst {:.2} % of the peak",
            100.0 * median,
            100.0 * p99,
            100.0 * of_peak[0],
            100.0 * of_peak[1]
        );
        assert!(median < 0.01, "median {median}");
        assert!(p99 < 0.07, "p99 {p99}");
        assert!(of_peak[0] < 0.03 && of_peak[1] < 0.15, "{of_peak:?}");
        // Lit and seen from straight above, the float reflects (its crest faces up).
        let up = Vec3::new(0.0, 0.0, 1.0);
        assert!(tilted.eval(up, up) > 0.0);
    }

    /// A tilted table is kept in the folder it is asked for with, read back the same, and
    /// rebuilt with a note when its file is damaged; another float is another file.
    #[test]
    fn a_tilted_table_is_kept_on_disk() {
        let m = Material::preset("belt-cloth").unwrap().yarn_family();
        let options = TableOptions {
            n_theta: 6,
            n_phi: 4,
            n_h: 15,
            colour: true,
            ..TableOptions::default()
        };
        let base = Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}).unwrap();
        let dir = std::env::temp_dir().join(format!("woven-tilted-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let notes = std::sync::Mutex::new(Vec::<String>::new());
        let note = |m: &str| notes.lock().unwrap().push(m.to_string());
        let float = FloatProfile::new(30f64.to_radians());
        let built = base.tilted_in(&float, &dir, &note);
        let read = base.tilted_in(&float, &dir, &note);
        assert!(
            notes.lock().unwrap().is_empty(),
            "{:?}",
            notes.lock().unwrap()
        );
        let (s, v) = (
            Vec3::from_spherical(0.5, 0.3),
            Vec3::from_spherical(1.0, 2.8),
        );
        let red = [Albedos {
            diffuse: 0.7,
            interreflection: 0.4,
        }];
        assert_eq!(built.eval_dyed(s, v, &red), read.eval_dyed(s, v, &red));
        assert_eq!(built.dims(), TILTED_MIN_GRID);
        let files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        assert_eq!(files.len(), 1, "{files:?}");
        let mut bytes = std::fs::read(&files[0]).unwrap();
        let at = bytes.len() - 9;
        bytes[at] ^= 0xff;
        std::fs::write(&files[0], bytes).unwrap();
        let again = base.tilted_in(&float, &dir, &note);
        assert_eq!(built.eval_dyed(s, v, &red), again.eval_dyed(s, v, &red));
        assert_eq!(
            notes.lock().unwrap().len(),
            1,
            "{:?}",
            notes.lock().unwrap()
        );
        let _ = base.tilted_in(&FloatProfile::new(20f64.to_radians()), &dir, &note);
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
