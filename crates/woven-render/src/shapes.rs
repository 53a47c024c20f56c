//! Shapes that become triangle meshes: OBJ files and the procedural cloth.

use crate::geometry::Mesh;
use crate::{Error, Result};
use std::f64::consts::PI;
use std::path::Path;
use woven::Vec3;

/// The triangle budget: the most triangles a scene may hold, all its meshes together (20
/// million). A triangle takes some 300 bytes once the scene is built (its primitive, its share
/// of the mesh's vertices, the hierarchy), so the budget is about 6 GB; over it a scene is
/// refused before the meshes are generated or the hierarchy is built.
pub const MAX_TRIANGLES: usize = 20_000_000;

/// The triangles of a grid mesh of `[na, nb]` cells, as [`Cloth::mesh`] and [`Drape::mesh`]
/// make them: two a cell.
pub fn grid_triangles([na, nb]: [usize; 2]) -> usize {
    2 * na * nb
}

/// Refuses `count` triangles over [`MAX_TRIANGLES`]; `what` says whose they are.
///
/// # Errors
/// [`Error::OverBudget`] naming the triangle budget and by how much `count` exceeds it.
pub fn check_triangle_budget(count: usize, what: &str) -> Result<()> {
    if count <= MAX_TRIANGLES {
        return Ok(());
    }
    Err(Error::OverBudget {
        budget: "triangles".into(),
        message: format!(
            "{what} makes {count} triangles, {:.2}× the budget of {MAX_TRIANGLES} a scene may \
             hold",
            count as f64 / MAX_TRIANGLES as f64
        ),
    })
}

/// The largest OBJ file [`load_obj`] reads, in bytes (4 GiB): room for a mesh of
/// [`MAX_TRIANGLES`] with uv and normals (about 115 bytes a triangle as exporters write them).
pub const MAX_OBJ_BYTES: u64 = 4 << 30;

/// The longest line of an OBJ file, in bytes (64 KiB): a face of some two thousand corners.
/// A longer line is not a mesh (an endless one would otherwise fill memory).
pub const MAX_OBJ_LINE_BYTES: usize = 64 << 10;

/// How a scene names a built-in mesh: `file = "builtin:NAME"`.
pub const BUILTIN_PREFIX: &str = "builtin:";

/// The meshes built into the renderer, by name: the showcase's draped cloths, cushions and
/// furniture (`scenes/meshes/`, written offline by `scripts/drape/drape.py`: a small cloth
/// simulation). Each cloth's uv is in metres along its weft (`u`) and warp (`v`), so
/// `yarns_per_unit` is yarns per metre, and each has a back face and an edge 0.8–1.5 mm thick.
pub const BUILTIN_MESHES: [(&str, &str); 6] = [
    (
        "tablecloth",
        include_str!("../scenes/meshes/tablecloth.obj"),
    ),
    ("table", include_str!("../scenes/meshes/table.obj")),
    (
        "satin-drape",
        include_str!("../scenes/meshes/satin-drape.obj"),
    ),
    ("stool", include_str!("../scenes/meshes/stool.obj")),
    (
        "cushion-shot-silk",
        include_str!("../scenes/meshes/cushion-shot-silk.obj"),
    ),
    (
        "cushion-twill",
        include_str!("../scenes/meshes/cushion-twill.obj"),
    ),
];

/// The entry of [`BUILTIN_MESHES`] named `name`: its name and OBJ text.
pub fn builtin_obj(name: &str) -> Option<(&'static str, &'static str)> {
    BUILTIN_MESHES.iter().copied().find(|(n, _)| *n == name)
}

/// The built-in mesh `name` ([`BUILTIN_MESHES`]), scaled by `scale` then moved by `translate`.
///
/// # Errors
/// [`Error::Scene`] naming `key` for a name not in [`BUILTIN_MESHES`].
pub fn builtin_mesh(name: &str, scale: f64, translate: Vec3, key: &str) -> Result<Mesh> {
    let origin = format!("{BUILTIN_PREFIX}{name}");
    match builtin_obj(name) {
        Some((_, text)) => read_obj(text.as_bytes(), &origin, scale, translate, key),
        None => Err(Error::Scene {
            path: origin,
            key: key.to_string(),
            line: None,
            message: "no such built-in mesh".into(),
        }),
    }
}

