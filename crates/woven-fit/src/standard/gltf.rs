//! A woven surface as a glTF 2.0 swatch: a square of cloth (`STEM.gltf`, its geometry in
//! `STEM.bin`) whose one material carries the two yarn families' standard lobes
//! ([`StandardSurface`]) texel by texel, as the layout ([`LayoutImages`]) lays them out.
//!
//! glTF has one BSDF per point, not a mix of two, so each texel carries:
//!
//! | glTF | per texel | notes |
//! |---|---|---|
//! | `baseColorTexture` (sRGB) | `w ρ_weft f_weft + p ρ_warp f_warp`: the shares `w`, `p`, the Lambertian albedos `ρ`, the dye factors `f` | exact (Lambert mixes linearly); at most 1; black in a hole |
//! | `metallicRoughnessTexture` | G: the dominant family's `roughnessFactor` ([`StandardFamily::gltf`]); B: metallic 0 | |
//! | `KHR_materials_anisotropy` `anisotropyTexture` | RG: the rougher axis in tangent space, `(1, 0)` along `u`, `(0, 1)` along `v`; B: the strength | the dominant family's |
//! | `KHR_materials_specular` | A (`specularTexture`): the mixed GGX weight's largest channel, at most 1; RGB (`specularColorTexture`, sRGB, × `specularColorFactor`): each channel over it | exact at normal incidence; see below |
//! | `KHR_materials_sheen` | RGB (`sheenColorTexture`, sRGB): the shares' mix of the sheens; A (`sheenRoughnessTexture`): the dominant family's | 0 while the projection fits no sheen |
//! | `KHR_materials_ior` | 1.5 ([`PROJECTION_ETA`]) | |
//!
//! No `normalTexture`: each family's lobes are fitted to its whole float, tilted, its facets'
//! masking in them (the [`standard`](super) module docs), and a normal map of the float's tilt
//! would count it twice.
//!
//! The dominant family is the one with the larger share; where the yarns meet inside a texel
//! (and everywhere on a surface without a pattern, where the shares are `γ` and `1 − γ`) the
//! colours mix but the lobe's shape is that family's.
//!
//! **The specular weight.** glTF's dielectric Fresnel is Schlick's from `f0 = min(F0 ·
//! specularColor, 1) · specular` to `f90 = specular`. With `specular` = `s`, the largest channel
//! of the weight (at most 1), and `specularColor` = each channel over `s`, every channel matches
//! the projection's lobe at normal incidence; toward grazing every channel tends to `s`. A
//! weight above 1 cannot scale `f90` past 1: it scales `f0` alone (as OpenPBR's
//! `specular_weight` does), reflecting less than the projection's lobe toward grazing.
//! `specularColorFactor` is the largest colour over the tile (at least 1), the texture the colour
//! over it.
//!
//! **The swatch.** A square of side [`GltfOptions::swatch_m`] metres in the `xy` plane, facing
//! `+z`, its `u` along `+x` and `v` along `+y`, with normals and tangents (`(1, 0, 0, 1)`: the
//! anisotropy's `y`, the bitangent, is `+v`). Its texture coordinates put the weave at the
//! surface's own thread count on a uv in metres: `(u n_u / cells_u, −v n_v / cells_v)`, the
//! sampler repeating the tile (glTF's images start at their top row, `v` at its largest). To see
//! the weave from a viewer's distance, export with fewer `yarns_per_unit` (the weave enlarged).

use super::textures::{LayoutImages, FACTOR_RANGE};
use super::{StandardFamily, StandardSurface};
use crate::error::FitError;
use crate::projection::PROJECTION_ETA;
use serde_json::json;
use std::path::{Path, PathBuf};
use woven::color::srgb_encode;

/// The swatch's side where none is given, metres: 5 cm.
pub const DEFAULT_SWATCH_M: f64 = 0.05;

/// The largest swatch side taken, metres.
pub const MAX_SWATCH_M: f64 = 100.0;

/// The glTF extensions the material uses (`extensionsUsed`).
pub const EXTENSIONS: [&str; 4] = [
    "KHR_materials_anisotropy",
    "KHR_materials_ior",
    "KHR_materials_sheen",
    "KHR_materials_specular",
];

/// How the swatch is laid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GltfOptions {
    /// The square's side, metres (the uv unit), in `(0, MAX_SWATCH_M]`.
    pub swatch_m: f64,
}

impl Default for GltfOptions {
    fn default() -> Self {
        GltfOptions {
            swatch_m: DEFAULT_SWATCH_M,
        }
    }
}

