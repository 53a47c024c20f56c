//! A material that lets light through (`[weave] gap` and `transmission`): the exact model's
//! reflection with gaps, its transmission, and their energy (docs/model.md, "Light through the
//! yarns").

use std::f64::consts::PI;
use std::sync::OnceLock;
use woven::bsdf::{Bsdf, LobeFlags, Transport};
use woven::catalog::DyedModel;
use woven::color::Rgb;
use woven::material::{Dye, Material, Openness};
use woven::math::sampling::cosine_hemisphere;
use woven::{Model, Vec3};

/// The sheer preset with another body albedo `ρ0` (and so another `τ`).
fn voile(diffuse: f64) -> Material {
    let mut m = Material::preset("cotton-voile").unwrap();
    m.fiber.diffuse = diffuse;
    m
}

/// The sheer preset built at 550 nm, once: its clones share the table of its transmission,
/// worked out when first asked (about ten seconds).
fn cream() -> Model {
    static MODEL: OnceLock<Model> = OnceLock::new();
    MODEL
        .get_or_init(|| {
            Material::preset("cotton-voile")
                .unwrap()
                .build(550.0)
                .unwrap()
        })
        .clone()
}

/// The cosine-weighted integral of `f` over the lower hemisphere (`n²` stratified directions).
fn through(f: impl Fn(Vec3) -> f64, n: usize) -> f64 {
    let mut sum = 0.0;
    for a in 0..n {
        for b in 0..n {
            let d = cosine_hemisphere((a as f64 + 0.5) / n as f64, (b as f64 + 0.5) / n as f64);
            sum += f(Vec3::new(d.x, d.y, -d.z));
        }
    }
    sum * PI / (n * n) as f64
}

#[test]
fn the_voile_is_an_open_transmitting_preset_that_reads_back_as_written() {
    let m = Material::preset("cotton-voile").unwrap();
    assert_eq!(
        m.openness,
        Openness {
            gap: 0.5,
            transmission: true
        }
    );
    let again = Material::from_toml_str(&m.to_toml_string(), "<again>").unwrap();
    assert_eq!(again, m);
    assert!(Material::all_preset_names().contains(&"cotton-voile"));
    // Gaps and transmission belong to a weave, in range.
    let e = Material::from_toml_str(
        "[fiber]\neta = 1.5\nroughness = 0.2\n[yarn]\nlateral_length = 4.0\nslope_mean = 0.0\n\
         [weave]\npattern = \"plain\"\ngap = 0.99\n",
        "<gap>",
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("weave.gap") && e.to_string().contains("0.95"),
        "{e}"
    );
    let mut loose = m.clone();
    loose.weave = None;
    let e = loose.validate().unwrap_err().to_string();
    assert!(e.contains("weave.gap"), "{e}");
    // The table a surface renders from is the yarn alone, opaque and gapless.
    assert_eq!(m.yarn_family().openness, Openness::default());
}

#[test]
fn a_plain_weaves_gaps_scale_its_reflection_by_the_covered_share() {
    let mut open = Material::preset("cotton-voile").unwrap();
    open.openness.transmission = false;
    let mut closed = open.clone();
    closed.openness.gap = 0.0;
    let (open, closed) = (open.build(550.0).unwrap(), closed.build(550.0).unwrap());
    assert!(!open.transmits());
    for (s, v) in [
        (
            Vec3::from_spherical(0.3, 0.2),
            Vec3::from_spherical(0.5, 2.9),
        ),
        (
            Vec3::from_spherical(1.2, 1.0),
            Vec3::from_spherical(0.1, 4.0),
        ),
    ] {
        // γ = ½: both families cover (1 − gap²)/2 of the cloth.
        let (f, g) = (open.eval(s, v), closed.eval(s, v));
        assert!((f - (1.0 - 0.25) * g).abs() < 1e-12 * g, "{f} {g}");
        // Opaque: nothing below.
        assert_eq!(open.eval(s, Vec3::new(v.x, v.y, -v.z)), 0.0);
    }
}

#[test]
fn a_white_voile_reflects_and_transmits_all_it_is_given_and_a_dyed_one_absorbs() {
    let white = voile(0.999).build(550.0).unwrap();
    let cream = cream();
    assert!(white.transmits() && white.lobes().contains(LobeFlags::TRANSMISSION));
    for (theta, phi) in [(0.05, 0.3), (0.6, 1.0), (1.1, 0.2), (1.4, 2.5)] {
        let (r, t) = (white.albedo(theta, phi), white.transmittance(theta, phi));
        assert!((r + t - 1.0).abs() < 2e-3, "θ {theta}: R {r} + T {t}");
        // The transmittance is the open area plus the diffuse transmission eval integrates
        // (the preset's own ρ0, whose table the other tests share).
        let s = Vec3::from_spherical(theta, phi);
        let budget = cream.budget(theta, phi);
        let diffuse = through(|v| cream.eval(s, v), 48);
        assert_eq!(budget.passed, cream.open_along(s));
        assert!(
            (diffuse - budget.transmitted).abs() < 0.01,
            "θ {theta}: eval integrates to {diffuse}, the budget says {}",
            budget.transmitted
        );
        let tc = budget.transmittance();
        assert!(
            budget.reflected + tc < 0.99 && tc > budget.passed,
            "θ {theta}: {budget:?}"
        );
    }
    // Along the normal, the gaps pass their square.
    assert!((white.open_along(Vec3::new(0.0, 0.0, 1.0)) - 0.25).abs() < 1e-15);
}

