//! Building a checked [`SceneDescription`] into a renderable [`Scene`]: materials (woven ones
//! tabulated), lights, geometry and its BVH.

use super::{
    Inset, LightDesc, MaterialDesc, MeshSource, PrimInfo, Scene, SceneDescription, ShapeDesc,
};
use crate::accel::Accel;
use crate::camera::Camera;
use crate::geometry::{Mesh, Primitive};
use crate::light::{Emitter, Environment, Light, PointLight, RectangleLight};
use crate::material::{Diffuse, SurfaceMaterial, Uniform};
use crate::shapes;
use crate::sky::{sky_image, SKY_MAP_HEIGHT, SKY_MAP_WIDTH};
use crate::woven_material::{TableCache, TableGrid, WovenMaterial};
use crate::Result;
use std::collections::BTreeMap;
use woven::math::sampling::Distribution1D;
use woven::progress::Progress;

impl Scene {
    /// Builds the scene: tabulates woven materials (`grid`), loads meshes and environment maps,
    /// builds the BVH. `on_table` is called with a woven material's name before a table is
    /// built for it (materials sharing a yarn share its table); `progress` receives the table
    /// build's `(done, total)`.
    ///
    /// # Errors
    /// Files that cannot be read; materials the model library refuses.
    pub fn build(
        desc: &SceneDescription,
        grid: &TableGrid,
        on_table: &dyn Fn(&str),
        progress: &dyn Progress,
    ) -> Result<Scene> {
        Scene::build_with(desc, grid, TableCache::default(), on_table, progress)
    }

    /// [`build`](Self::build) with the tables of `cache` (e.g. [`TableCache::with_disk`], so that
    /// tables built on an earlier run are loaded, not built).
    ///
    /// # Errors
    /// As [`build`](Self::build).
    pub fn build_with(
        desc: &SceneDescription,
        grid: &TableGrid,
        mut cache: TableCache,
        on_table: &dyn Fn(&str),
        progress: &dyn Progress,
    ) -> Result<Scene> {
        let view = |c: &super::CameraSpec, [w, h]: [usize; 2]| {
            Camera::new(c.origin, c.target, c.up, c.fov_deg, w, h)
        };
        let camera = view(&desc.camera, [desc.film.width, desc.film.height]);
        let inset = desc.inset.as_ref().map(|i| {
            let at = i.pixels([desc.film.width, desc.film.height]);
            Inset {
                camera: view(&i.camera, at.inner.1),
                at,
            }
        });
        let (materials, index_of) = build_materials(desc, grid, &mut cache, on_table, progress)?;
        let mut geometry = Geometry::default();
        let lights = build_lights(desc, &mut geometry)?;
        build_shapes(desc, &index_of, &mut geometry)?;
        let mut integrator = desc.integrator.clone();
        // Footprints only where a material reads them.
        integrator.footprint_filter &= materials.iter().any(|m| m.uses_footprint());
        Ok(Scene {
            film: desc.film.clone(),
            integrator,
            camera,
            inset,
            environment: lights
                .iter()
                .position(|l| matches!(l, Light::Environment(_))),
            emitters_can_be_hit: lights.iter().any(|l| !l.is_delta()),
            lights,
            light_choice: Distribution1D::new(&desc.light_weights),
            accel: Accel::new(geometry.prims, geometry.meshes),
            prim_info: geometry.prim_info,
            transmits: materials.iter().any(|m| m.transmits()),
            materials,
        })
    }
}

/// The primitives gathered so far, what each is made of, and the meshes triangles refer to.
#[derive(Default)]
struct Geometry {
    prims: Vec<Primitive>,
    prim_info: Vec<PrimInfo>,
    meshes: Vec<Mesh>,
    /// The triangles of `meshes`, all together.
    triangles: usize,
}

impl Geometry {
    /// Adds a primitive; returns its index.
    fn push(&mut self, prim: Primitive, info: PrimInfo) -> usize {
        self.prims.push(prim);
        self.prim_info.push(info);
        self.prims.len() - 1
    }

    /// Counts `count` more triangles, those of `key`, refused when they take the scene over
    /// its triangle budget (called before a procedural mesh is generated).
    fn budget(&mut self, count: usize, key: &str) -> Result<()> {
        self.triangles += count;
        shapes::check_triangle_budget(self.triangles, &format!("the scene up to `{key}`"))
    }

    /// Adds a mesh's triangles (counted by [`budget`](Self::budget)).
    fn add_mesh(&mut self, mesh: Mesh, info: PrimInfo) {
        let m = self.meshes.len();
        for t in 0..mesh.indices.len() {
            self.push(Primitive::Triangle { mesh: m, index: t }, info);
        }
        self.meshes.push(mesh);
    }
}

/// The materials some shape uses, in name order, and each one's index by name.
type Materials = (Vec<Box<dyn SurfaceMaterial>>, BTreeMap<String, usize>);