/// Reads a triangle mesh from a Wavefront OBJ file (all its objects, triangulated), with its
/// uv (`vt`) and normals (`vn`) where the file has them, scaled by `scale` then moved by
/// `translate`. The file must be a regular file of at most [`MAX_OBJ_BYTES`] (checked before it
/// is read), with lines of at most [`MAX_OBJ_LINE_BYTES`]; material libraries (`mtllib`) are
/// not read (the scene gives each shape its material).
///
/// # Errors
/// [`Error::Scene`] naming `key` and the file when it cannot be opened, is not a regular file,
/// is too large, has a line too long, cannot be parsed or holds no valid mesh.
pub fn load_obj(path: &Path, scale: f64, translate: Vec3, key: &str) -> Result<Mesh> {
    // Every failure names the key, a missing file included.
    let (file, _) =
        woven::fsutil::open_regular(path, MAX_OBJ_BYTES, "an OBJ mesh").map_err(|e| {
            Error::Scene {
                path: path.display().to_string(),
                key: key.to_string(),
                line: None,
                message: match e {
                    woven::Error::Parse { message, .. } => message,
                    woven::Error::Io { source, .. } => {
                        format!("cannot read the OBJ mesh: {source}")
                    }
                    e => e.to_string(),
                },
            }
        })?;
    read_obj(file, &path.display().to_string(), scale, translate, key)
}

/// [`load_obj`] from a reader (`origin` names it in messages): lines of at most
/// [`MAX_OBJ_LINE_BYTES`], at most [`MAX_OBJ_BYTES`] in all.
///
/// # Errors
/// [`Error::Scene`] naming `key` and `origin` when the text breaks a limit, cannot be parsed or
/// holds no valid mesh.
pub fn read_obj(
    reader: impl std::io::Read,
    origin: &str,
    scale: f64,
    translate: Vec3,
    key: &str,
) -> Result<Mesh> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..tobj::LoadOptions::default()
    };
    let bad = |what: String| Error::Scene {
        path: origin.to_string(),
        key: key.to_string(),
        line: None,
        message: what,
    };
    let mut text = woven::fsutil::BoundedText::new(reader, MAX_OBJ_LINE_BYTES, MAX_OBJ_BYTES);
    // Materials are the scene's: a `mtllib` line loads nothing (and opens no file).
    let no_materials = |_: &Path| Ok((Vec::new(), Default::default()));
    let (models, _) = match tobj::load_obj_buf(&mut text, &options, no_materials) {
        Ok(loaded) => loaded,
        Err(e) => {
            return Err(bad(match text.limit_hit() {
                Some(limit) => format!("{limit}: not an OBJ mesh"),
                None => format!("cannot read the OBJ mesh: {e}"),
            }))
        }
    };
    mesh_of(&models, scale, translate, &|what| bad(what.to_string()))
}

/// The models tobj read as one checked mesh (`bad` makes the error).
fn mesh_of(
    models: &[tobj::Model],
    scale: f64,
    translate: Vec3,
    bad: &dyn Fn(&str) -> Error,
) -> Result<Mesh> {
    let mut mesh = Mesh::default();
    let mut with_normals = true;
    let mut with_uv = true;
    for m in models {
        with_normals &= !m.mesh.normals.is_empty();
        with_uv &= !m.mesh.texcoords.is_empty();
    }
    for m in models {
        let base = mesh.positions.len() as u32;
        let mm = &m.mesh;
        for p in mm.positions.chunks_exact(3) {
            let p = Vec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
            mesh.positions.push(p * scale + translate);
        }
        if with_normals {
            for n in mm.normals.chunks_exact(3) {
                let n = Vec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
                let l = n.length();
                mesh.normals
                    .push(if l > 0.0 { n * (1.0 / l) } else { Vec3::Z });
            }
        }
        if with_uv {
            for t in mm.texcoords.chunks_exact(2) {
                mesh.uvs.push([t[0] as f64, t[1] as f64]);
            }
        }
        for t in mm.indices.chunks_exact(3) {
            mesh.indices.push([base + t[0], base + t[1], base + t[2]]);
        }
    }
    let n = mesh.positions.len();
    if mesh.indices.is_empty() {
        return Err(bad("the OBJ file holds no triangles"));
    }
    check_triangle_budget(mesh.indices.len(), "the OBJ file")?;
    if mesh.normals.len() != n && !mesh.normals.is_empty()
        || mesh.uvs.len() != n && !mesh.uvs.is_empty()
    {
        return Err(bad("normals or uv do not match the vertices"));
    }
    if mesh.indices.iter().flatten().any(|&i| i as usize >= n)
        || mesh
            .positions
            .iter()
            .any(|p| !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()))
    {
        return Err(bad(
            "a face refers to a missing vertex, or a vertex is not finite",
        ));
    }
    Ok(mesh)
}

