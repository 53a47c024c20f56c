//! Exact masking intervals (docs/spec.md §2.2) against brute-force ray casting, and their limits
//! (docs/spec.md §2.1, §2.3): V-groove, flat, unshadowed below the onset, mirror symmetry, and the
//! conservation of light falling on one period.

use crate::common::Rng;
use std::f64::consts::FRAC_PI_2;

use woven::yarn::profile::{Piece, PieceIntervals, Profile};
use woven::yarn::raycast::{sample_lit, sample_lit_and_visible, SampledPieces};

/// Samples per piece for the brute force (docs/spec.md §2.2 asks for at least 10⁴).
const SAMPLES: usize = 10_000;
/// Agreement asked of closed form and brute force, as a fraction of the piece's length.
const REL_TOL: f64 = 1e-3;

impl Rng {
    fn sign(&mut self) -> f64 {
        if self.next_u64() & 1 == 0 {
            1.0
        } else {
            -1.0
        }
    }
}

/// A random valid profile, weighted toward the hard corners: `θ_a` near 0 and near π/2 (and
/// exactly 0 and π/2), `L` = 0, tiny, and up to 100.
fn random_profile(rng: &mut Rng) -> Profile {
    let r = rng.uniform();
    let theta_a = if r < 0.40 {
        rng.range(0.0, FRAC_PI_2)
    } else if r < 0.55 {
        rng.log_range(-9.0, -1.0)
    } else if r < 0.72 {
        FRAC_PI_2 - rng.log_range(-7.0, -1.0)
    } else if r < 0.78 {
        0.0
    } else if r < 0.86 {
        FRAC_PI_2
    } else {
        rng.range(1.2, FRAC_PI_2)
    };
    let r = rng.uniform();
    let l = if FRAC_PI_2 - theta_a <= 1e-12 || r < 0.15 {
        0.0
    } else if r < 0.55 {
        rng.log_range(-6.0, 2.0)
    } else {
        rng.range(0.0, 100.0)
    };
    Profile::new(theta_a, l).unwrap()
}

/// A random projected angle in `(−π/2, π/2)`, weighted toward grazing (within 1e-3 of ±π/2)
/// and toward the masking onset `±(π/2 − θ_a)`.
fn random_psi(rng: &mut Rng, profile: &Profile) -> f64 {
    let onset = profile.masking_onset();
    // 1e-6: the closest approach to grazing tested (ray casting is still cheap there).
    let max = FRAC_PI_2 - 1e-6;
    let r = rng.uniform();
    let magnitude = if r < 0.35 {
        rng.range(0.0, FRAC_PI_2)
    } else if r < 0.55 {
        FRAC_PI_2 - rng.log_range(-6.0, -3.0)
    } else if r < 0.75 {
        onset + rng.sign() * rng.log_range(-8.0, -1.0)
    } else {
        rng.range(onset, FRAC_PI_2)
    };
    rng.sign() * magnitude.clamp(0.0, max)
}

/// Case description for failure messages (full precision, so a failing case can be replayed).
fn case(profile: &Profile, what: &str) -> String {
    format!(
        "theta_a = {:?}, L = {:?}, {what}",
        profile.theta_a, profile.lateral_length
    )
}

/// Whether the light of projected angle `psi` grazes the lateral `piece` (`|a·d|` at rounding
/// level): whether it faces the light is then decided by rounding, in the closed form and in the
/// ray casting alike, and its weight `a·d` is 0.
fn grazed(profile: &Profile, piece: Piece, psi: f64) -> bool {
    let a = profile.normal(piece, 0.0);
    piece != Piece::Arc && (a.0 * psi.sin() + a.1 * psi.cos()).abs() <= 1e-12
}

