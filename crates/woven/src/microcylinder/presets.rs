//! The six fabrics of the paper's Table II (parameters fitted by the authors to their
//! measurements). Three public transcriptions of the table disagree in two places; these take
//! the majority value (docs/microcylinder.md §10).

use super::curve::TangentCurve;
use super::thread::Thread;
use crate::color::Rgb;
use crate::error::{Error, Result};

/// The preset names, in the order of the paper's Table II.
pub const PRESET_NAMES: [&str; 6] = [
    "microcylinder-linen-plain",
    "microcylinder-silk-crepe-de-chine",
    "microcylinder-satin-charmeuse",
    "microcylinder-satin-charmeuse-back",
    "microcylinder-silk-shot",
    "microcylinder-velvet",
];

/// Each preset's energy guard, `h(θ_k) = cos θ_k · max_φ max_channel A(θ_k, φ)` of the printed
/// model at [`GUARD_THETA_DEG`](super::GUARD_THETA_DEG) and
/// [`PRESET_GUARD_PHI_COUNT`](super::PRESET_GUARD_PHI_COUNT) azimuths, in the order of
/// [`PRESET_NAMES`]: printed by `cargo run --release -p woven --example microcylinder_guard`
/// (about 5 minutes on two cores), checked by an ignored test that measures them again.
pub const PRESET_GUARDS: [[f64; 13]; 6] = [
    // microcylinder-linen-plain
    [
        2.8337231636405924e-1,
        2.3328706039194272e-1,
        1.6484282826414484e-1,
        1.1972673311572074e-1,
        9.481082582041242e-2,
        7.402829268229301e-2,
        5.987672796371936e-2,
        5.131873697136154e-2,
        4.331143675065766e-2,
        3.772712907096364e-2,
        3.426206354634089e-2,
        3.1900958375252156e-2,
        3.062753458497796e-2,
    ],
    // microcylinder-silk-crepe-de-chine
    [
        1.878108661484536e-1,
        1.8993533670284532e-1,
        1.9370649557581862e-1,
        1.8170680832098368e-1,
        1.7920897561855192e-1,
        1.8241598664318331e-1,
        1.9119685319897495e-1,
        2.02630845531852e-1,
        2.2216490952458878e-1,
        2.5223118877359796e-1,
        2.8895873649508275e-1,
        3.400774884447022e-1,
        4.789618123067644e-1,
    ],
    // microcylinder-satin-charmeuse
    [
        1.8971966048213737e-1,
        1.7784689649943608e-1,
        1.8701337169442775e-1,
        1.7668437236843262e-1,
        1.6893360951773617e-1,
        1.6613583676549815e-1,
        1.6933538967855005e-1,
        1.7756428258440496e-1,
        1.9611955046102927e-1,
        2.2445079769866694e-1,
        2.588234182202499e-1,
        3.255490327184139e-1,
        4.9965698555504584e-1,
    ],
    // microcylinder-satin-charmeuse-back
    [
        2.1074811430637103e-1,
        1.8646427952042835e-1,
        1.6160396960589327e-1,
        1.351721637494742e-1,
        1.2106200839744392e-1,
        1.1237314921547972e-1,
        1.102973629873124e-1,
        1.1384290323795664e-1,
        1.2539840894773432e-1,
        1.437003300730784e-1,
        1.719790716127966e-1,
        2.2164264226319444e-1,
        3.5150610435182267e-1,
    ],
    // microcylinder-silk-shot
    [
        3.059589678353735e-1,
        2.6804863895565234e-1,
        2.633926403742719e-1,
        2.651074722158417e-1,
        2.6414245894343025e-1,
        2.6984288622634434e-1,
        2.806967780298796e-1,
        2.9689265926620245e-1,
        3.2817937275571696e-1,
        3.6936905093701816e-1,
        4.1422200193304176e-1,
        4.814444131295475e-1,
        6.695105254407122e-1,
    ],
    // microcylinder-velvet
    [
        1.7965602084171718e-3,
        1.4541168071839295e-2,
        3.596456513952207e-2,
        5.151941192426058e-2,
        6.0351417521331135e-2,
        6.784420994534279e-2,
        7.375536509050079e-2,
        7.807931975555982e-2,
        8.355799235956204e-2,
        8.799127881608597e-2,
        9.107462462008792e-2,
        9.362094054442903e-2,
        9.558000459269884e-2,
    ],
];

/// A thread from Table II's units: angles in degrees, the albedo as a scale times a colour.
#[allow(clippy::too_many_arguments)]
fn thread(
    eta: f64,
    scale: f64,
    colour: [f64; 3],
    kd: f64,
    gamma_s_deg: f64,
    gamma_v_deg: f64,
    coverage: f64,
    offsets_deg: &[f64],
    lengths: &[f64],
) -> Thread {
    let offsets: Vec<f64> = offsets_deg.iter().map(|d| d.to_radians()).collect();
    Thread {
        eta,
        albedo: Rgb(colour) * scale,
        kd,
        gamma_s: gamma_s_deg.to_radians(),
        gamma_v: gamma_v_deg.to_radians(),
        coverage,
        // The table's curves are valid (the preset test builds every one).
        tangents: TangentCurve::new(&offsets, lengths).expect("Table II's curves are valid"),
    }
}

