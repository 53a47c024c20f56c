//! The checks of a parsed scene file: every value against its valid range, every reference
//! against what the file defines; the result is a [`SceneDescription`]. Each error names the
//! file, the key, the value and what was expected.

use super::parse::{
    line_of, RawCamera, RawCloth, RawFilm, RawInset, RawIntegrator, RawLight, RawMaterial,
    RawScene, RawShape,
};
use super::{
    CameraSpec, Film, InsetSpec, IntegratorSettings, LightDesc, MaterialDesc, MeshSource,
    SceneDescription, ShapeDesc, Strategy, MAX_EXPOSURE, MAX_FILM_SIDE, MAX_SPP,
    SAMPLING_WEIGHT_RANGE,
};
use crate::color::Rgb;
use crate::rng::SamplerKind;
use crate::shapes::{builtin_obj, Cloth, Drape, BUILTIN_MESHES, BUILTIN_PREFIX};
use crate::sky::{Sky, SkyParams};
use crate::tonemap::Display;
use crate::woven_material::WovenSpec;
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::path::Path;
use toml::Spanned;
use woven::baseline::{Distribution, RoughPlastic, RoughPlasticParams, Sheen, SheenParams};
use woven::fsutil::check_regular;
use woven::keys::{KeySource, Keys};
use woven::material::MAX_FILE_BYTES;
use woven::microcylinder::Microcylinder;
use woven::surface::SurfaceSpec;
use woven::Vec3;

/// Checks a parsed file (`text`, named `origin` in messages; relative paths resolve against
/// `base`) table by table, in the file format's order: camera, film, integrator, lights,
/// materials, shapes.
///
/// # Errors
/// [`Error::Scene`] for the first value out of range or reference to nothing.
pub(super) fn check(
    raw: RawScene,
    text: &str,
    origin: &str,
    base: &Path,
) -> Result<SceneDescription> {
    let c = Checker { origin, text, base };
    let camera = camera(&c, raw.camera)?;
    let film = film(&c, raw.film)?;
    let inset = match raw.inset {
        Some(i) => Some(inset(&c, i)?),
        None => None,
    };
    let integrator = integrator(&c, raw.integrator)?;
    let (lights, light_weights) = lights(&c, raw.light)?;
    let materials = materials(&c, raw.material)?;
    let shapes = shapes(&c, raw.shape, &materials)?;
    Ok(SceneDescription {
        origin: origin.to_string(),
        camera,
        inset,
        film,
        integrator,
        lights,
        light_weights,
        shapes,
        materials,
    })
}

/// `[camera]`.
fn camera(c: &Checker, raw: Spanned<RawCamera>) -> Result<CameraSpec> {
    let at = raw.span().start;
    let cam = raw.into_inner();
    view(c, "camera", at, cam.origin, cam.target, cam.up, cam.fov_deg)
}

/// A camera's `origin`, `target`, `up` and `fov_deg`, under the table `table`.
fn view(
    c: &Checker,
    table: &str,
    at: usize,
    origin: [f64; 3],
    target: [f64; 3],
    up: [f64; 3],
    fov_deg: f64,
) -> Result<CameraSpec> {
    let origin_v = c.vec(&format!("{table}.origin"), at, origin)?;
    let target = c.vec(&format!("{table}.target"), at, target)?;
    let up = c.nonzero(&format!("{table}.up"), at, up)?;
    if (target - origin_v).length() <= 0.0 {
        return Err(c.err(
            &format!("{table}.target"),
            at,
            format!("equals {table}.origin: nothing to look at"),
        ));
    }
    if (target - origin_v)
        .normalize()
        .cross(up.normalize())
        .length()
        < 1e-9
    {
        return Err(c.err(&format!("{table}.up"), at, "parallel to the view direction"));
    }
    if !(fov_deg > 0.0 && fov_deg < 180.0) {
        return Err(c.err(
            &format!("{table}.fov_deg"),
            at,
            format!("{fov_deg}: expected degrees in (0, 180)"),
        ));
    }
    Ok(CameraSpec {
        origin: origin_v,
        target,
        up,
        fov_deg,
    })
}