/// Compares closed form and brute force piece by piece, for light from each angle in `psis`;
/// asserts agreement to `REL_TOL` of each piece's length and that the brute-force set is one run;
/// returns the worst error relative to the piece's length.
#[track_caller]
fn assert_agree(
    profile: &Profile,
    psis: &[f64],
    exact: &PieceIntervals,
    brute: &SampledPieces,
    what: &str,
) -> f64 {
    let mut worst: f64 = 0.0;
    for piece in Piece::ALL {
        let len = profile.piece_length(piece);
        if len == 0.0 || psis.iter().any(|&psi| grazed(profile, piece, psi)) {
            // No weight: a piece of zero length is a point, and a grazed lateral has a·d = 0.
            continue;
        }
        let runs = brute.runs[piece.index()];
        assert!(
            runs <= 1,
            "{}: {piece:?} lit set is {runs} intervals by ray casting (exact {:?}, brute {:?})",
            case(profile, what),
            exact.get(piece),
            brute.intervals.get(piece)
        );
        let (e, b) = (exact.get(piece), brute.intervals.get(piece));
        let err = match (e, b) {
            (Some(e), Some(b)) => (e.0 - b.0).abs().max((e.1 - b.1).abs()),
            (Some((lo, hi)), None) | (None, Some((lo, hi))) => hi - lo,
            (None, None) => 0.0,
        };
        assert!(
            err <= REL_TOL * len,
            "{}: {piece:?} exact {e:?} vs ray casting {b:?}: |err| {err:.3e} > tol {:.3e} \
             ({REL_TOL:e} of length {len:?})",
            case(profile, what),
            REL_TOL * len
        );
        worst = worst.max(err / len);
    }
    worst
}

/// Fixed corner cases: (θ_a, L, ψ).
fn corner_cases() -> Vec<(f64, f64, f64)> {
    let mut cases = Vec::new();
    for (ta, l) in [
        (FRAC_PI_2, 0.0),
        (0.0, 0.0),
        (0.0, 5.0),
        (1e-9, 0.0),
        (1e-3, 1e-3),
        (0.3, 0.0),
        (0.3, 1e-9),
        (0.8, 1.0),
        (1.2, 100.0),
        (FRAC_PI_2 - 1e-6, 100.0),
        (FRAC_PI_2 - 1e-3, 0.5),
    ] {
        let onset = FRAC_PI_2 - ta;
        for psi in [
            0.0,
            0.5 * onset,
            onset,
            onset + 1e-12,
            onset + 1e-6,
            0.5 * (onset + FRAC_PI_2),
            FRAC_PI_2 - 1e-3,
            FRAC_PI_2 - 1e-6,
        ] {
            let psi = psi.min(FRAC_PI_2 - 1e-6);
            cases.push((ta, l, psi));
            cases.push((ta, l, -psi));
        }
    }
    cases
}

#[test]
fn lit_matches_ray_casting() {
    let mut worst = (0.0, String::new());
    let mut count = 0;
    // How many cases reach each regime, so that the agreement is not only the easy one.
    let (mut shadowed, mut lateral_partly, mut arc_partly) = (0, 0, 0);
    let mut check = |profile: &Profile, psi: f64| {
        let exact = profile.lit(psi);
        let brute = sample_lit(profile, psi, SAMPLES);
        let what = format!("psi = {psi:?}");
        let err = assert_agree(profile, &[psi], &exact, &brute, &what);
        if err >= worst.0 {
            worst = (err, case(profile, &what));
        }
        count += 1;
        let (ta, l) = (profile.theta_a, profile.lateral_length);
        if psi.abs() > profile.masking_onset() {
            shadowed += 1;
            // The lateral facing the light is partly shadowed by the neighbour.
            let facing = if psi > 0.0 { Piece::Right } else { Piece::Left };
            let lit = exact.length(facing);
            if lit > 1e-3 * l && lit < (1.0 - 1e-3) * l {
                lateral_partly += 1;
            }
            // The arc's facing part, [|ψ| − π/2, θ_a] for ψ > 0, is cut short by the neighbour's arc.
            let facing_arc = ta - (psi.abs() - FRAC_PI_2).max(-ta);
            if exact.length(Piece::Arc) < facing_arc - 1e-3 * 2.0 * ta {
                arc_partly += 1;
            }
        }
    };
    for (ta, l, psi) in corner_cases() {
        check(&Profile::new(ta, l).unwrap(), psi);
    }
    let mut rng = Rng(0x5EED_0001);
    for _ in 0..3000 {
        let profile = random_profile(&mut rng);
        let psi = random_psi(&mut rng, &profile);
        check(&profile, psi);
    }
    println!(
        "lit vs ray casting: {count} cases ({shadowed} beyond the masking onset, {lateral_partly} \
         with a lateral partly shadowed, {arc_partly} with the arc partly shadowed), worst error \
         {:.3e} of the piece length at {}",
        worst.0, worst.1
    );
    assert!(
        shadowed >= 1000 && lateral_partly >= 200 && arc_partly >= 200,
        "too few hard cases: {shadowed} shadowed, {lateral_partly} lateral, {arc_partly} arc"
    );
}

