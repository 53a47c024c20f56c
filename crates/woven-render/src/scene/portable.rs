//! A checked scene as plain data for another renderer: what `python -m woven.mitsuba` turns
//! into a Mitsuba 3 scene. Every shape that may carry a texture becomes triangles with the uv
//! `woven render` gives it (built-in and OBJ meshes, procedural cloths, rectangles); a woven
//! material becomes its material's self-contained TOML and the keys that read back as its
//! surface ([`SurfaceSpec::to_keys`](woven::surface::SurfaceSpec::to_keys)); the Preetham sun
//! and sky become the environment map `woven render` bakes ([`sky_image`]). What another
//! renderer cannot take is refused here, naming the scene's key.

use super::{CameraSpec, LightDesc, MaterialDesc, MeshSource, SceneDescription, ShapeDesc};
use crate::color::Rgb;
use crate::geometry::Mesh;
use crate::rng::SamplerKind;
use crate::shapes;
use crate::sky::{sky_image, SKY_MAP_HEIGHT, SKY_MAP_WIDTH};
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::path::PathBuf;
use woven::keys::{KeyValue, Keys};
use woven::Vec3;

/// A scene as plain data ([`SceneDescription::portable`]).
#[derive(Clone, Debug)]
pub struct Portable {
    /// The camera (`fov_deg` spans the film's width).
    pub camera: CameraSpec,
    /// The inset's camera and its rectangles on the film, if any.
    pub inset: Option<PortableInset>,
    /// Film width and height, pixels.
    pub size: [usize; 2],
    /// Samples per pixel.
    pub spp: usize,
    /// The film's seed.
    pub seed: u64,
    /// `"independent"` or `"sobol"`.
    pub sampler: &'static str,
    /// Mitsuba's `max_depth` (`None`: no limit).
    pub max_depth: Option<u32>,
    /// Mitsuba's `rr_depth`.
    pub rr_depth: u32,
    /// Whether emitters seen directly render black.
    pub hide_emitters: bool,
    /// Shapes, in file order.
    pub shapes: Vec<PortableShape>,
    /// Materials by name.
    pub materials: BTreeMap<String, PortableMaterial>,
    /// Lights, in file order, each with its `sampling_weight`.
    pub lights: Vec<(PortableLight, f64)>,
}

/// The inset: its camera, and where its image goes on the film.
#[derive(Clone, Debug)]
pub struct PortableInset {
    /// Its camera (`fov_deg` spans the inset's width).
    pub camera: CameraSpec,
    /// The inset's own image: top-left pixel and size.
    pub inner: ([usize; 2], [usize; 2]),
    /// With its white border: top-left pixel and size.
    pub outer: ([usize; 2], [usize; 2]),
}

/// A shape and the name of its material.
#[derive(Clone, Debug)]
pub struct PortableShape {
    /// The scene's key of the shape (`shape[3]`).
    pub key: String,
    /// Its material's name (a key of [`Portable::materials`]).
    pub material: String,
    /// Its geometry.
    pub geometry: PortableGeometry,
}

/// A shape's geometry.
#[derive(Clone, Debug)]
pub enum PortableGeometry {
    /// A sphere (its material reads no uv).
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f64,
    },
    /// Triangles with `woven render`'s uv.
    Triangles(Mesh),
}

/// A material.
#[derive(Clone, Debug)]
pub enum PortableMaterial {
    /// Lambertian.
    Diffuse {
        /// Reflectance per channel.
        reflectance: Rgb,
    },
    /// A woven surface: its material (self-contained TOML: a WIF pattern written as its
    /// matrix) and the keys that read back as the surface on it.
    Woven {
        /// The material file's text.
        material: String,
        /// The other keys, `footprint_filter` the integrator's.
        keys: Keys,
    },
    /// A microcylinder fabric: its file's text.
    Microcylinder {
        /// The fabric file's text.
        fabric: String,
    },
    /// Mitsuba's `roughplastic`, its own keys.
    RoughPlastic {
        /// `diffuse_reflectance`.
        diffuse_reflectance: Rgb,
        /// `specular_reflectance`.
        specular_reflectance: Rgb,
        /// `distribution`: `"beckmann"` or `"ggx"`.
        distribution: &'static str,
        /// `alpha`.
        alpha: f64,
        /// `int_ior`.
        int_ior: f64,
        /// `ext_ior`.
        ext_ior: f64,
        /// `nonlinear`.
        nonlinear: bool,
    },
}