/// `[inset]`: its camera, and a rectangle inside the film (fractions of its sides).
fn inset(c: &Checker, raw: Spanned<RawInset>) -> Result<InsetSpec> {
    let at = raw.span().start;
    let i = raw.into_inner();
    let camera = view(c, "inset", at, i.origin, i.target, i.up, i.fov_deg)?;
    let border = c.range("inset.border", at, i.border, 0, 64)?;
    for k in 0..2 {
        let (axis, corner, size) = (["x", "y"][k], i.corner[k], i.size[k]);
        if !(0.0..1.0).contains(&corner) {
            return Err(c.err(
                "inset.corner",
                at,
                format!("{corner} ({axis}): expected a fraction of the film in [0, 1)"),
            ));
        }
        if !(size > 0.0 && corner + size <= 1.0 + 1e-9) {
            return Err(c.err(
                "inset.size",
                at,
                format!(
                    "{size} ({axis}): expected a fraction of the film in (0, {}], so the inset \
                     ends inside the film",
                    // Rounded to 1e-9, so that 1 − 0.9 reads 0.1.
                    ((1.0 - corner) * 1e9).round() / 1e9
                ),
            ));
        }
    }
    Ok(InsetSpec {
        camera,
        corner: i.corner,
        size: i.size,
        border,
    })
}

/// A mesh's `file`: a path against the scene's folder, or `builtin:NAME`.
fn mesh_source(c: &Checker, key: &str, at: usize, file: &str) -> Result<MeshSource> {
    let Some(name) = file.strip_prefix(BUILTIN_PREFIX) else {
        return Ok(MeshSource::File(c.base.join(file)));
    };
    match builtin_obj(name) {
        Some((n, _)) => Ok(MeshSource::Builtin(n)),
        None => {
            let known: Vec<String> = BUILTIN_MESHES
                .iter()
                .map(|(n, _)| format!("{BUILTIN_PREFIX}{n}"))
                .collect();
            Err(c.err(
                key,
                at,
                format!(
                    "`{file}`: no such built-in mesh (there are {})",
                    known.join(", ")
                ),
            ))
        }
    }
}

/// `[film]` (absent: the defaults).
fn film(c: &Checker, raw: Option<Spanned<RawFilm>>) -> Result<Film> {
    Ok(match raw {
        None => Film {
            width: 512,
            height: 512,
            spp: 64,
            seed: 0,
            sampler: SamplerKind::default(),
            first_sample: 0,
            display: Display::default(),
            denoise: false,
        },
        Some(f) => {
            let at = f.span().start;
            let f = f.into_inner();
            let side = MAX_FILM_SIDE as i64;
            let film = Film {
                width: c.range("film.width", at, f.width, 1, side)?,
                height: c.range("film.height", at, f.height, 1, side)?,
                spp: c.range("film.spp", at, f.spp, 1, MAX_SPP as i64)?,
                seed: f.seed,
                sampler: f.sampler,
                first_sample: 0,
                display: Display {
                    exposure: c.within("film.exposure", at, f.exposure, MAX_EXPOSURE)?,
                    tonemap: f.tonemap,
                },
                denoise: f.denoise,
            };
            crate::render::check_film_budget(film.width, film.height, film.denoise)
                .map_err(|e| c.err("film", at, e.to_string()))?;
            film
        }
    })
}

/// `[integrator]` (absent: the defaults).
fn integrator(c: &Checker, raw: Option<Spanned<RawIntegrator>>) -> Result<IntegratorSettings> {
    Ok(match raw {
        None => IntegratorSettings {
            max_depth: Some(16),
            hide_emitters: false,
            strategy: Strategy::Mis,
            rr_depth: 5,
            footprint_filter: true,
        },
        Some(i) => {
            let at = i.span().start;
            let i = i.into_inner();
            let max_depth = match i.max_depth {
                -1 => None,
                d if (1..=1024).contains(&d) => Some(d as u32),
                d => {
                    return Err(c.err(
                        "integrator.max_depth",
                        at,
                        format!("{d}: expected 1..=1024, or -1 for unlimited"),
                    ))
                }
            };
            IntegratorSettings {
                max_depth,
                hide_emitters: i.hide_emitters,
                strategy: i.strategy,
                rr_depth: c.range("integrator.rr_depth", at, i.rr_depth, 1, 1024)? as u32,
                footprint_filter: i.footprint_filter,
            }
        }
    })
}

