//! A woven surface as a MaterialX 1.39 document of OpenPBR Surface 1.1 (`open_pbr_surface`):
//! each yarn family's standard lobes ([`StandardSurface`]) as one `open_pbr_surface`, the two
//! mixed by the layout texture ([`LayoutImages`]) as woven mixes their BRDFs, holes black.
//!
//! | OpenPBR input | from | notes |
//! |---|---|---|
//! | `base_color` | the family's Lambertian albedo × its dye factor (`STEM-factors.png` × [`FACTOR_RANGE`]) | at most 1 per channel (`min`) |
//! | `specular_weight`, `specular_color` | the GGX weight per channel: its largest channel, and the channels over it | the weight at most [`MAX_SPECULAR_WEIGHT`] |
//! | `specular_ior` | [`PROJECTION_ETA`] (1.5) | |
//! | `specular_roughness`, `specular_roughness_anisotropy` | the GGX roughnesses by OpenPBR's own mapping ([`OpenPbrSpecular`]) | exact: no clamp |
//! | `geometry_tangent` | the rougher axis: the weft's along `u` (`tangent`) or across it, the warp's along `v` (`bitangent`) or across it | |
//! | `geometry_normal` | not set: the geometry's | the lobes hold the float's tilt (below) |
//! | `fuzz_weight`, `fuzz_color`, `fuzz_roughness` | the sheen's weight, colour and roughness | 0 while the projection fits no sheen; Zeltner's sheen, not the projection's Charlie lobe |
//! | `geometry_thin_walled` | `true`: cloth is a sheet | |
//!
//! **No normal map.** Each family's lobes are fitted to the family as the cloth shows it, its
//! whole float tilted and its facets' masking in them (the [`standard`](super) module docs, with
//! the measurement that chose it). Laying the float's tilt on again as a normal map would count
//! it twice, so the layout is `STEM-layout.png` and `STEM-factors.png`.
//!
//! **The mix.** OpenPBR's `mix` of two `surfaceshader`s is the weighted sum of their BSDFs, as
//! woven's layout mixes its families' BRDFs: `mix(weft, warp, w / (w + p))`, then `mix(that,
//! black, w + p)`, with `w` and `p` the weft's and the warp's shares (`STEM-layout.png`, red and
//! green). The black surface (`base_weight` 0, `specular_weight` 0) is a hole: woven reflects
//! nothing there.
//!
//! **Texture coordinates.** The images span one tile of [`LayoutImages::cells`] pattern cells.
//! The document multiplies the geometry's first uv set by `(n_u / cells_u, n_v / cells_v)`, with
//! `n` the surface's `yarns_per_unit`: on a uv in metres, the weave lies at `n` cells per metre,
//! as woven's own renderer lays it on the same uv. MaterialX reads images with `(0, 0)` at their
//! bottom-left corner, so the images' first row (the tile's top) is `v` at its largest, as
//! [`textures`](super::textures) writes them.
//!
//! **Which mapping.** The roughness inputs follow the nodegraph `NG_open_pbr_anisotropy` of
//! MaterialX 1.39's `libraries/bxdf/open_pbr_surface.mtlx` (`open_pbr_surface` version 1.1.1; the
//! OpenPBR 1.1 specification's "Specular anisotropy"): `α_t = r² √(2 / (1 + (1 − a)²))` along
//! the tangent, `α_b = (1 − a) α_t` across it.
//!
//! **The specular weight.** OpenPBR's `specular_weight` `ξ` scales a dielectric's Fresnel at
//! normal incidence, `F0 → ξ F0`, by changing its index (the nodegraph's `modulated_eta_s`,
//! with `ξ F0` clamped below 1), where woven's projection scales the whole GGX lobe: the two
//! agree at normal incidence; toward grazing OpenPBR's Fresnel still rises to 1, so a weight above
//! 1 reflects less there than the projection's lobe, and one below 1 more. Its
//! `specular_color` is a tint of the dielectric's reflection (in `[0, 1]`), which carries the
//! channels' ratios.