#[test]
fn lit_and_visible_matches_ray_casting() {
    let mut rng = Rng(0x5EED_0002);
    let mut worst = (0.0, String::new());
    let mut count = 0;
    for i in 0..1500 {
        let profile = random_profile(&mut rng);
        let psi_s = random_psi(&mut rng, &profile);
        let mut psi_v = random_psi(&mut rng, &profile);
        // A third each: same sign, opposite signs, as drawn.
        match i % 3 {
            0 => psi_v = psi_v.abs().copysign(psi_s),
            1 => psi_v = psi_v.abs().copysign(-psi_s),
            _ => {}
        }
        let exact = profile.lit_and_visible(psi_s, psi_v);
        let brute = sample_lit_and_visible(&profile, psi_s, psi_v, SAMPLES);
        let what = format!("psi_s = {psi_s:?}, psi_v = {psi_v:?}");
        let err = assert_agree(&profile, &[psi_s, psi_v], &exact, &brute, &what);
        if err >= worst.0 {
            worst = (err, case(&profile, &what));
        }
        count += 1;
    }
    println!(
        "lit_and_visible vs ray casting: {count} cases, worst error {:.3e} of the piece length at {}",
        worst.0, worst.1
    );
}

/// Torrance–Sparrow's V-cavity: the lit fraction of the facet facing the light (its normal
/// tilted toward the light, at `θ_a` from `z`) is `min(1, 2 cos θ_a cos ψ / cos(ψ − θ_a))`, the
/// `2 (n·h)(n·s)/(s·h)` of their geometric attenuation with `h` the facet normal.
#[test]
fn v_groove_limit() {
    let l = 1e4;
    for ta in [0.05, 0.2, 0.5, 0.785, 1.0, 1.3, 1.5] {
        let profile = Profile::new(ta, l).unwrap();
        for k in 0..=40 {
            let psi = k as f64 / 40.0 * (FRAC_PI_2 - 1e-3);
            let ts = (2.0 * ta.cos() * psi.cos() / (psi - ta).cos()).min(1.0);
            for sign in [1.0, -1.0] {
                let lit = profile.lit(sign * psi);
                // From +u (ψ > 0) the right lateral faces the light; from −u, the left one.
                let facing = if sign > 0.0 { lit.right } else { lit.left };
                let fraction = facing.map_or(0.0, |(lo, hi)| (hi - lo) / l);
                assert!(
                    (fraction - ts).abs() <= 1e-3,
                    "theta_a = {ta}, L = {l}, psi = {:?}: lit fraction {fraction:.6} vs \
                     V-groove {ts:.6}, tol 1e-3",
                    sign * psi
                );
            }
        }
    }
}