/// `[[light]]`: the lights in file order and their sampling weights.
fn lights(c: &Checker, raw: Vec<Spanned<RawLight>>) -> Result<(Vec<LightDesc>, Vec<f64>)> {
    let mut lights = Vec::new();
    let mut light_weights = Vec::new();
    let mut environments = 0;
    for (k, l) in raw.into_iter().enumerate() {
        let at = l.span().start;
        let key = format!("light[{k}]");
        let l = l.into_inner();
        let weight = l.sampling_weight();
        let (lo, hi) = SAMPLING_WEIGHT_RANGE;
        if !(lo..=hi).contains(&weight) {
            return Err(c.err(
                &format!("{key}.sampling_weight"),
                at,
                format!("{weight:e}: expected a number in [{lo:e}, {hi:e}] (only ratios matter)"),
            ));
        }
        light_weights.push(weight);
        lights.push(match l {
            RawLight::Point {
                position,
                intensity,
                ..
            } => LightDesc::Point {
                position: c.vec(&format!("{key}.position"), at, position)?,
                intensity: c.rgb(&format!("{key}.intensity"), at, intensity, None)?,
            },
            RawLight::Environment {
                radiance,
                file,
                scale,
                ..
            } => {
                environments += 1;
                if environments > 1 {
                    return Err(c.err(&key, at, "a second environment: a scene has at most one"));
                }
                if !(scale.is_finite() && scale >= 0.0) {
                    return Err(c.err(
                        &format!("{key}.scale"),
                        at,
                        format!("{scale}: expected a finite number >= 0"),
                    ));
                }
                match (radiance, file) {
                    (Some(r), None) => LightDesc::EnvironmentConstant {
                        radiance: c.rgb(&format!("{key}.radiance"), at, r, None)?,
                        scale,
                    },
                    (None, Some(f)) => LightDesc::EnvironmentMap {
                        path: c.base.join(f),
                        scale,
                    },
                    _ => {
                        return Err(c.err(
                            &key,
                            at,
                            "an environment takes exactly one of `radiance` and `file`",
                        ))
                    }
                }
            }
            RawLight::Sky {
                sun_elevation_deg,
                sun_azimuth_deg,
                turbidity,
                scale,
                sun,
                ..
            } => {
                environments += 1;
                if environments > 1 {
                    return Err(c.err(&key, at, "a second environment: a scene has at most one"));
                }
                let params = SkyParams {
                    sun_elevation_deg,
                    sun_azimuth_deg,
                    turbidity,
                    scale,
                    sun,
                };
                // The sky's own checks, its messages under this light's key.
                match Sky::new(&params) {
                    Ok(_) => LightDesc::Sky { params },
                    Err(Error::InvalidSetting {
                        name,
                        value,
                        expected,
                    }) => {
                        return Err(c.err(
                            &format!("{key}.{name}"),
                            at,
                            format!("{value}: expected {expected}"),
                        ))
                    }
                    Err(e) => return Err(e),
                }
            }
            RawLight::Rectangle {
                corner,
                edge_u,
                edge_v,
                radiance,
                ..
            } => {
                let (edge_u, edge_v) = c.edges(&key, at, edge_u, edge_v)?;
                LightDesc::Rectangle {
                    corner: c.vec(&format!("{key}.corner"), at, corner)?,
                    edge_u,
                    edge_v,
                    radiance: c.rgb(&format!("{key}.radiance"), at, radiance, None)?,
                }
            }
        });
    }
    Ok((lights, light_weights))
}