use super::textures::{LayoutFiles, LayoutImages, FACTOR_RANGE};
use super::{StandardFamily, StandardSurface};
use crate::error::FitError;
use crate::projection::PROJECTION_ETA;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The largest `specular_weight` written: `1 / F0` at the index [`PROJECTION_ETA`] (25), where
/// OpenPBR's modulated Fresnel at normal incidence reaches 1 (its nodegraph clamps `ξ F0` to
/// 0.99999). Projections stay far below it.
pub const MAX_SPECULAR_WEIGHT: f64 = 1.0 / F0_AT_ETA;

/// A dielectric's Fresnel reflectance at normal incidence for [`PROJECTION_ETA`]: 0.04.
const F0_AT_ETA: f64 = ((PROJECTION_ETA - 1.0) / (PROJECTION_ETA + 1.0))
    * ((PROJECTION_ETA - 1.0) / (PROJECTION_ETA + 1.0));

/// One family's GGX lobe as OpenPBR's inputs (module docs, "Which mapping").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OpenPbrSpecular {
    /// `specular_roughness` `r`, in `[0, 1]`: `r² = √((α_t² + α_b²) / 2)`.
    pub roughness: f64,
    /// `specular_roughness_anisotropy` `a`, in `[0, 1)`: `1 − α_b / α_t`.
    pub anisotropy: f64,
    /// Whether `geometry_tangent` (the rougher axis) runs along the yarn, else across it.
    pub along_yarn: bool,
}

impl OpenPbrSpecular {
    /// The inputs that render the roughnesses `alpha`, `[along the yarn, across it]` (each in
    /// `(0, 1]`): the inverse of OpenPBR's mapping, exact.
    pub fn of_alpha(alpha: [f64; 2]) -> OpenPbrSpecular {
        let [along, across] = alpha;
        let (t, b) = (along.max(across), along.min(across));
        OpenPbrSpecular {
            roughness: ((t * t + b * b) / 2.0).sqrt().sqrt(),
            anisotropy: if t > 0.0 { 1.0 - b / t } else { 0.0 },
            along_yarn: along >= across,
        }
    }

    /// The roughnesses OpenPBR renders, `[along the yarn, across it]`: its nodegraph
    /// `NG_open_pbr_anisotropy` evaluated.
    pub fn alpha(&self) -> [f64; 2] {
        let inverse = 1.0 - self.anisotropy;
        let t = self.roughness * self.roughness * (2.0 / (1.0 + inverse * inverse)).sqrt();
        let b = inverse * t;
        if self.along_yarn {
            [t, b]
        } else {
            [b, t]
        }
    }
}

/// A family's GGX weight per channel as OpenPBR's `specular_weight` (its largest channel, at
/// most [`MAX_SPECULAR_WEIGHT`]) and `specular_color` (each channel over that largest; white
/// where the weight is 0).
pub fn specular_weight(family: &StandardFamily) -> (f64, [f64; 3]) {
    let top = family.specular.iter().copied().fold(0.0, f64::max);
    if top > 0.0 {
        (
            top.min(MAX_SPECULAR_WEIGHT),
            // Each channel over the largest is in [0, 1]; the clamp only guards rounding.
            family.specular.map(|s| (s / top).clamp(0.0, 1.0)),
        )
    } else {
        (0.0, [1.0; 3])
    }
}

/// The files [`write()`] writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OpenPbrFiles {
    /// The MaterialX document.
    pub document: PathBuf,
    /// The textures it reads, beside it.
    pub textures: LayoutFiles,
}

/// Writes `surface` laid out by `images` as the MaterialX document `path` (`STEM.mtlx`) and the
/// layout's two textures beside it (`STEM-layout.png`, `STEM-factors.png`,
/// [`LayoutImages::write`]), each file whole or not at all; the document names them relative to
/// itself (module docs: no normal map).
///
/// # Errors
/// [`FitError::InvalidParameter`] naming `transmission` for a surface that lets light through
/// ([`check_spec`](super::check_spec)) or `path` when it has no file name;
/// [`FitError::Material`] holding the I/O error that names a file that cannot be written.
pub fn write(
    surface: &StandardSurface,
    images: &LayoutImages,
    path: &Path,
) -> Result<OpenPbrFiles, FitError> {
    super::refuse_transmission(surface.translucent.is_some())?;
    let (folder, stem) = folder_and_stem(path)?;
    let textures = images.write(&folder, &stem)?;
    let text = document(surface, images, &stem);
    woven::fsutil::atomic_write(path, |out| out.write_all(text.as_bytes()))?;
    Ok(OpenPbrFiles {
        document: path.to_path_buf(),
        textures,
    })
}

