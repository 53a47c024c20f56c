//! The live views of a material: the BRDF over the view hemisphere for one incidence (the map of
//! `woven plot hemisphere`, [`woven::figures::hemisphere`]), the BRDF in the plane of incidence,
//! and the paper's goniometer curves (Figs. 8–10, [`woven::gonio`]).
//!
//! Each is computed over all cores (rayon) in small chunks — a row of the map, a point of a
//! curve — and stops between chunks once the job is stale ([`Emitter::cancelled`]).

use crate::job::Emitter;
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::PI;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use woven::figures::cloth::{tilts, AZIMUTHS};
use woven::figures::hemisphere::{self, evaluate_row, nodes_needed};
use woven::{gonio, Model, Vec3};

/// The hemisphere map's grids, coarse to fine: each is sent when done, so a slow material shows
/// a coarse map at once and refines it.
pub const HEMISPHERE_LEVELS: [usize; 3] = [16, 32, 64];
/// Step of the in-plane curve's view angle, degrees.
pub const PLANE_STEP_DEG: f64 = 1.0;
/// Step of the goniometer curves' tilt, degrees (the paper measured every 3°).
pub const GONIO_STEP_DEG: f64 = 1.0;
/// Least time between two progress messages.
const PROGRESS_EVERY: Duration = Duration::from_millis(100);

/// Which views to compute.
#[derive(Clone, Copy, Debug)]
pub struct Which {
    /// The hemisphere map.
    pub hemisphere: bool,
    /// The in-plane curve.
    pub plane: bool,
    /// The goniometer curves.
    pub gonio: bool,
}

/// One line of a views stream.
#[derive(Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Message {
    /// Work done so far, in BRDF evaluations.
    Progress {
        /// Evaluations done.
        done: u64,
        /// Evaluations in all.
        total: u64,
    },
    /// The map over the view hemisphere at one grid size.
    Hemisphere {
        /// Nodes per side.
        n: usize,
        /// `f` (sr⁻¹) per node, row-major, row 0 at the top (`y` near +1), `null` outside the
        /// disc (see [`woven::figures::hemisphere`]).
        values: Vec<f64>,
        /// The largest value inside the disc.
        max: f64,
    },
    /// The BRDF in the plane of incidence.
    Plane {
        /// The points, view angle increasing.
        points: Vec<PlanePoint>,
    },
    /// The goniometer curves.
    Gonio {
        /// Tilts, degrees.
        tilts_deg: Vec<f64>,
        /// Sample azimuths, degrees, with their names.
        azimuths: Vec<(f64, &'static str)>,
        /// `f cos θi` (sr⁻¹) per azimuth, per tilt.
        radiance: Vec<Vec<f64>>,
    },
    /// Everything asked for is done.
    Done {
        /// Wall time since the request, milliseconds.
        ms: f64,
    },
}

/// A point of the in-plane curve: the viewer in the plane of the light and the normal.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct PlanePoint {
    /// Signed view angle, degrees: positive on the mirror side (`φr = φi + 180°`).
    pub x_deg: f64,
    /// The viewer's polar angle, radians.
    pub theta_r: f64,
    /// The viewer's azimuth, radians.
    pub phi_r: f64,
    /// `f(s, v)`, sr⁻¹.
    pub f: f64,
}

/// The view angles of the in-plane curve, degrees: −89° to 89° (the BRDF at the horizon is 0 by
/// definition, its limit is not).
fn plane_angles() -> Vec<f64> {
    let k = (89.0 / PLANE_STEP_DEG).floor() as i64;
    (-k..=k).map(|i| i as f64 * PLANE_STEP_DEG).collect()
}

/// The viewer of in-plane angle `x_deg` for light at azimuth `phi_i`.
pub fn plane_viewer(x_deg: f64, phi_i: f64) -> (f64, f64) {
    let theta_r = x_deg.abs().to_radians();
    let phi_r = if x_deg >= 0.0 { phi_i + PI } else { phi_i };
    (theta_r, phi_r.rem_euclid(2.0 * PI))
}

/// Counts evaluations and sends progress now and then.
struct Meter<'a> {
    out: &'a Emitter,
    done: AtomicU64,
    total: u64,
    last: Mutex<Instant>,
}

impl Meter<'_> {
    fn add(&self, n: u64) {
        let done = self.done.fetch_add(n, Ordering::Relaxed) + n;
        let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
        if last.elapsed() >= PROGRESS_EVERY {
            *last = Instant::now();
            drop(last);
            self.out.send(&Message::Progress {
                done,
                total: self.total,
            });
        }
    }
}