/// `[material.NAME]`.
fn materials(
    c: &Checker,
    raw: BTreeMap<String, Spanned<RawMaterial>>,
) -> Result<BTreeMap<String, MaterialDesc>> {
    let mut materials = BTreeMap::new();
    for (name, m) in raw {
        let at = m.span().start;
        let key = format!("material.{name}");
        let desc = match m.into_inner() {
            RawMaterial::Diffuse { reflectance } => MaterialDesc::Diffuse {
                reflectance: c.rgb(&format!("{key}.reflectance"), at, reflectance, Some(1.0))?,
            },
            RawMaterial::Woven(w) => MaterialDesc::Woven(Box::new(woven(c, &key, at, w)?)),
            RawMaterial::Microcylinder { material } => {
                MaterialDesc::Microcylinder(Box::new(microcylinder(c, &key, at, &material)?))
            }
            RawMaterial::Roughplastic {
                diffuse_reflectance,
                distribution,
                alpha,
                int_ior,
                ext_ior,
                nonlinear,
            } => {
                let d = RoughPlasticParams::default();
                let distribution = match distribution.as_deref() {
                    None => d.distribution,
                    Some(name) => Distribution::parse(name).ok_or_else(|| {
                        c.err(
                            &format!("{key}.distribution"),
                            at,
                            format!("{name:?}: expected {}", Distribution::NAMES),
                        )
                    })?,
                };
                let params = RoughPlasticParams {
                    distribution,
                    alpha: alpha.unwrap_or(d.alpha),
                    int_ior: int_ior.unwrap_or(d.int_ior),
                    ext_ior: ext_ior.unwrap_or(d.ext_ior),
                    diffuse_reflectance: match diffuse_reflectance {
                        Some(v) => {
                            c.rgb(&format!("{key}.diffuse_reflectance"), at, v, Some(1.0))?
                        }
                        None => d.diffuse_reflectance,
                    },
                    nonlinear: nonlinear.unwrap_or(d.nonlinear),
                    ..d
                };
                let built =
                    RoughPlastic::new(&params).map_err(|e| c.err(&key, at, e.to_string()))?;
                MaterialDesc::RoughPlastic(Box::new(built))
            }
            RawMaterial::Sheen {
                diffuse_reflectance,
                sheen_color,
                roughness,
            } => {
                let d = SheenParams::default();
                let colour = |k: &str, v: Option<[f64; 3]>, default: Rgb| match v {
                    Some(v) => c.rgb(&format!("{key}.{k}"), at, v, Some(1.0)),
                    None => Ok(default),
                };
                let params = SheenParams {
                    diffuse: colour("diffuse_reflectance", diffuse_reflectance, d.diffuse)?,
                    sheen_color: colour("sheen_color", sheen_color, d.sheen_color)?,
                    roughness: roughness.unwrap_or(d.roughness),
                };
                let built = Sheen::new(&params).map_err(|e| c.err(&key, at, e.to_string()))?;
                MaterialDesc::Sheen(Box::new(built))
            }
        };
        materials.insert(name, desc);
    }
    Ok(materials)
}

/// A `type = "woven"` material at `key`: the library reads its keys
/// ([`SurfaceSpec::from_keys`], whose `material` and `pattern = { wif = … }` files resolve
/// against the scene's folder); the scene keeps what is its own: where an error points, and the
/// two keys that belong to another table or that `woven render` does not take.
fn woven(c: &Checker, key: &str, at: usize, raw: toml::Table) -> Result<WovenSpec> {
    let keys = Keys::from(raw).in_folder(c.base);
    let read = SurfaceSpec::from_keys(&keys).map_err(|e| {
        let message = match (&e.error, keys.get("material")) {
            // A material file's own error names the file: say which material it was.
            (woven::Error::InvalidParameter { .. }, _) | (_, None) => e.to_string(),
            (error, Some(m)) if e.key == "material" => format!("{m}: {error}"),
            _ => e.to_string(),
        };
        c.err(&format!("{key}.{}", e.key), at, message)
    })?;
    let wavelength = format!(
        "left out: `woven render` builds every table at {} nm",
        crate::woven_material::WAVELENGTH_NM
    );
    for (name, instead) in [
        (
            "footprint_filter",
            "a key of [integrator] in scenes (footprint_filter = false there)",
        ),
        ("wavelength_nm", wavelength.as_str()),
    ] {
        if read.given(name) {
            return Err(c.err(
                &format!("{key}.{name}"),
                at,
                format!("not a material key here: {instead}"),
            ));
        }
    }
    Ok(read.spec)
}

/// A `type = "microcylinder"` material at `key`: a preset's name or a file beside the scene.
fn microcylinder(c: &Checker, key: &str, at: usize, material: &str) -> Result<Microcylinder> {
    let mkey = format!("{key}.material");
    if Microcylinder::preset_names().contains(&material) {
        return Microcylinder::preset(material).map_err(|e| c.err(&mkey, at, e.to_string()));
    }
    let path = c.base.join(material);
    check_regular(&path, MAX_FILE_BYTES, "a material file")
        .and_then(|_| Microcylinder::from_path(&path))
        .map_err(|e| {
            c.err(
                &mkey,
                at,
                format!(
                    "`{material}`: {e} (the presets: {})",
                    Microcylinder::preset_names().join(", ")
                ),
            )
        })
}

