//! The thread frame of one tangent and the angles the thread model is written in (paper §4,
//! Fig. 5; docs/microcylinder.md §1).
//!
//! A tangent `t` of thread 1 (along `x`) tilted by the offset `α` is `t = (cos α, 0, sin α)`; its
//! normal, the cloth normal turned with it, is `n_t = (−sin α, 0, cos α)`; `b = t × n_t` completes
//! the frame (for thread 2, along `y`, the same with `x` and `y` exchanged). A direction `ω`
//! (unit, away from the surface) then has
//! - `θ`, the longitudinal angle: `sin θ = ω·t`, `θ ∈ [−π/2, π/2]`;
//! - `φ`, the azimuth in the normal plane of `t`, from `n_t` toward `b`: `φ = atan2(ω·b, ω·n_t)`;
//! - `ψ`, the angle of `ω` projected into the plane of `t` and `n_t`, from `n_t` toward `t`:
//!   `ψ = atan2(ω·t, ω·n_t)` — the foreshortening of the thread's length (reweighting, Eq. (13)).

use crate::math::Vec3;
use std::f64::consts::PI;

/// One tangent of a thread's curve: its frame, with the curve's quadrature weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentFrame {
    /// The tangent `t`, unit.
    pub t: Vec3,
    /// The thread normal `n_t`: the cloth normal turned about `b` with the tangent.
    pub n: Vec3,
    /// `b = t × n_t`, the axis the tangent turns about (in the cloth plane).
    pub b: Vec3,
}

impl TangentFrame {
    /// The frame of a tangent of thread `thread` (0: along `x`, the weft; 1: along `y`) tilted
    /// by the offset `alpha` (radians; positive tilts the tangent toward `+z`).
    ///
    /// ```
    /// use woven::microcylinder::TangentFrame;
    /// let f = TangentFrame::new(0, 0.0);
    /// assert_eq!((f.t.x, f.n.z), (1.0, 1.0));
    /// ```
    pub fn new(thread: usize, alpha: f64) -> TangentFrame {
        debug_assert!(thread < 2, "a cloth has threads 0 and 1");
        let (s, c) = alpha.sin_cos();
        let (t, n) = if thread == 0 {
            (Vec3::new(c, 0.0, s), Vec3::new(-s, 0.0, c))
        } else {
            (Vec3::new(0.0, c, s), Vec3::new(0.0, -s, c))
        };
        TangentFrame {
            t,
            n,
            b: t.cross(n),
        }
    }

    /// The angles of a direction `w` (unit) in this frame.
    #[inline]
    pub fn angles(&self, w: Vec3) -> ThreadAngles {
        let sin_theta = w.dot(self.t).clamp(-1.0, 1.0);
        ThreadAngles {
            sin_theta,
            // max(0): rounding of 1 − sin² near the tangent.
            cos_theta: (1.0 - sin_theta * sin_theta).max(0.0).sqrt(),
            cos_n: w.dot(self.n),
            cos_b: w.dot(self.b),
        }
    }
}

/// A direction's coordinates in a [`TangentFrame`], from which its angles follow: `θ`
/// ([`theta`](Self::theta)), `φ` ([`phi`](Self::phi)) and `ψ` ([`psi`](Self::psi)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThreadAngles {
    /// `sin θ = ω·t`.
    pub sin_theta: f64,
    /// `cos θ ≥ 0`.
    pub cos_theta: f64,
    /// `ω·n_t = cos θ cos φ`: the cosine to the thread normal.
    pub cos_n: f64,
    /// `ω·b = cos θ sin φ`.
    pub cos_b: f64,
}

impl ThreadAngles {
    /// The longitudinal angle `θ ∈ [−π/2, π/2]`, `sin θ = ω·t`.
    #[inline]
    pub fn theta(&self) -> f64 {
        self.sin_theta.asin()
    }

    /// The azimuth `φ ∈ (−π, π]` in the normal plane, from `n_t` toward `b`.
    #[inline]
    pub fn phi(&self) -> f64 {
        self.cos_b.atan2(self.cos_n)
    }