/// A procedural cloth: a sheet hanging in folds.
///
/// The flat sheet is `corner + a·edge_u + b·edge_v`, `a, b ∈ [0, 1]`; it folds in `folds`
/// sinusoidal waves across `edge_u` (the folds run along `edge_v`), displaced along the sheet's
/// normal `edge_u × edge_v` by `amplitude·(1 − taper·b)·sin(2π·folds·a)` metres, so a positive
/// `taper` makes the folds shallower toward `corner + edge_v`. The uv follows the folded surface:
/// `u` is the arc length across the folds divided by the flat width `|edge_u|` (it runs past 1
/// where the sheet folds), `v = b` — so a weave keeps its scale along the folds instead of
/// stretching.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cloth {
    /// A corner of the flat sheet.
    pub corner: Vec3,
    /// The flat sheet's first edge (across the folds; the weft direction `u`).
    pub edge_u: Vec3,
    /// The second edge (along the folds; `v`).
    pub edge_v: Vec3,
    /// Waves across the sheet, ≥ 0.
    pub folds: f64,
    /// Fold depth, metres.
    pub amplitude: f64,
    /// How much shallower the folds get toward `corner + edge_v`, in `[0, 1]`.
    pub taper: f64,
    /// Grid resolution `[across, along]`, each ≥ 1.
    pub resolution: [usize; 2],
}

impl Cloth {
    /// The point of the folded sheet at flat coordinates `(a, b)` and its partial derivatives.
    fn point(&self, a: f64, b: f64) -> (Vec3, Vec3, Vec3) {
        let n = self.edge_u.cross(self.edge_v).normalize();
        let k = 2.0 * PI * self.folds;
        let amp = self.amplitude * (1.0 - self.taper * b);
        let p = self.corner + self.edge_u * a + self.edge_v * b + n * (amp * (k * a).sin());
        let dpda = self.edge_u + n * (amp * k * (k * a).cos());
        let dpdb = self.edge_v + n * (-self.amplitude * self.taper * (k * a).sin());
        (p, dpda, dpdb)
    }

    /// Triangulates the sheet with smooth normals and arc-length uv.
    pub fn mesh(&self) -> Mesh {
        let [na, nb] = self.resolution;
        let width = self.edge_u.length();
        let mut mesh = Mesh::default();
        for j in 0..=nb {
            let b = j as f64 / nb as f64;
            // Arc length across this row, by the trapezoid rule on a finer grid.
            let mut arc = 0.0;
            let sub = 8;
            let mut prev_speed = self.point(0.0, b).1.length();
            for i in 0..=na {
                let a = i as f64 / na as f64;
                if i > 0 {
                    for s in 1..=sub {
                        let t = (i as f64 - 1.0 + s as f64 / sub as f64) / na as f64;
                        let speed = self.point(t, b).1.length();
                        arc += 0.5 * (prev_speed + speed) / (na * sub) as f64;
                        prev_speed = speed;
                    }
                }
                let (p, dpda, dpdb) = self.point(a, b);
                mesh.positions.push(p);
                mesh.normals.push(dpda.cross(dpdb).normalize());
                mesh.uvs.push([arc / width, b]);
            }
        }
        let row = (na + 1) as u32;
        for j in 0..nb as u32 {
            for i in 0..na as u32 {
                let v00 = j * row + i;
                let (v10, v01, v11) = (v00 + 1, v00 + row, v00 + row + 1);
                mesh.indices.push([v00, v10, v11]);
                mesh.indices.push([v00, v11, v01]);
            }
        }
        mesh
    }
}