impl GltfOptions {
    /// Checks the options.
    ///
    /// # Errors
    /// [`FitError::InvalidParameter`] naming `swatch_m` outside `(0, MAX_SWATCH_M]`.
    pub fn validate(&self) -> Result<(), FitError> {
        if self.swatch_m.is_finite() && self.swatch_m > 0.0 && self.swatch_m <= MAX_SWATCH_M {
            Ok(())
        } else {
            Err(FitError::invalid(
                "swatch_m",
                self.swatch_m,
                format!("metres in (0, {MAX_SWATCH_M}]"),
            ))
        }
    }
}

/// What one texel of the material carries, before its 8-bit encoding (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GltfTexel {
    /// The base colour, linear, each channel in `[0, 1]`.
    pub base_color: [f64; 3],
    /// `roughness`: `√α` across the rougher axis.
    pub roughness: f64,
    /// The rougher axis in tangent space (`x` along `u`, `y` along `v`), unit length.
    pub anisotropy_direction: [f64; 2],
    /// The anisotropy's strength, in `[0, 1]`.
    pub anisotropy_strength: f64,
    /// The sheen's colour, linear.
    pub sheen_color: [f64; 3],
    /// The sheen's roughness.
    pub sheen_roughness: f64,
    /// `specular`, in `[0, 1]`.
    pub specular: f64,
    /// `specularColor` (≥ 0; may pass 1).
    pub specular_color: [f64; 3],
}

impl GltfTexel {
    /// The texel of the shares `[weft, warp]` and dye factors `[weft, warp]`.
    pub fn new(surface: &StandardSurface, shares: [f64; 2], factors: [f64; 2]) -> GltfTexel {
        let [w, p] = shares;
        let mixed = |f: &dyn Fn(&StandardFamily) -> [f64; 3]| -> [f64; 3] {
            let (a, b) = (f(&surface.weft), f(&surface.warp));
            [0, 1, 2].map(|c| w * a[c] + p * b[c])
        };
        if w + p <= 0.0 {
            // A hole: nothing reflects.
            return GltfTexel {
                base_color: [0.0; 3],
                roughness: 1.0,
                anisotropy_direction: [1.0, 0.0],
                anisotropy_strength: 0.0,
                sheen_color: [0.0; 3],
                sheen_roughness: 1.0,
                specular: 0.0,
                specular_color: [1.0; 3],
            };
        }
        let warp = p > w;
        let family = if warp { &surface.warp } else { &surface.weft };
        let g = family.gltf();
        // The rougher axis runs along u where the weft's runs along its yarn, or the warp's
        // across its own.
        let along_u = warp != g.along_yarn;
        let spec = mixed(&|f| f.specular);
        let top = spec.iter().copied().fold(0.0, f64::max);
        // glTF's `specular` scales f0 and f90 alike, up to 1; what passes 1 goes to f0 alone.
        let s = top.min(1.0);
        GltfTexel {
            // A reflectance: a dye factor above 1 may not lift a channel past 1.
            base_color: [0, 1, 2].map(|c| {
                (w * surface.weft.diffuse[c] * factors[0]
                    + p * surface.warp.diffuse[c] * factors[1])
                    .clamp(0.0, 1.0)
            }),
            roughness: g.roughness,
            anisotropy_direction: if along_u { [1.0, 0.0] } else { [0.0, 1.0] },
            anisotropy_strength: g.anisotropy_strength,
            // glTF's sheen colour is a weight in [0, 1].
            sheen_color: mixed(&|f| f.sheen).map(|c| c.clamp(0.0, 1.0)),
            sheen_roughness: family.lobes.sheen_roughness,
            specular: s,
            specular_color: if s > 0.0 {
                spec.map(|c| c / s)
            } else {
                [1.0; 3]
            },
        }
    }

    /// The GGX roughnesses glTF renders here, `[along u, along v]`: `α_b = roughness²` across
    /// the anisotropy's direction, `α_t = α_b + (1 − α_b) strength²` along it.
    pub fn alpha(&self) -> [f64; 2] {
        let b = self.roughness * self.roughness;
        let t = b + (1.0 - b) * self.anisotropy_strength * self.anisotropy_strength;
        if self.anisotropy_direction[0].abs() >= self.anisotropy_direction[1].abs() {
            [t, b]
        } else {
            [b, t]
        }
    }
}