/// `θ_a → 0`: a flat surface; every piece faces every direction above it and is lit whole.
#[test]
fn flat_limit_lights_everything() {
    for ta in [0.0, 1e-12, 1e-9, 1e-6] {
        for l in [0.0, 1.0, 100.0] {
            let profile = Profile::new(ta, l).unwrap();
            for k in -40..=40 {
                let psi = k as f64 / 40.0 * (FRAC_PI_2 - 1e-3);
                let lit = profile.lit(psi);
                let whole = PieceIntervals {
                    arc: Some((-ta, ta)),
                    right: Some((0.0, l)),
                    left: Some((0.0, l)),
                };
                assert_eq!(
                    lit,
                    whole,
                    "{}: not everything lit",
                    case(&profile, &format!("psi = {psi:?}"))
                );
            }
        }
    }
}

/// `|ψ| ≤ π/2 − θ_a`: nothing is shadowed and every piece faces the light.
#[test]
fn unshadowed_below_the_onset() {
    let mut rng = Rng(0x5EED_0003);
    for _ in 0..20_000 {
        let profile = random_profile(&mut rng);
        let onset = profile.masking_onset();
        if onset == 0.0 {
            // Touching cylinders: no ψ below the onset (at ψ = 0 the laterals are grazed).
            continue;
        }
        let psi = rng.sign() * rng.range(0.0, onset);
        let whole = PieceIntervals {
            arc: Some((-profile.theta_a, profile.theta_a)),
            right: Some((0.0, profile.lateral_length)),
            left: Some((0.0, profile.lateral_length)),
        };
        assert_eq!(
            profile.lit(psi),
            whole,
            "{}",
            case(&profile, &format!("psi = {psi:?} <= onset {onset:?}"))
        );
    }
}

/// `lit(−ψ)` is `lit(ψ)` mirrored; `lit_and_visible(ψ, ψ)` is `lit(ψ)`; `lit_and_visible` is
/// symmetric in its arguments and mirrors too.
#[test]
fn mirror_symmetry_and_consistency() {
    let mut rng = Rng(0x5EED_0004);
    for _ in 0..20_000 {
        let profile = random_profile(&mut rng);
        let psi = random_psi(&mut rng, &profile);
        let psi_v = random_psi(&mut rng, &profile);
        let what = case(&profile, &format!("psi = {psi:?}, psi_v = {psi_v:?}"));
        let (a, b) = (profile.lit(-psi), profile.lit(psi).mirrored());
        assert_eq!(a, b, "{what}: lit(−ψ) {a:?} vs mirrored lit(ψ) {b:?}");
        assert_eq!(
            profile.lit_and_visible(psi, psi),
            profile.lit(psi),
            "{what}"
        );
        let (a, b) = (
            profile.lit_and_visible(psi, psi_v),
            profile.lit_and_visible(psi_v, psi),
        );
        assert_eq!(a, b, "{what}: not symmetric in (ψ_s, ψ_v)");
        let b = profile.lit_and_visible(-psi, -psi_v).mirrored();
        assert_eq!(a, b, "{what}: lit_and_visible does not mirror");
    }
}

/// Conservation of the light falling on one period: every ray from the light meets the profile
/// exactly once first, so the lit set, weighted by `a·d`, intercepts the period's width seen
/// from the light: `Σ ∫_lit a·(sin ψ, cos ψ) dl = P cos ψ`. An exact identity, independent of
/// the ray casting.
#[test]
fn lit_set_intercepts_exactly_one_period_of_light() {
    let mut rng = Rng(0x5EED_0005);
    let mut worst: f64 = 0.0;
    for _ in 0..50_000 {
        let profile = random_profile(&mut rng);
        let psi = random_psi(&mut rng, &profile);
        let (ta, p) = (profile.theta_a, profile.period());
        let lit = profile.lit(psi);
        let mut intercepted = 0.0;
        if let Some((lo, hi)) = lit.arc {
            // ∫ cos(θ − ψ) dθ.
            intercepted += (hi - psi).sin() - (lo - psi).sin();
        }
        intercepted += lit.length(Piece::Right) * (ta - psi).cos();
        intercepted += lit.length(Piece::Left) * (ta + psi).cos();
        let want = p * psi.cos();
        let err = (intercepted - want).abs();
        // Rounding: a few ulps of the largest term (L ≤ 100 here).
        let tol = 1e-12 * (1.0 + p);
        assert!(
            err <= tol,
            "{}: intercepted {intercepted:.15e} vs P cos ψ {want:.15e}, |err| {err:.3e} > {tol:.1e}",
            case(&profile, &format!("psi = {psi:?}"))
        );
        worst = worst.max(err);
    }
    println!("light conservation: worst absolute error {worst:.3e}");
}