#[test]
fn the_transmission_is_reciprocal_and_the_back_is_the_front_turned_over() {
    let m = cream();
    let back = |w: Vec3| Vec3::new(w.x, -w.y, -w.z);
    for (a, b) in [((0.3, 0.4), (2.1, 1.0)), ((1.2, 5.0), (2.8, 2.2))] {
        let (wo, wi) = (
            Vec3::from_spherical(a.0, a.1),
            Vec3::from_spherical(b.0, b.1),
        );
        let (f, g) = (m.eval(wi, wo), m.eval(back(wo), back(wi)));
        assert!(f > 0.0 && (f - g).abs() < 1e-12 * f, "{f} {g}");
        // Seen from below, the cloth reflects as its front turned over about the weft.
        let (s, v) = (
            Vec3::from_spherical(a.0, a.1),
            Vec3::from_spherical(0.7, 2.0),
        );
        assert_eq!(m.eval(back(s), back(v)), m.eval(s, v));
    }
}

#[test]
fn a_satins_back_is_its_sateen() {
    let mut satin = Material::preset("filament-satin").unwrap();
    satin.openness = Openness {
        gap: 0.1,
        transmission: true,
    };
    let mut back = satin.back();
    assert!((back.weft_fraction() - (1.0 - satin.weft_fraction())).abs() < 1e-15);
    back.openness.transmission = false;
    let (m, b) = (satin.build(550.0).unwrap(), back.build(550.0).unwrap());
    let turn = |w: Vec3| Vec3::new(w.x, -w.y, -w.z);
    // The viewer on the weft's specular cone (v·x = −s·x) and off the warp's (v·y = −s·y = 0).
    let s = Vec3::from_spherical(0.6, 0.0);
    let v = Vec3::from_spherical(1.2, (-s.x / 1.2f64.sin()).acos());
    assert!((v.x + s.x).abs() < 1e-12 && v.y.abs() > 0.5);
    assert_eq!(m.eval(turn(s), turn(v)), b.eval(s, v));
    // Warp-faced in front, weft-faced behind: the weft's sheen is the back's.
    let (front, behind) = (m.eval(s, v), b.eval(s, v));
    assert!(behind > 1.5 * front, "front {front}, back {behind}");
}

#[test]
fn the_exact_models_draws_cross_the_cloth_with_the_density_it_reports() {
    let m = cream();
    let dyed = DyedModel {
        model: m.clone(),
        dye: Dye {
            weft: Some(Rgb([0.6, 0.3, 0.2])),
            warp: Some(Rgb([0.6, 0.3, 0.2])),
        },
    };
    let known = Vec3::from_spherical(0.5, 0.8);
    let (mut crossed, n) = (0, 400);
    for k in 0..n {
        let u = [
            (k % 20) as f64 / 20.0 + 0.025,
            (k / 20) as f64 / 20.0 + 0.025,
        ];
        let uc = (k as f64 * 0.618_034) % 1.0;
        let d = Bsdf::sample(&m, known, uc, u, Transport::Radiance).unwrap();
        assert_eq!(d.pdf, Bsdf::pdf(&m, d.wi, d.wo, Transport::Radiance));
        assert_eq!(d.f, m.eval(d.wi, d.wo));
        crossed += usize::from(d.wi.z < 0.0);
        let c = dyed.sample(known, uc, u, Transport::Radiance).unwrap();
        assert_eq!((c.wi, c.pdf), (d.wi, d.pdf));
        // The dyed transmission: each channel's τ of the same shape, red passing most.
        if c.wi.z < 0.0 {
            assert!(c.f.0[0] > c.f.0[1] && c.f.0[1] > c.f.0[2] && c.f.0[2] > 0.0);
        }
    }
    assert!((150..250).contains(&crossed), "{crossed} of {n} crossed");
    // The density covers the whole sphere once.
    let total = through(
        |d| Bsdf::pdf(&m, d, known, Transport::Radiance) / d.z.abs(),
        64,
    ) + through(
        |d| {
            let up = Vec3::new(d.x, d.y, -d.z);
            Bsdf::pdf(&m, up, known, Transport::Radiance) / up.z
        },
        64,
    );
    assert!((total - 1.0).abs() < 1e-9, "{total}");
}

#[test]
fn the_hemisphere_below_shows_what_the_voile_transmits_and_an_opaque_cloth_nothing() {
    use woven::figures::hemisphere::{evaluate, Side};
    let s = Vec3::from_spherical(0.6, 0.3);
    let voile = evaluate(&cream(), s, 8, Side::Below, |_| {});
    let silk = Material::preset("silk").unwrap().build(550.0).unwrap();
    let opaque = evaluate(&silk, s, 8, Side::Below, |_| {});
    let inside = |g: &[f64]| {
        g.iter()
            .copied()
            .filter(|f| !f.is_nan())
            .collect::<Vec<_>>()
    };
    assert!(inside(&voile.values).iter().all(|&f| f > 0.0));
    assert!(inside(&opaque.values).iter().all(|&f| f == 0.0));
    // Below, the disc's centre is the direction straight through.
    assert_eq!(Side::Below.view(0.0, 0.0), Vec3::new(0.0, 0.0, -1.0));
}