/// Builds the materials some shape uses (woven ones tabulated, or taken from `cache`).
fn build_materials(
    desc: &SceneDescription,
    grid: &TableGrid,
    cache: &mut TableCache,
    on_table: &dyn Fn(&str),
    progress: &dyn Progress,
) -> Result<Materials> {
    let mut index_of = BTreeMap::new();
    let mut materials: Vec<Box<dyn SurfaceMaterial>> = Vec::new();
    for (name, m) in &desc.materials {
        if !desc.shapes.iter().any(|(_, n)| n == name) {
            continue;
        }
        let built: Box<dyn SurfaceMaterial> = match m {
            MaterialDesc::Diffuse { reflectance } => Box::new(Diffuse {
                reflectance: *reflectance,
            }),
            MaterialDesc::Microcylinder(m) => Box::new(Uniform((**m).clone())),
            MaterialDesc::RoughPlastic(m) => Box::new(Uniform((**m).clone())),
            MaterialDesc::Sheen(m) => Box::new(Uniform((**m).clone())),
            MaterialDesc::Woven(spec) => Box::new(WovenMaterial::build(
                spec,
                grid,
                cache,
                &|| on_table(name),
                progress,
            )?),
        };
        index_of.insert(name.clone(), materials.len());
        materials.push(built);
    }
    Ok((materials, index_of))
}

/// Builds the lights in file order; a rectangle light adds its (non-reflecting) surface to
/// `geometry`.
fn build_lights(desc: &SceneDescription, geometry: &mut Geometry) -> Result<Vec<Light>> {
    let mut lights = Vec::with_capacity(desc.lights.len());
    for l in &desc.lights {
        lights.push(match l {
            LightDesc::Point {
                position,
                intensity,
            } => Light::Point(PointLight {
                position: *position,
                intensity: *intensity,
            }),
            LightDesc::EnvironmentConstant { radiance, scale } => {
                Light::Environment(Environment::constant(*radiance, *scale))
            }
            LightDesc::EnvironmentMap { path, scale } => {
                Light::Environment(Environment::from_exr(path, *scale)?)
            }
            LightDesc::Sky { params } => Light::Environment(
                sky_image(params, SKY_MAP_WIDTH, SKY_MAP_HEIGHT)?.into_environment(),
            ),
            LightDesc::Rectangle {
                corner,
                edge_u,
                edge_v,
                radiance,
            } => {
                let prim = geometry.push(
                    Primitive::Rectangle {
                        corner: *corner,
                        edge_u: *edge_u,
                        edge_v: *edge_v,
                    },
                    PrimInfo {
                        material: None,
                        light: Some(lights.len()),
                    },
                );
                Light::Rectangle(RectangleLight::new(
                    *corner, *edge_u, *edge_v, *radiance, prim,
                ))
            }
        });
    }
    Ok(lights)
}

/// How the scene file names shape `k`.
fn shape_key(k: usize) -> String {
    format!("shape[{k}]")
}

/// Adds the shapes to `geometry` (meshes loaded, cloths generated), each with its material's
/// index from `index_of`.
fn build_shapes(
    desc: &SceneDescription,
    index_of: &BTreeMap<String, usize>,
    geometry: &mut Geometry,
) -> Result<()> {
    for (k, (shape, name)) in desc.shapes.iter().enumerate() {
        let info = PrimInfo {
            material: Some(index_of[name]),
            light: None,
        };
        match shape {
            ShapeDesc::Sphere { center, radius } => {
                geometry.push(
                    Primitive::Sphere {
                        center: *center,
                        radius: *radius,
                    },
                    info,
                );
            }
            ShapeDesc::Rectangle {
                corner,
                edge_u,
                edge_v,
            } => {
                geometry.push(
                    Primitive::Rectangle {
                        corner: *corner,
                        edge_u: *edge_u,
                        edge_v: *edge_v,
                    },
                    info,
                );
            }
            ShapeDesc::Cylinder { base, axis, radius } => {
                geometry.push(
                    Primitive::Cylinder {
                        base: *base,
                        axis: *axis,
                        radius: *radius,
                    },
                    info,
                );
            }
            ShapeDesc::Mesh {
                source,
                scale,
                translate,
            } => {
                let key = format!("shape[{k}].file");
                let mesh = match source {
                    MeshSource::File(path) => shapes::load_obj(path, *scale, *translate, &key)?,
                    MeshSource::Builtin(name) => {
                        shapes::builtin_mesh(name, *scale, *translate, &key)?
                    }
                };
                geometry.budget(mesh.indices.len(), &key)?;
                geometry.add_mesh(mesh, info)
            }
            ShapeDesc::Cloth(cloth) => {
                geometry.budget(shapes::grid_triangles(cloth.resolution), &shape_key(k))?;
                geometry.add_mesh(cloth.mesh(), info)
            }
            ShapeDesc::Drape(drape) => {
                geometry.budget(shapes::grid_triangles(drape.resolution), &shape_key(k))?;
                geometry.add_mesh(drape.mesh(), info)
            }
        }
    }
    Ok(())
}