/// Linen plain weave (Table II, "Linen Plain"): two like threads, each tilting ±25°, covering
/// 0.33 each with gaps between.
pub fn linen_plain() -> [Thread; 2] {
    let t = || {
        let c = [0.2, 0.8, 1.0];
        thread(1.46, 0.3, c, 0.3, 12.0, 24.0, 0.33, &[-25.0, 25.0], &[1.0])
    };
    [t(), t()]
}

/// Silk crêpe de Chine (Table II): a weft rising and falling ±35° with flat stretches, a
/// straight warp.
pub fn silk_crepe_de_chine() -> [Thread; 2] {
    let c = [1.0, 0.95, 0.05];
    [
        thread(
            1.345,
            0.12,
            c,
            0.2,
            5.0,
            10.0,
            0.75,
            &[-35.0, -35.0, 35.0, 35.0],
            &[1.0, 1.0, 1.0],
        ),
        thread(1.345, 0.16, c, 0.3, 18.0, 32.0, 0.25, &[0.0, 0.0], &[1.0]),
    ]
}

/// The satin charmeuse's warp (Table II: two of three transcriptions give the albedo scale
/// 0.2, one 0.02; the majority is taken).
fn satin_warp(coverage: f64) -> Thread {
    let c = [1.0, 0.37, 0.3];
    thread(
        1.539,
        0.2,
        c,
        0.7,
        30.0,
        60.0,
        coverage,
        &[0.0, 0.0],
        &[1.0],
    )
}

/// Polyester satin charmeuse, front (Table II): long floats of a glossy weft with flat tops.
pub fn satin_charmeuse() -> [Thread; 2] {
    let c = [1.0, 0.37, 0.3];
    let offsets = [-32.0, -32.0, -18.0, 0.0, 0.0, 18.0, 32.0, 32.0];
    let lengths = [1.33, 0.66, 2.0, 2.0, 2.0, 0.66, 1.33];
    [
        thread(1.539, 0.035, c, 0.1, 2.5, 5.0, 0.9, &offsets, &lengths),
        satin_warp(0.1),
    ]
}

/// Polyester satin charmeuse, back (Table II): the weft in two families (±30° and ±5°),
/// separated by a jump.
pub fn satin_charmeuse_back() -> [Thread; 2] {
    let c = [1.0, 0.37, 0.3];
    let offsets = [-30.0, -30.0, 30.0, 30.0, -5.0, -5.0, 5.0, 5.0];
    let lengths = [1.33, 1.33, 1.33, 0.0, 0.67, 0.67, 0.67];
    [
        thread(1.539, 0.035, c, 0.1, 2.5, 5.0, 0.67, &offsets, &lengths),
        satin_warp(0.33),
    ]
}

/// Silk shot (Table II): a green weft over a red warp, for the colour shift with view.
pub fn silk_shot() -> [Thread; 2] {
    let offsets = [-25.0, -25.0, 25.0, 25.0];
    let lengths = [1.33, 2.67, 1.33];
    [
        thread(
            1.345,
            0.2,
            [0.1, 1.0, 0.4],
            0.1,
            4.0,
            8.0,
            0.86,
            &offsets,
            &lengths,
        ),
        thread(
            1.345,
            0.6,
            [1.0, 0.0, 0.1],
            0.1,
            5.0,
            10.0,
            0.14,
            &[0.0, 0.0],
            &[1.0],
        ),
    ]
}

/// Velvet (Table II): upright pile, its tangents near the normal (two of three transcriptions
/// give thread 1's second offset as −50°, one +50°; the majority is taken).
pub fn velvet() -> [Thread; 2] {
    let c = [0.05, 0.02, 0.0];
    [
        thread(1.46, 0.3, c, 0.1, 6.0, 12.0, 0.5, &[-90.0, -50.0], &[1.0]),
        thread(
            1.46,
            0.3,
            c,
            0.1,
            6.0,
            12.0,
            0.5,
            &[-90.0, -55.0, 55.0, 90.0],
            &[0.5, 0.0, 0.5],
        ),
    ]
}

/// The threads of a preset by name.
///
/// # Errors
/// [`Error::InvalidParameter`] naming `material` for an unknown name, listing the presets.
pub fn preset_threads(name: &str) -> Result<[Thread; 2]> {
    Ok(match name {
        "microcylinder-linen-plain" => linen_plain(),
        "microcylinder-silk-crepe-de-chine" => silk_crepe_de_chine(),
        "microcylinder-satin-charmeuse" => satin_charmeuse(),
        "microcylinder-satin-charmeuse-back" => satin_charmeuse_back(),
        "microcylinder-silk-shot" => silk_shot(),
        "microcylinder-velvet" => velvet(),
        _ => {
            return Err(Error::invalid(
                "material",
                format!("{name:?}"),
                format!("a microcylinder preset: {}", PRESET_NAMES.join(", ")),
            ))
        }
    })
}