    /// The reweighting angle `ψ ∈ (−π, π]` in the plane of `t` and `n_t`, from `n_t` toward `t`.
    #[inline]
    pub fn psi(&self) -> f64 {
        self.sin_theta.atan2(self.cos_n)
    }

    /// `cos ψ` (1 for a direction along `b`, where `ψ` is undefined: it sees the thread whole).
    #[inline]
    pub fn cos_psi(&self) -> f64 {
        let rho = self.sin_theta.hypot(self.cos_n);
        if rho > 0.0 {
            self.cos_n / rho
        } else {
            1.0
        }
    }
}

/// The pair angles of the thread scattering function (paper §4.1): the half angle
/// `θ_h = (θ_i + θ_r)/2`, the difference angle `θ_d = (θ_i − θ_r)/2` (through `cos θ_d`), the
/// azimuth difference `φ_d = φ_i − φ_r` as a magnitude in `[0, π]` (every function of it is
/// even).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairAngles {
    /// `θ_h`, 0 on the specular cone `θ_r = −θ_i`.
    pub theta_h: f64,
    /// `cos θ_d ≥ 0`.
    pub cos_theta_d: f64,
    /// `|φ_d| ∈ [0, π]`.
    pub phi_d: f64,
    /// `cos(φ_d/2) ≥ 0`.
    pub cos_half_phi_d: f64,
}

impl PairAngles {
    /// The pair angles of `ω_i` and `ω_r` given their [`ThreadAngles`], without a
    /// trigonometric function per direction: `θ_h` from `atan2` of `sin`, `cos` of `θ_i + θ_r`,
    /// `cos φ_d` from the projections into the normal plane.
    ///
    /// ```
    /// use woven::microcylinder::{PairAngles, TangentFrame};
    /// let f = TangentFrame::new(0, 0.0);
    /// let (wi, wr) = (woven::Vec3::new(0.6, 0.0, 0.8), woven::Vec3::new(-0.6, 0.0, 0.8));
    /// let p = PairAngles::new(&f.angles(wi), &f.angles(wr));
    /// assert!(p.theta_h.abs() < 1e-15); // the mirror direction lies on the specular cone
    /// ```
    #[inline]
    pub fn new(i: &ThreadAngles, r: &ThreadAngles) -> PairAngles {
        let (si, ci, sr, cr) = (i.sin_theta, i.cos_theta, r.sin_theta, r.cos_theta);
        let theta_h = 0.5 * (si * cr + ci * sr).atan2(ci * cr - si * sr);
        // cos²θ_d = (1 + cos(θ_i − θ_r))/2.
        let cos_theta_d = (0.5 * (1.0 + ci * cr + si * sr)).max(0.0).sqrt();
        let cc = ci * cr;
        // Along the tangent φ is undefined; take φ_d = 0 there (a set of measure zero).
        let cos_phi_d = if cc > 0.0 {
            ((i.cos_n * r.cos_n + i.cos_b * r.cos_b) / cc).clamp(-1.0, 1.0)
        } else {
            1.0
        };
        PairAngles {
            theta_h,
            cos_theta_d,
            phi_d: cos_phi_d.acos(),
            cos_half_phi_d: (0.5 * (1.0 + cos_phi_d)).sqrt(),
        }
    }
}

/// `|ψ_d| = |ψ_i − ψ_r| ∈ [0, π]`, the correlation argument of the reweighting, from the
/// directions' projections into the plane of `t` and `n_t` (0 where one projection vanishes).
#[inline]
pub fn psi_difference(i: &ThreadAngles, r: &ThreadAngles) -> f64 {
    let rho = i.sin_theta.hypot(i.cos_n) * r.sin_theta.hypot(r.cos_n);
    if rho > 0.0 {
        ((i.sin_theta * r.sin_theta + i.cos_n * r.cos_n) / rho)
            .clamp(-1.0, 1.0)
            .acos()
    } else {
        0.0
    }
}

/// `x` wrapped into `[−π, π]` (for a difference of two angles in `(−π, π]`).
#[inline]
pub fn wrap_pi(x: f64) -> f64 {
    if x > PI {
        x - 2.0 * PI
    } else if x < -PI {
        x + 2.0 * PI
    } else {
        x
    }
}