/// `[[shape]]`, each with its material's name, which `materials` must define.
fn shapes(
    c: &Checker,
    raw: Vec<Spanned<RawShape>>,
    materials: &BTreeMap<String, MaterialDesc>,
) -> Result<Vec<(ShapeDesc, String)>> {
    let mut shapes = Vec::new();
    for (k, s) in raw.into_iter().enumerate() {
        let at = s.span().start;
        let key = format!("shape[{k}]");
        let (desc, material) = match s.into_inner() {
            RawShape::Sphere {
                center,
                radius,
                material,
            } => (
                ShapeDesc::Sphere {
                    center: c.vec(&format!("{key}.center"), at, center)?,
                    radius: c.positive(&format!("{key}.radius"), at, radius)?,
                },
                material,
            ),
            RawShape::Rectangle {
                corner,
                edge_u,
                edge_v,
                material,
            } => {
                let (edge_u, edge_v) = c.edges(&key, at, edge_u, edge_v)?;
                (
                    ShapeDesc::Rectangle {
                        corner: c.vec(&format!("{key}.corner"), at, corner)?,
                        edge_u,
                        edge_v,
                    },
                    material,
                )
            }
            RawShape::Cylinder {
                base: b,
                axis,
                radius,
                material,
            } => (
                ShapeDesc::Cylinder {
                    base: c.vec(&format!("{key}.base"), at, b)?,
                    axis: c.nonzero(&format!("{key}.axis"), at, axis)?,
                    radius: c.positive(&format!("{key}.radius"), at, radius)?,
                },
                material,
            ),
            RawShape::Mesh {
                file,
                scale,
                translate,
                material,
            } => (
                ShapeDesc::Mesh {
                    source: mesh_source(c, &format!("{key}.file"), at, &file)?,
                    scale: c.positive(&format!("{key}.scale"), at, scale)?,
                    translate: c.vec(&format!("{key}.translate"), at, translate)?,
                },
                material,
            ),
            RawShape::Cloth(raw) => cloth(c, &key, at, raw)?,
        };
        if !materials.contains_key(&material) {
            let known: Vec<&str> = materials.keys().map(String::as_str).collect();
            return Err(c.err(
                &format!("{key}.material"),
                at,
                format!(
                    "`{material}` is not defined: add a [material.{material}] table (defined: {})",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            ));
        }
        shapes.push((desc, material));
    }
    Ok(shapes)
}

/// A `type = "cloth"` shape at `key`: hanging in folds, or draped over a sphere.
fn cloth(c: &Checker, key: &str, at: usize, raw: RawCloth) -> Result<(ShapeDesc, String)> {
    let RawCloth {
        corner,
        edge_u,
        edge_v,
        folds,
        amplitude,
        taper,
        resolution,
        drape,
        center,
        radius,
        material,
    } = raw;
    let (edge_u, edge_v) = c.edges(key, at, edge_u, edge_v)?;
    let over_sphere = match drape.as_deref() {
        None | Some("folds") => false,
        Some("sphere") => true,
        Some(other) => {
            return Err(c.err(
                &format!("{key}.drape"),
                at,
                format!("`{other}`: expected \"folds\" (the default) or \"sphere\""),
            ))
        }
    };
    if !over_sphere {
        if let Some(k) = [("center", center.is_some()), ("radius", radius.is_some())]
            .into_iter()
            .find_map(|(k, given)| given.then_some(k))
        {
            return Err(c.err(
                &format!("{key}.{k}"),
                at,
                "a cloth's sphere is only for drape = \"sphere\"",
            ));
        }
    }
    if !(folds.is_finite() && (0.0..=1000.0).contains(&folds)) {
        return Err(c.err(
            &format!("{key}.folds"),
            at,
            format!("{folds}: expected a number in [0, 1000]"),
        ));
    }
    if !amplitude.is_finite() {
        return Err(c.err(
            &format!("{key}.amplitude"),
            at,
            format!("{amplitude}: expected a finite number"),
        ));
    }
    if !(0.0..=1.0).contains(&taper) {
        return Err(c.err(
            &format!("{key}.taper"),
            at,
            format!("{taper}: expected a number in [0, 1]"),
        ));
    }
    let rkey = format!("{key}.resolution");
    let resolution = [
        c.range(&rkey, at, resolution[0], 1, 4096)?,
        c.range(&rkey, at, resolution[1], 1, 4096)?,
    ];
    crate::shapes::check_triangle_budget(
        crate::shapes::grid_triangles(resolution),
        &format!("a cloth of resolution {resolution:?}"),
    )
    .map_err(|e| c.err(&rkey, at, e.to_string()))?;
    if over_sphere {
        let missing = |k: &str| {
            c.err(
                &format!("{key}.{k}"),
                at,
                "missing: drape = \"sphere\" needs the sphere's `center` and `radius`",
            )
        };
        let center = center.ok_or_else(|| missing("center"))?;
        let radius = radius.ok_or_else(|| missing("radius"))?;
        let drape = Drape {
            corner: c.vec(&format!("{key}.corner"), at, corner)?,
            edge_u,
            edge_v,
            center: c.vec(&format!("{key}.center"), at, center)?,
            radius: c.positive(&format!("{key}.radius"), at, radius)?,
            folds,
            amplitude,
            resolution,
        };
        Ok((ShapeDesc::Drape(drape), material))
    } else {
        let cloth = Cloth {
            corner: c.vec(&format!("{key}.corner"), at, corner)?,
            edge_u,
            edge_v,
            folds,
            amplitude,
            taper,
            resolution,
        };
        Ok((ShapeDesc::Cloth(cloth), material))
    }
}

/// One file's context for the checks: its name and text (for messages and their lines) and its
/// folder; builds [`Error::Scene`] errors and checks the value kinds every table uses.
struct Checker<'a> {
    /// The file's name in messages.
    origin: &'a str,
    /// The file's text (spans are byte offsets into it).
    text: &'a str,
    /// The folder relative paths resolve against.
    base: &'a Path,
}