/// The folder a file goes in and its stem (its name without the extension).
///
/// # Errors
/// [`FitError::InvalidParameter`] naming `path` when it has no file name.
pub(crate) fn folder_and_stem(path: &Path) -> Result<(PathBuf, String), FitError> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty() && path.file_name().is_some());
    let Some(stem) = stem else {
        return Err(FitError::invalid(
            "path",
            path.display(),
            "a file's path (a name to write, such as cloth.mtlx)",
        ));
    };
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    Ok((folder, stem))
}

/// The MaterialX document of `surface` laid out by `images`, whose textures are
/// `STEM-layout.png` and `STEM-factors.png` beside it (module docs).
pub fn document(surface: &StandardSurface, images: &LayoutImages, stem: &str) -> String {
    let mut x = Xml::default();
    x.line(r#"<?xml version="1.0"?>"#);
    x.line(r#"<materialx version="1.39" colorspace="lin_rec709">"#);
    x.comment(&format!(
        "woven {}: a woven surface on OpenPBR Surface 1.1, each yarn family's standard lobes \
         mixed by its layout. One tile of {}x{} pattern cells; uv in metres at {}x{} cells per \
         metre. Mixture RMS log error: weft {:.3}, warp {:.3} (one isotropic GGX + Lambert: \
         {:.3}, {:.3}).",
        env!("CARGO_PKG_VERSION"),
        images.cells[0],
        images.cells[1],
        surface.yarns_per_unit[0],
        surface.yarns_per_unit[1],
        surface.weft.rms_log,
        surface.warp.rms_log,
        surface.weft.isotropic_rms_log,
        surface.warp.isotropic_rms_log,
    ));
    texture_nodes(&mut x, surface, images, stem);
    family_surface(&mut x, "weft", &surface.weft);
    family_surface(&mut x, "warp", &surface.warp);
    mix_nodes(&mut x, stem);
    x.line("</materialx>");
    x.out
}

/// The texture coordinate, the three images and what is read from them.
fn texture_nodes(x: &mut Xml, surface: &StandardSurface, images: &LayoutImages, stem: &str) {
    use Input::{Node, Value};
    let scale = [0, 1].map(|k| surface.yarns_per_unit[k] / images.cells[k] as f64);
    x.node(
        "texcoord",
        "uv",
        "vector2",
        &[Value("index", "integer", "0".into())],
    );
    x.node(
        "multiply",
        "tile_uv",
        "vector2",
        &[
            Node("in1", "vector2", "uv"),
            Value(
                "in2",
                "vector2",
                format!("{}, {}", num(scale[0]), num(scale[1])),
            ),
        ],
    );
    for (name, file) in [("layout_image", "layout"), ("factors_image", "factors")] {
        x.node(
            "image",
            name,
            "vector3",
            &[
                Value("file", "filename", format!("{stem}-{file}.png")),
                Node("texcoord", "vector2", "tile_uv"),
            ],
        );
    }
    for (name, image, index) in [
        ("weft_share", "layout_image", 0),
        ("warp_share", "layout_image", 1),
        ("weft_factor_stored", "factors_image", 0),
        ("warp_factor_stored", "factors_image", 1),
    ] {
        x.node(
            "extract",
            name,
            "float",
            &[
                Node("in", "vector3", image),
                Value("index", "integer", index.to_string()),
            ],
        );
    }
    for family in ["weft", "warp"] {
        x.node(
            "multiply",
            &format!("{family}_factor"),
            "float",
            &[
                Node("in1", "float", &format!("{family}_factor_stored")),
                Value("in2", "float", num(FACTOR_RANGE)),
            ],
        );
    }
    // World space, as `geometry_tangent`'s default (`Tworld`).
    let world = || [Value("space", "string", "world".into())];
    x.node("tangent", "u_tangent", "vector3", &world());
    x.node("bitangent", "v_tangent", "vector3", &world());
}

/// One family's `open_pbr_surface` (`NAME_surface`) and its base colour (`NAME_base_color`).
fn family_surface(x: &mut Xml, name: &str, family: &StandardFamily) {
    use Input::{Node, Value};
    let rgb = |c: [f64; 3]| format!("{}, {}, {}", num(c[0]), num(c[1]), num(c[2]));
    let base = format!("{name}_base_color");
    x.node(
        "multiply",
        &format!("{name}_dyed"),
        "color3",
        &[
            Value("in1", "color3", rgb(family.diffuse)),
            Node("in2", "float", &format!("{name}_factor")),
        ],
    );
    // A reflectance: a dye factor above 1 may not lift a channel past 1.
    x.node(
        "min",
        &base,
        "color3",
        &[
            Node("in1", "color3", &format!("{name}_dyed")),
            Value("in2", "float", "1".into()),
        ],
    );
    let spec = family.openpbr();
    let (weight, tint) = specular_weight(family);
    // The weft runs along u, the warp along v: the rougher axis is the yarn's or the one across.
    let along_u = (name == "weft") == spec.along_yarn;
    let sheen_top = family.sheen.iter().copied().fold(0.0, f64::max);
    let sheen_tint = if sheen_top > 0.0 {
        family.sheen.map(|s| s / sheen_top)
    } else {
        [1.0; 3]
    };
    x.node(
        "open_pbr_surface",
        &format!("{name}_surface"),
        "surfaceshader",
        &[
            Value("base_weight", "float", "1".into()),
            Node("base_color", "color3", &base),
            Value("base_metalness", "float", "0".into()),
            Value("specular_weight", "float", num(weight)),
            Value("specular_color", "color3", rgb(tint)),
            Value("specular_roughness", "float", num(spec.roughness)),
            Value(
                "specular_roughness_anisotropy",
                "float",
                num(spec.anisotropy),
            ),
            Value("specular_ior", "float", num(PROJECTION_ETA)),
            // OpenPBR's fuzz_weight is a presence in [0, 1], as the projection's sheen weight.
            Value("fuzz_weight", "float", num(sheen_top.min(1.0))),
            Value("fuzz_color", "color3", rgb(sheen_tint)),
            Value("fuzz_roughness", "float", num(family.lobes.sheen_roughness)),
            Value("geometry_thin_walled", "boolean", "true".into()),
            Node(
                "geometry_tangent",
                "vector3",
                if along_u { "u_tangent" } else { "v_tangent" },
            ),
        ],
    );
}

/// The hole's black surface, the families' mix by their shares, and the material.
fn mix_nodes(x: &mut Xml, stem: &str) {
    use Input::{Node, Value};
    x.node(
        "open_pbr_surface",
        "hole_surface",
        "surfaceshader",
        &[
            Value("base_weight", "float", "0".into()),
            Value("specular_weight", "float", "0".into()),
            Value("geometry_thin_walled", "boolean", "true".into()),
        ],
    );
    x.node(
        "add",
        "yarn_share",
        "float",
        &[
            Node("in1", "float", "weft_share"),
            Node("in2", "float", "warp_share"),
        ],
    );
    // The shares sum to at most 1; 16-bit rounding may pass it by 1/65535.
    x.node(
        "clamp",
        "yarn_cover",
        "float",
        &[Node("in", "float", "yarn_share")],
    );
    // A hole has no yarn: any weft share there, 0 / (0 + tiny), mixes nothing in.
    x.node(
        "max",
        "yarn_share_nonzero",
        "float",
        &[
            Node("in1", "float", "yarn_share"),
            Value("in2", "float", "0.000001".into()),
        ],
    );
    x.node(
        "divide",
        "weft_of_yarns",
        "float",
        &[
            Node("in1", "float", "weft_share"),
            Node("in2", "float", "yarn_share_nonzero"),
        ],
    );
    x.node(
        "mix",
        "yarns",
        "surfaceshader",
        &[
            Node("fg", "surfaceshader", "weft_surface"),
            Node("bg", "surfaceshader", "warp_surface"),
            Node("mix", "float", "weft_of_yarns"),
        ],
    );
    x.node(
        "mix",
        "woven_surface",
        "surfaceshader",
        &[
            Node("fg", "surfaceshader", "yarns"),
            Node("bg", "surfaceshader", "hole_surface"),
            Node("mix", "float", "yarn_cover"),
        ],
    );
    x.node(
        "surfacematerial",
        &material_name(stem),
        "material",
        &[Node("surfaceshader", "surfaceshader", "woven_surface")],
    );
}

/// A number as the document writes it: at most 6 decimals (a millionth of a roughness or a
/// weight), trailing zeros dropped.
fn num(x: f64) -> String {
    let text = format!("{x:.6}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    match text {
        "" | "-" | "-0" => "0".to_string(),
        t => t.to_string(),
    }
}

/// A MaterialX element name from a file's stem: letters, digits and `_` (others become `_`),
/// not starting with a digit.
fn material_name(stem: &str) -> String {
    let name: String = stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    match name.chars().next() {
        Some(c) if c.is_ascii_alphabetic() => name,
        _ => format!("M_{name}"),
    }
}

/// An input of a node: a value, or another node's output.
enum Input<'a> {
    Value(&'a str, &'a str, String),
    Node(&'a str, &'a str, &'a str),
}

/// A MaterialX document's text, indented.
#[derive(Default)]
struct Xml {
    out: String,
}

impl Xml {
    fn line(&mut self, text: &str) {
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn comment(&mut self, text: &str) {
        // "--" may not appear inside an XML comment.
        let _ = writeln!(self.out, "  <!-- {} -->", text.replace("--", "- -"));
    }

    fn node(&mut self, kind: &str, name: &str, ty: &str, inputs: &[Input]) {
        let _ = write!(self.out, r#"  <{kind} name="{}" type="{ty}""#, escape(name));
        if inputs.is_empty() {
            self.out.push_str(" />\n");
            return;
        }
        self.out.push_str(">\n");
        for input in inputs {
            let (name, ty, attr, value) = match input {
                Input::Value(n, t, v) => (n, t, "value", v.as_str()),
                Input::Node(n, t, v) => (n, t, "nodename", *v),
            };
            let _ = writeln!(
                self.out,
                r#"    <input name="{name}" type="{ty}" {attr}="{}" />"#,
                escape(value)
            );
        }
        let _ = writeln!(self.out, "  </{kind}>");
    }
}

/// `text` as an XML attribute value.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if c.is_control() => {
                let _ = write!(out, "&#{};", u32::from(c));
            }
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn openpbrs_mapping_round_trips_the_roughnesses_either_way_round() {
        for alpha in [
            [0.05, 0.4],
            [0.4, 0.05],
            [0.2, 0.2],
            [1.0, 0.001],
            [0.001, 1.0],
        ] {
            let s = OpenPbrSpecular::of_alpha(alpha);
            assert!((0.0..=1.0).contains(&s.roughness) && (0.0..1.0).contains(&s.anisotropy));
            assert_eq!(s.along_yarn, alpha[0] >= alpha[1]);
            let back = s.alpha();
            for k in 0..2 {
                assert!(
                    (back[k] / alpha[k] - 1.0).abs() < 1e-12,
                    "{alpha:?} → {s:?} → {back:?}"
                );
            }
        }
        // Isotropic: OpenPBR's r² is α, as every GGX parametrisation has it.
        let s = OpenPbrSpecular::of_alpha([0.09, 0.09]);
        assert!((s.roughness - 0.3).abs() < 1e-12 && s.anisotropy == 0.0);
    }

    #[test]
    fn names_and_values_are_escaped_for_xml() {
        assert_eq!(escape(r#"a&b<"c">"#), "a&amp;b&lt;&quot;c&quot;&gt;");
        assert_eq!(material_name("3 silk-shot"), "M_3_silk_shot");
        assert_eq!(material_name("silk"), "silk");
        assert_eq!(
            (num(0.25), num(2.0), num(1e-9), num(0.1234567)),
            ("0.25".into(), "2".into(), "0".into(), "0.123457".into())
        );
        assert!(folder_and_stem(Path::new("/")).is_err());
        let (folder, stem) = folder_and_stem(Path::new("cloth.mtlx")).unwrap();
        assert_eq!((folder, stem.as_str()), (PathBuf::from("."), "cloth"));
    }
}