/// A light.
#[derive(Clone, Debug)]
pub enum PortableLight {
    /// A point light: position, intensity (W/sr).
    Point {
        /// Position.
        position: Vec3,
        /// Intensity, W/sr.
        intensity: Rgb,
    },
    /// A uniform environment, its scale applied.
    Constant {
        /// Radiance.
        radiance: Rgb,
    },
    /// An environment map in `woven render`'s layout: row 0 at the zenith (+z), column `x` at
    /// azimuth `φ = 2π (x + ½) / width` from +x toward +y.
    Map {
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
        /// Row-major pixels, the scale applied.
        pixels: Vec<Rgb>,
    },
    /// An environment map file (EXR) in that layout, and its scale.
    MapFile {
        /// The file.
        path: PathBuf,
        /// Multiplier.
        scale: f64,
    },
    /// A rectangle emitting on the side of `edge_u × edge_v`.
    Rectangle {
        /// A corner.
        corner: Vec3,
        /// First edge.
        edge_u: Vec3,
        /// Second edge.
        edge_v: Vec3,
        /// Radiance.
        radiance: Rgb,
    },
}

impl SceneDescription {
    /// The scene as plain data for another renderer ([`Portable`]).
    ///
    /// # Errors
    /// [`Error::Scene`] naming the key another renderer cannot take: a `sheen` material (no
    /// Charlie sheen there), a cylinder (its uv is `woven render`'s own), a sphere with a woven
    /// material (likewise); a mesh that cannot be read; the sky's map.
    pub fn portable(&self) -> Result<Portable> {
        let cannot = |key: String, why: &str| Error::Scene {
            path: self.origin.clone(),
            key,
            line: None,
            message: format!("another renderer cannot take this: {why}"),
        };
        let mut materials = BTreeMap::new();
        for (name, desc) in &self.materials {
            let key = format!("material.{name}.type");
            let m = match desc {
                MaterialDesc::Diffuse { reflectance } => PortableMaterial::Diffuse {
                    reflectance: *reflectance,
                },
                MaterialDesc::Woven(spec) => PortableMaterial::Woven {
                    material: spec.material.to_self_contained_toml_string(),
                    keys: spec.to_keys().with(
                        "footprint_filter",
                        KeyValue::Bool(self.integrator.footprint_filter),
                    ),
                },
                MaterialDesc::Microcylinder(fabric) => PortableMaterial::Microcylinder {
                    fabric: fabric.to_toml_string(),
                },
                MaterialDesc::RoughPlastic(plastic) => {
                    let p = plastic.params();
                    PortableMaterial::RoughPlastic {
                        diffuse_reflectance: p.diffuse_reflectance,
                        specular_reflectance: p.specular_reflectance,
                        distribution: match p.distribution {
                            woven::baseline::Distribution::Beckmann => "beckmann",
                            woven::baseline::Distribution::Ggx => "ggx",
                        },
                        alpha: p.alpha,
                        int_ior: p.int_ior,
                        ext_ior: p.ext_ior,
                        nonlinear: p.nonlinear,
                    }
                }
                MaterialDesc::Sheen(_) => {
                    return Err(cannot(
                        key,
                        "Mitsuba 3 has no Charlie sheen (`type = \"sheen\"`)",
                    ))
                }
            };
            materials.insert(name.clone(), m);
        }
        let mut shapes = Vec::with_capacity(self.shapes.len());
        for (k, (shape, material)) in self.shapes.iter().enumerate() {
            let key = format!("shape[{k}]");
            let reads_uv = matches!(self.materials.get(material), Some(MaterialDesc::Woven(_)));
            let geometry = match shape {
                ShapeDesc::Sphere { .. } | ShapeDesc::Cylinder { .. } if reads_uv => {
                    return Err(cannot(
                        format!("{key}.type"),
                        "a woven material on a sphere or cylinder (their uv is woven render's \
                         own): give it a mesh",
                    ))
                }
                ShapeDesc::Cylinder { .. } => {
                    return Err(cannot(format!("{key}.type"), "a cylinder: give it a mesh"))
                }
                ShapeDesc::Sphere { center, radius } => PortableGeometry::Sphere {
                    center: *center,
                    radius: *radius,
                },
                ShapeDesc::Rectangle {
                    corner,
                    edge_u,
                    edge_v,
                } => PortableGeometry::Triangles(rectangle(*corner, *edge_u, *edge_v)),
                ShapeDesc::Mesh {
                    source,
                    scale,
                    translate,
                } => {
                    let key = format!("{key}.file");
                    PortableGeometry::Triangles(match source {
                        MeshSource::File(path) => shapes::load_obj(path, *scale, *translate, &key)?,
                        MeshSource::Builtin(name) => {
                            shapes::builtin_mesh(name, *scale, *translate, &key)?
                        }
                    })
                }
                ShapeDesc::Cloth(cloth) => PortableGeometry::Triangles(cloth.mesh()),
                ShapeDesc::Drape(drape) => PortableGeometry::Triangles(drape.mesh()),
            };
            shapes.push(PortableShape {
                key,
                material: material.clone(),
                geometry,
            });
        }
        let mut lights = Vec::with_capacity(self.lights.len());
        for (light, weight) in self.lights.iter().zip(&self.light_weights) {
            lights.push((light_of(light)?, *weight));
        }
        let film = [self.film.width, self.film.height];
        Ok(Portable {
            camera: self.camera.clone(),
            inset: self.inset.as_ref().map(|i| {
                let r = i.pixels(film);
                PortableInset {
                    camera: i.camera.clone(),
                    inner: r.inner,
                    outer: r.outer,
                }
            }),
            size: film,
            spp: self.film.spp,
            seed: self.film.seed,
            sampler: match self.film.sampler {
                SamplerKind::Independent => "independent",
                _ => "sobol",
            },
            max_depth: self.integrator.max_depth,
            rr_depth: self.integrator.rr_depth,
            hide_emitters: self.integrator.hide_emitters,
            shapes,
            materials,
            lights,
        })
    }
}