/// The material's textures over one tile, 8 bits a channel, row-major from the top row.
#[derive(Clone, Debug, PartialEq)]
pub struct GltfTextures {
    /// The tile's size in texels, `[width, height]`.
    pub size: [usize; 2],
    /// The base colour, sRGB.
    pub base_color: Vec<[u8; 3]>,
    /// G roughness, B metallic (0); R unused (255).
    pub metallic_roughness: Vec<[u8; 3]>,
    /// RG the anisotropy's direction, `(d + 1) / 2`; B its strength.
    pub anisotropy: Vec<[u8; 3]>,
    /// RGB the sheen's colour (sRGB), A its roughness.
    pub sheen: Vec<[u8; 4]>,
    /// RGB `specularColor` over [`specular_color_factor`](Self::specular_color_factor)
    /// (sRGB), A `specular`.
    pub specular: Vec<[u8; 4]>,
    /// `specularColorFactor` (grey): the largest `specularColor` over the tile, at least 1.
    pub specular_color_factor: f64,
}

/// A value in `[0, 1]` as 8 bits.
fn unit8(x: f64) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// A 16-bit texture value in `[0, 1]`.
fn from16(x: u16) -> f64 {
    f64::from(x) / 65535.0
}

impl GltfTextures {
    /// The textures of `surface` laid out by `images` (module docs).
    pub fn bake(surface: &StandardSurface, images: &LayoutImages) -> GltfTextures {
        let texels: Vec<GltfTexel> = images
            .layout
            .iter()
            .zip(&images.factors)
            .map(|(l, f)| {
                let shares = [from16(l[0]), from16(l[1])];
                let factors = [from16(f[0]), from16(f[1])].map(|x| x * FACTOR_RANGE);
                GltfTexel::new(surface, shares, factors)
            })
            .collect();
        let factor = texels
            .iter()
            .flat_map(|t| t.specular_color)
            .fold(1.0, f64::max);
        // sRGB's curve is defined on [0, 1], as an 8-bit texture holds.
        let srgb = |c: [f64; 3]| c.map(|x| unit8(srgb_encode(x.clamp(0.0, 1.0))));
        GltfTextures {
            size: images.size(),
            base_color: texels.iter().map(|t| srgb(t.base_color)).collect(),
            metallic_roughness: texels
                .iter()
                .map(|t| [255, unit8(t.roughness), 0])
                .collect(),
            anisotropy: texels
                .iter()
                .map(|t| {
                    let [x, y] = t.anisotropy_direction.map(|d| unit8(0.5 * (d + 1.0)));
                    [x, y, unit8(t.anisotropy_strength)]
                })
                .collect(),
            sheen: texels
                .iter()
                .map(|t| {
                    let [r, g, b] = srgb(t.sheen_color);
                    [r, g, b, unit8(t.sheen_roughness)]
                })
                .collect(),
            specular: texels
                .iter()
                .map(|t| {
                    let [r, g, b] = srgb(t.specular_color.map(|c| c / factor));
                    [r, g, b, unit8(t.specular)]
                })
                .collect(),
            specular_color_factor: factor,
        }
    }
}

/// The files [`write()`] writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GltfFiles {
    /// The glTF document.
    pub gltf: PathBuf,
    /// Its binary buffer (the swatch's geometry).
    pub bin: PathBuf,
    /// Its textures: base colour, metallic-roughness, anisotropy, sheen, specular.
    pub textures: Vec<PathBuf>,
}

/// The textures' file names after the stem, in [`GltfFiles::textures`]' order.
const TEXTURE_NAMES: [&str; 5] = [
    "gltf-basecolor",
    "gltf-metalrough",
    "gltf-anisotropy",
    "gltf-sheen",
    "gltf-specular",
];