impl Checker<'_> {
    fn err(&self, key: &str, span_start: usize, message: impl Into<String>) -> Error {
        Error::Scene {
            path: self.origin.to_string(),
            key: key.to_string(),
            line: Some(line_of(self.text, span_start)),
            message: message.into(),
        }
    }

    fn vec(&self, key: &str, at: usize, v: [f64; 3]) -> Result<Vec3> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(Vec3::new(v[0], v[1], v[2]))
        } else {
            Err(self.err(key, at, format!("{v:?}: expected three finite numbers")))
        }
    }

    fn nonzero(&self, key: &str, at: usize, v: [f64; 3]) -> Result<Vec3> {
        let x = self.vec(key, at, v)?;
        if x.length() > 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, at, format!("{v:?}: expected a non-zero vector")))
        }
    }

    fn rgb(&self, key: &str, at: usize, v: [f64; 3], max: Option<f64>) -> Result<Rgb> {
        let ok = v
            .iter()
            .all(|c| c.is_finite() && *c >= 0.0 && max.is_none_or(|m| *c <= m));
        if ok {
            Ok(Rgb(v))
        } else {
            let range = match max {
                Some(m) => format!("each in [0, {m}]"),
                None => "each finite and >= 0".to_string(),
            };
            Err(self.err(key, at, format!("{v:?}: expected three numbers, {range}")))
        }
    }

    fn positive(&self, key: &str, at: usize, x: f64) -> Result<f64> {
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(key, at, format!("{x}: expected a finite number > 0")))
        }
    }

    /// `x` in `[-max, max]`.
    fn within(&self, key: &str, at: usize, x: f64, max: f64) -> Result<f64> {
        if x.is_finite() && x.abs() <= max {
            Ok(x)
        } else {
            Err(self.err(
                key,
                at,
                format!("{x}: expected a number in [-{max}, {max}]"),
            ))
        }
    }

    fn range(&self, key: &str, at: usize, x: i64, lo: i64, hi: i64) -> Result<usize> {
        if (lo..=hi).contains(&x) {
            Ok(x as usize)
        } else {
            Err(self.err(key, at, format!("{x}: expected an integer in [{lo}, {hi}]")))
        }
    }

    fn edges(&self, key: &str, at: usize, eu: [f64; 3], ev: [f64; 3]) -> Result<(Vec3, Vec3)> {
        let u = self.nonzero(&format!("{key}.edge_u"), at, eu)?;
        let v = self.nonzero(&format!("{key}.edge_v"), at, ev)?;
        if u.cross(v).length() <= 1e-12 * u.length() * v.length() {
            return Err(self.err(
                &format!("{key}.edge_v"),
                at,
                "parallel to edge_u: the edges must span a parallelogram",
            ));
        }
        Ok((u, v))
    }
}