/// A light as plain data; the sky baked as `woven render` bakes it.
fn light_of(light: &LightDesc) -> Result<PortableLight> {
    Ok(match light {
        LightDesc::Point {
            position,
            intensity,
        } => PortableLight::Point {
            position: *position,
            intensity: *intensity,
        },
        LightDesc::EnvironmentConstant { radiance, scale } => PortableLight::Constant {
            radiance: *radiance * *scale,
        },
        LightDesc::EnvironmentMap { path, scale } => PortableLight::MapFile {
            path: path.clone(),
            scale: *scale,
        },
        LightDesc::Sky { params } => {
            let image = sky_image(params, SKY_MAP_WIDTH, SKY_MAP_HEIGHT)?;
            PortableLight::Map {
                width: image.width,
                height: image.height,
                pixels: image.pixels,
            }
        }
        LightDesc::Rectangle {
            corner,
            edge_u,
            edge_v,
            radiance,
        } => PortableLight::Rectangle {
            corner: *corner,
            edge_u: *edge_u,
            edge_v: *edge_v,
            radiance: *radiance,
        },
    })
}

/// A rectangle as two triangles, uv `(a, b)` its fractions along the edges (as `woven
/// render` shades it), counter-clockwise seen from the side of `edge_u × edge_v`.
fn rectangle(corner: Vec3, edge_u: Vec3, edge_v: Vec3) -> Mesh {
    Mesh {
        positions: vec![
            corner,
            corner + edge_u,
            corner + edge_u + edge_v,
            corner + edge_v,
        ],
        normals: Vec::new(),
        uvs: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        indices: vec![[0, 1, 2], [0, 2, 3]],
    }
}