/// Finite, ordered, inside the pieces, for extreme and boundary inputs.
#[test]
fn never_nan_and_inside_the_pieces() {
    let thetas = [
        0.0,
        f64::MIN_POSITIVE,
        1e-300,
        1e-12,
        1e-6,
        0.5,
        FRAC_PI_2 - 1e-6,
        FRAC_PI_2 - 1e-12,
        FRAC_PI_2,
    ];
    let lengths = [0.0, f64::MIN_POSITIVE, 1e-12, 1.0, 1e4, 1e6];
    for ta in thetas {
        for l in lengths {
            let Ok(profile) = Profile::new(ta, l) else {
                continue;
            };
            let onset = profile.masking_onset();
            let mut psis = vec![
                0.0,
                -0.0,
                f64::MIN_POSITIVE,
                1e-300,
                onset,
                onset * (1.0 + f64::EPSILON),
                onset + 1e-15,
                FRAC_PI_2 - 1e-15,
                FRAC_PI_2 * (1.0 - f64::EPSILON),
                FRAC_PI_2,
                1.6,
                f64::NAN,
                f64::INFINITY,
            ];
            psis.extend((0..=1000).map(|k| k as f64 / 1000.0 * FRAC_PI_2));
            for &psi in &psis {
                for psi in [psi, -psi] {
                    for lit in [profile.lit(psi), profile.lit_and_visible(psi, 0.3)] {
                        for piece in Piece::ALL {
                            let Some((lo, hi)) = lit.get(piece) else {
                                continue;
                            };
                            let (a, b) = profile.parameter_range(piece);
                            assert!(
                                lo.is_finite() && hi.is_finite() && a <= lo && lo <= hi && hi <= b,
                                "{}: {piece:?} interval ({lo:?}, {hi:?}) outside [{a:?}, {b:?}]",
                                case(&profile, &format!("psi = {psi:?}"))
                            );
                        }
                    }
                }
            }
        }
    }
}

/// Regressions: literal inputs whose intervals were computed by hand (docs/masking.md §6).
#[test]
fn hand_computed_values() {
    // Touching cylinders, ψ = π/3: arc lit on [−π/6, π/3].
    let p = Profile::new(FRAC_PI_2, 0.0).unwrap();
    let (lo, hi) = p.lit(std::f64::consts::FRAC_PI_3).arc.unwrap();
    assert!((lo + std::f64::consts::FRAC_PI_6).abs() < 1e-15, "lo {lo}");
    assert!((hi - std::f64::consts::FRAC_PI_3).abs() < 1e-15, "hi {hi}");
    // θ_a = π/4, L = 1, ψ = π/3 (onset π/4): t* = (√2·½ + sin(7π/12) − 1)/cos(π/12).
    let p = Profile::new(std::f64::consts::FRAC_PI_4, 1.0).unwrap();
    let want = (std::f64::consts::FRAC_1_SQRT_2 + (7.0 * std::f64::consts::PI / 12.0).sin() - 1.0)
        / (std::f64::consts::PI / 12.0).cos();
    let (_, t) = p.lit(std::f64::consts::FRAC_PI_3).right.unwrap();
    assert!((t - want).abs() < 1e-15, "t* {t} vs {want}");
}