/// A procedural cloth draped over a sphere: a flat sheet laid on the sphere's top and hanging
/// down around it, like a cloth thrown over a ball.
///
/// The flat sheet is `corner + a·edge_u + b·edge_v`, `a, b ∈ [0, 1]`; its middle touches the
/// sphere (`center`, `radius`) at the point where the sheet's normal `edge_u × edge_v` points
/// from the centre. A sheet point at flat distance `r` from the middle, in flat direction `d̂`,
/// goes to the sphere point `r` along the great circle from the top toward `d̂` (polar angle
/// `θ = r/radius`), up to the equator; beyond it the sheet hangs straight down (along `−n̂`) the
/// rest of its length, waving in `folds` sinusoidal folds around the sphere of depth
/// `amplitude` that grow in over the first `radius` of the hanging part. The uv is the flat
/// sheet's `(a, b)`: lengths along every line from the middle are kept (the cloth does not
/// stretch along them; around, it shears, as woven cloth does over a ball), so the weave
/// follows the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drape {
    /// A corner of the flat sheet.
    pub corner: Vec3,
    /// The flat sheet's first edge (the weft direction `u`).
    pub edge_u: Vec3,
    /// The second edge (`v`).
    pub edge_v: Vec3,
    /// The sphere's centre.
    pub center: Vec3,
    /// The sphere's radius, > 0 (a sphere shape under the cloth should be a little smaller).
    pub radius: f64,
    /// Folds around the hanging part, ≥ 0.
    pub folds: f64,
    /// Fold depth, metres.
    pub amplitude: f64,
    /// Grid resolution `[along edge_u, along edge_v]`, each ≥ 1.
    pub resolution: [usize; 2],
}

impl Drape {
    /// The draped point of flat sheet coordinates `(a, b)`.
    pub fn point(&self, a: f64, b: f64) -> Vec3 {
        let n = self.edge_u.cross(self.edge_v).normalize();
        let e1 = self.edge_u.normalize();
        let e2 = n.cross(e1);
        let d = self.edge_u * (a - 0.5) + self.edge_v * (b - 0.5);
        let r = d.length();
        let dir = if r > 0.0 { d * (1.0 / r) } else { e1 };
        let big_r = self.radius;
        let theta = r / big_r;
        let half = PI / 2.0;
        if theta <= half {
            let (st, ct) = theta.sin_cos();
            return self.center + (dir * st + n * ct) * big_r;
        }
        // Hanging below the equator, waving around.
        let hang = r - half * big_r;
        let phi = dir.dot(e2).atan2(dir.dot(e1));
        let grow = {
            let x = (hang / big_r).min(1.0);
            x * x * (3.0 - 2.0 * x)
        };
        let wave = self.amplitude * grow * (self.folds * phi).sin();
        self.center + dir * (big_r + wave) - n * hang
    }