/// Writes the swatch of `surface` laid out by `images` as `path` (`STEM.gltf`), its geometry
/// `STEM.bin` and its five textures `STEM-gltf-*.png` beside it, each file whole or not at all;
/// the document names them relative to itself (module docs).
///
/// # Errors
/// [`FitError::InvalidParameter`] naming `transmission` for a surface that lets light through
/// ([`check_spec`](super::check_spec)), `swatch_m` out of range or `path` without a file
/// name; [`FitError::Material`] holding the I/O error that names a file that cannot be written.
pub fn write(
    surface: &StandardSurface,
    images: &LayoutImages,
    path: &Path,
    options: &GltfOptions,
) -> Result<GltfFiles, FitError> {
    super::refuse_transmission(surface.translucent.is_some())?;
    options.validate()?;
    let (folder, stem) = super::openpbr::folder_and_stem(path)?;
    let textures = GltfTextures::bake(surface, images);
    let names: Vec<String> = TEXTURE_NAMES
        .iter()
        .map(|n| format!("{stem}-{n}.png"))
        .collect();
    let paths: Vec<PathBuf> = names.iter().map(|n| folder.join(n)).collect();
    let size = textures.size;
    write_png8(&paths[0], size, &flat(&textures.base_color), 3)?;
    write_png8(&paths[1], size, &flat(&textures.metallic_roughness), 3)?;
    write_png8(&paths[2], size, &flat(&textures.anisotropy), 3)?;
    write_png8(&paths[3], size, &flat(&textures.sheen), 4)?;
    write_png8(&paths[4], size, &flat(&textures.specular), 4)?;
    let bin_name = format!("{stem}.bin");
    let bin_path = folder.join(&bin_name);
    let geometry = swatch(surface, images, options);
    woven::fsutil::atomic_write(&bin_path, |out| out.write_all(&geometry.bytes))?;
    let doc = document(surface, &textures, &geometry, &bin_name, &names, &stem);
    let text = serde_json::to_string_pretty(&doc).unwrap_or_default();
    woven::fsutil::atomic_write(path, |out| out.write_all(text.as_bytes()))?;
    Ok(GltfFiles {
        gltf: path.to_path_buf(),
        bin: bin_path,
        textures: paths,
    })
}

/// Pixels as bytes.
fn flat<const N: usize>(pixels: &[[u8; N]]) -> Vec<u8> {
    pixels.iter().flatten().copied().collect()
}

/// The swatch's geometry: the buffer's bytes and where each attribute lies.
struct Swatch {
    bytes: Vec<u8>,
    /// `(byte offset, byte length)` of positions, normals, tangents, texture coordinates and
    /// indices.
    views: [(usize, usize); 5],
    /// The texture coordinates' bounds, `[min, max]`.
    uv_bounds: [[f64; 2]; 2],
    half: f64,
}

/// The square (module docs): four vertices and two triangles, little-endian as glTF reads.
fn swatch(surface: &StandardSurface, images: &LayoutImages, options: &GltfOptions) -> Swatch {
    let half = 0.5 * options.swatch_m;
    let corners = [[-half, -half], [half, -half], [half, half], [-half, half]];
    let k = [0, 1].map(|a| surface.yarns_per_unit[a] / images.cells[a] as f64);
    // Woven's uv is in metres from the swatch's corner; glTF's t runs down the image.
    let uv: Vec<[f64; 2]> = corners
        .iter()
        // + 0.0: the corner at v = 0 is t = 0, not −0 (as JSON would write it).
        .map(|[x, y]| [(x + half) * k[0], -(y + half) * k[1] + 0.0])
        .collect();
    let mut bytes = Vec::new();
    let mut views = [(0, 0); 5];
    let mut floats = |values: &mut dyn Iterator<Item = f64>, view: &mut (usize, usize)| {
        let start = bytes.len();
        for v in values {
            bytes.extend_from_slice(&(v as f32).to_le_bytes());
        }
        *view = (start, bytes.len() - start);
    };
    floats(
        &mut corners.iter().flat_map(|&[x, y]| [x, y, 0.0]),
        &mut views[0],
    );
    floats(
        &mut corners.iter().flat_map(|_| [0.0, 0.0, 1.0]),
        &mut views[1],
    );
    floats(
        &mut corners.iter().flat_map(|_| [1.0, 0.0, 0.0, 1.0]),
        &mut views[2],
    );
    floats(&mut uv.iter().flatten().copied(), &mut views[3]);
    let start = bytes.len();
    for i in [0u16, 1, 2, 0, 2, 3] {
        bytes.extend_from_slice(&i.to_le_bytes());
    }
    views[4] = (start, bytes.len() - start);
    // A buffer's length is a multiple of 4 (glTF aligns the next view's start).
    while bytes.len() % 4 != 0 {
        bytes.push(0);
    }
    let bound = |f: fn(f64, f64) -> f64, a: usize| uv.iter().map(|p| p[a]).reduce(f).unwrap_or(0.0);
    Swatch {
        bytes,
        views,
        uv_bounds: [
            [bound(f64::min, 0), bound(f64::min, 1)],
            [bound(f64::max, 0), bound(f64::max, 1)],
        ],
        half,
    }
}