/// Computes the views of `model` for light from `(theta_i, phi_i)` (radians) and sends each as
/// it is done: the in-plane curve, the coarsest map, the goniometer curves, then the finer maps.
/// Returns early, sending nothing more, once the job is stale.
pub fn compute(model: &Model, theta_i: f64, phi_i: f64, which: Which, out: &Emitter) {
    let start = Instant::now();
    let s = Vec3::from_spherical(theta_i, phi_i);
    let gonio_tilts = tilts(GONIO_STEP_DEG);
    let angles = plane_angles();
    let total = which.plane as u64 * angles.len() as u64
        + which.gonio as u64 * (gonio_tilts.len() * AZIMUTHS.len()) as u64
        + if which.hemisphere {
            HEMISPHERE_LEVELS.iter().map(|&n| nodes_needed(n)).sum()
        } else {
            0
        };
    let meter = Meter {
        out,
        done: AtomicU64::new(0),
        total,
        last: Mutex::new(Instant::now()),
    };

    if which.plane {
        let points: Option<Vec<PlanePoint>> = angles
            .par_iter()
            .map(|&x_deg| {
                if out.cancelled() {
                    return None;
                }
                let (theta_r, phi_r) = plane_viewer(x_deg, phi_i);
                let f = model.eval(s, Vec3::from_spherical(theta_r, phi_r));
                meter.add(1);
                Some(PlanePoint {
                    x_deg,
                    theta_r,
                    phi_r,
                    f,
                })
            })
            .collect();
        let Some(points) = points else { return };
        if !out.send(&Message::Plane { points }) {
            return;
        }
    }
    for (level, &n) in HEMISPHERE_LEVELS.iter().enumerate() {
        if which.hemisphere {
            let Some(grid) = hemisphere_grid(model, s, n, out, &meter) else {
                return;
            };
            let max = grid.max_in_disc();
            if !out.send(&Message::Hemisphere {
                n,
                values: grid.values,
                max,
            }) {
                return;
            }
        }
        // The goniometer curves after the coarsest map: all three views show early.
        if level == 0 && which.gonio {
            let Some(msg) = gonio_curves(model, &gonio_tilts, out, &meter) else {
                return;
            };
            if !out.send(&msg) {
                return;
            }
        }
    }
    out.send(&Message::Done {
        ms: start.elapsed().as_secs_f64() * 1e3,
    });
}

/// The hemisphere map on an `n`-grid, row by row; `None` once stale.
fn hemisphere_grid(
    model: &Model,
    s: Vec3,
    n: usize,
    out: &Emitter,
    meter: &Meter,
) -> Option<hemisphere::Grid> {
    let mut values = vec![f64::NAN; n * n];
    let complete = values
        .par_chunks_mut(n)
        .enumerate()
        .map(|(row, chunk)| {
            if out.cancelled() {
                return false;
            }
            meter.add(evaluate_row(
                model,
                s,
                n,
                row,
                hemisphere::Side::Above,
                chunk,
            ));
            true
        })
        .reduce(|| true, |a, b| a && b);
    complete.then_some(hemisphere::Grid { n, values })
}

/// The goniometer curves at `tilts_deg` for the paper's three azimuths; `None` once stale.
fn gonio_curves(model: &Model, tilts_deg: &[f64], out: &Emitter, meter: &Meter) -> Option<Message> {
    let azimuths: Vec<f64> = AZIMUTHS.iter().map(|&(a, _)| a).collect();
    let readings: Option<Vec<f64>> = gonio::sweep_grid(&azimuths, tilts_deg)
        .par_iter()
        .with_max_len(4)
        .map(|&(a, t)| {
            if out.cancelled() {
                return None;
            }
            let r = gonio::read(model, a, t).radiance;
            meter.add(1);
            Some(r)
        })
        .collect();
    let readings = readings?;
    let n = tilts_deg.len();
    Some(Message::Gonio {
        tilts_deg: tilts_deg.to_vec(),
        azimuths: AZIMUTHS.to_vec(),
        radiance: readings.chunks(n).map(<[f64]>::to_vec).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::Channels;
    use tokio::sync::mpsc;

    #[test]
    fn a_stale_job_stops_without_sending() {
        let model = woven::material::Material::preset("silk")
            .unwrap()
            .build(550.0)
            .unwrap();
        let channels = Channels::default();
        let (tx, mut rx) = mpsc::channel(64);
        let out = Emitter::new(tx, channels.begin(Some("v")));
        // A newer request on the channel: the old job is stale before it starts.
        let _newer = channels.begin(Some("v"));
        let which = Which {
            hemisphere: true,
            plane: true,
            gonio: true,
        };
        compute(&model, 0.5, 0.0, which, &out);
        drop(out);
        assert!(rx.blocking_recv().is_none());
    }

    #[test]
    fn the_plane_runs_through_the_light_and_the_mirror_direction() {
        let phi_i = 0.3;
        let (t, p) = plane_viewer(30.0, phi_i);
        assert!((t - 30f64.to_radians()).abs() < 1e-15);
        assert!((p - (phi_i + PI)).abs() < 1e-12);
        let (t, p) = plane_viewer(-30.0, phi_i);
        assert!((t - 30f64.to_radians()).abs() < 1e-15 && (p - phi_i).abs() < 1e-15);
        let a = plane_angles();
        assert_eq!((a[0], a[a.len() - 1], a.len()), (-89.0, 89.0, 179));
    }
}