    /// Triangulates the sheet, with normals from the surface's derivatives and uv = `(a, b)`.
    pub fn mesh(&self) -> Mesh {
        let [na, nb] = self.resolution;
        let mut mesh = Mesh::default();
        let h = 1e-5;
        for j in 0..=nb {
            let b = j as f64 / nb as f64;
            for i in 0..=na {
                let a = i as f64 / na as f64;
                let p = self.point(a, b);
                let pa = self.point(a + h, b) - self.point(a - h, b);
                let pb = self.point(a, b + h) - self.point(a, b - h);
                let nrm = pa.cross(pb);
                let l = nrm.length();
                mesh.positions.push(p);
                mesh.normals.push(if l > 0.0 && l.is_finite() {
                    nrm * (1.0 / l)
                } else {
                    self.edge_u.cross(self.edge_v).normalize()
                });
                mesh.uvs.push([a, b]);
            }
        }
        let row = (na + 1) as u32;
        for j in 0..nb as u32 {
            for i in 0..na as u32 {
                let v00 = j * row + i;
                let (v10, v01, v11) = (v00 + 1, v00 + row, v00 + row + 1);
                mesh.indices.push([v00, v10, v11]);
                mesh.indices.push([v00, v11, v01]);
            }
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Unfolded, the cloth is its flat rectangle with uv = (a, b); folded, `u` grows with the
    /// arc length and the normals face the sheet's side.
    #[test]
    fn cloth_uv_follows_the_surface() {
        let mut c = Cloth {
            corner: Vec3::new(0.0, 0.0, 0.0),
            edge_u: Vec3::new(2.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 1.0, 0.0),
            folds: 3.0,
            amplitude: 0.0,
            taper: 0.0,
            resolution: [60, 4],
        };
        let m = c.mesh();
        let last = m.uvs[60];
        assert!((last[0] - 1.0).abs() < 1e-9 && last[1] == 0.0);
        c.amplitude = 0.2;
        let m = c.mesh();
        let u_end = m.uvs[60][0];
        // Arc length of x ↦ 0.2 sin(3πx) over [0, 2], divided by 2: by fine quadrature.
        let n = 100_000;
        let exact: f64 = (0..n)
            .map(|i| {
                let x = (i as f64 + 0.5) * 2.0 / n as f64;
                let slope = 0.2 * 3.0 * PI * (3.0 * PI * x).cos();
                (1.0 + slope * slope).sqrt() * 2.0 / n as f64
            })
            .sum::<f64>()
            / 2.0;
        assert!((u_end - exact).abs() < 2e-3 * exact, "{u_end} vs {exact}");
        assert!(m.normals.iter().all(|n| n.z > 0.0));
        assert_eq!(m.indices.len(), 2 * 60 * 4);
    }

    /// Draped over a sphere, the sheet lies on it down to the equator with lengths along lines
    /// from its middle kept, hangs straight below, and its normals face outward.
    #[test]
    fn drape_lies_on_the_sphere_and_keeps_radial_lengths() {
        let d = Drape {
            corner: Vec3::new(-1.5, -1.5, 0.0),
            edge_u: Vec3::new(3.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 3.0, 0.0),
            center: Vec3::new(0.2, 0.1, 0.5),
            radius: 0.6,
            folds: 0.0,
            amplitude: 0.0,
            resolution: [60, 60],
        };
        let c = d.center;
        // The middle is the sphere's top; a point 0.5 m from it along the flat sheet is 0.5 m
        // along the great circle.
        let top = d.point(0.5, 0.5);
        assert!((top - (c + Vec3::Z * 0.6)).length() < 1e-12);
        let p = d.point(0.5 + 0.5 / 3.0, 0.5);
        assert!(((p - c).length() - 0.6).abs() < 1e-12);
        let angle = ((p - c).normalize().dot(Vec3::Z)).acos();
        assert!((angle * 0.6 - 0.5).abs() < 1e-12);
        // Beyond π r / 2 it hangs: x stays at the equator, z drops by the rest of the length.
        let q = d.point(0.5 + 1.2 / 3.0, 0.5);
        assert!((q.x - (c.x + 0.6)).abs() < 1e-12);
        assert!((q.z - (c.z - (1.2 - 0.3 * PI))).abs() < 1e-12);
        // Arc length along a diagonal line from the middle = its flat length.
        let n = 4000;
        let end = 0.45;
        let mut arc = 0.0;
        let mut prev = d.point(0.5, 0.5);
        for k in 1..=n {
            let t = 0.5 + end * k as f64 / n as f64;
            let p = d.point(t, t);
            arc += (p - prev).length();
            prev = p;
        }
        let flat = end * (2.0f64).sqrt() * 3.0;
        assert!((arc - flat).abs() < 1e-4 * flat, "{arc} vs {flat}");
        let m = d.mesh();
        for (p, nrm) in m.positions.iter().zip(&m.normals) {
            let out = *p - c;
            let radial = Vec3::new(out.x, out.y, out.z.max(0.0));
            assert!(nrm.dot(radial) > 0.0, "normal {nrm:?} at {p:?}");
        }
        // Folds wave the hanging part only.
        let folded = Drape {
            folds: 8.0,
            amplitude: 0.05,
            ..d
        };
        assert_eq!(folded.point(0.6, 0.55), d.point(0.6, 0.55));
        assert!((folded.point(0.02, 0.4) - d.point(0.02, 0.4)).length() > 0.04);
    }
}