/// The glTF document.
fn document(
    surface: &StandardSurface,
    textures: &GltfTextures,
    geometry: &Swatch,
    bin: &str,
    images: &[String],
    stem: &str,
) -> serde_json::Value {
    let h = geometry.half as f32 as f64;
    let view = |k: usize, target: u32| {
        let (offset, length) = geometry.views[k];
        json!({"buffer": 0, "byteOffset": offset, "byteLength": length, "target": target})
    };
    let (array, elements) = (34962, 34963);
    let c = textures.specular_color_factor;
    let texture = |k: usize| json!({ "index": k });
    json!({
        "asset": {
            "version": "2.0",
            "generator": format!("woven {}", env!("CARGO_PKG_VERSION")),
            "extras": {
                "woven": format!(
                    "a woven surface on glTF's lobes; mixture RMS log error weft {:.3}, warp {:.3} \
                     (one isotropic GGX + Lambert {:.3}, {:.3})",
                    surface.weft.rms_log, surface.warp.rms_log,
                    surface.weft.isotropic_rms_log, surface.warp.isotropic_rms_log
                ),
                "yarns_per_unit": surface.yarns_per_unit,
            }
        },
        "extensionsUsed": EXTENSIONS,
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "name": stem, "mesh": 0 }],
        "meshes": [{
            "name": stem,
            "primitives": [{
                "attributes": { "POSITION": 0, "NORMAL": 1, "TANGENT": 2, "TEXCOORD_0": 3 },
                "indices": 4,
                "material": 0
            }]
        }],
        "buffers": [{ "uri": uri(bin), "byteLength": geometry.bytes.len() }],
        "bufferViews": [
            view(0, array), view(1, array), view(2, array), view(3, array), view(4, elements)
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-h, -h, 0.0], "max": [h, h, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC4"},
            {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2",
             "min": geometry.uv_bounds[0].map(|x| x as f32 as f64),
             "max": geometry.uv_bounds[1].map(|x| x as f32 as f64)},
            {"bufferView": 4, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ],
        "samplers": [{ "magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497 }],
        "images": images.iter().map(|n| json!({ "uri": uri(n) })).collect::<Vec<_>>(),
        "textures": (0..images.len()).map(|k| json!({ "sampler": 0, "source": k })).collect::<Vec<_>>(),
        "materials": [{
            "name": stem,
            "doubleSided": true,
            "pbrMetallicRoughness": {
                "baseColorTexture": texture(0),
                "metallicFactor": 0.0,
                "roughnessFactor": 1.0,
                "metallicRoughnessTexture": texture(1)
            },
            "extensions": {
                "KHR_materials_anisotropy": {
                    "anisotropyStrength": 1.0,
                    "anisotropyRotation": 0.0,
                    "anisotropyTexture": texture(2)
                },
                "KHR_materials_ior": { "ior": PROJECTION_ETA },
                "KHR_materials_sheen": {
                    "sheenColorFactor": [1.0, 1.0, 1.0],
                    "sheenColorTexture": texture(3),
                    "sheenRoughnessFactor": 1.0,
                    "sheenRoughnessTexture": texture(3)
                },
                "KHR_materials_specular": {
                    "specularFactor": 1.0,
                    "specularTexture": texture(4),
                    "specularColorFactor": [c, c, c],
                    "specularColorTexture": texture(4)
                }
            }
        }]
    })
}

/// A file name as a relative URI: unreserved characters kept, every other byte
/// percent-encoded (RFC 3986).
fn uri(name: &str) -> String {
    let mut out = String::new();
    for b in name.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
            out.push(char::from(b));
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// An 8-bit PNG of `channels` (3: RGB, 4: RGBA) written atomically.
fn write_png8(
    path: &Path,
    [w, h]: [usize; 2],
    bytes: &[u8],
    channels: usize,
) -> Result<(), FitError> {
    let colour = if channels == 4 {
        image::ColorType::Rgba8
    } else {
        image::ColorType::Rgb8
    };
    super::textures::write_png(path, [w, h], bytes, colour)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_become_relative_uris() {
        assert_eq!(uri("silk shot.bin"), "silk%20shot.bin");
        assert_eq!(uri("a-b_c.d~e.png"), "a-b_c.d~e.png");
        assert_eq!(uri("é.png"), "%C3%A9.png");
    }

    #[test]
    fn a_swatch_side_out_of_range_is_refused_by_name() {
        for bad in [0.0, -1.0, f64::NAN, 1e9] {
            let e = GltfOptions { swatch_m: bad }.validate().unwrap_err();
            assert!(e.to_string().contains("swatch_m"), "{e}");
        }
        assert!(GltfOptions::default().validate().is_ok());
    }
}
