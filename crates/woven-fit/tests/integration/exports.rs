//! A woven surface written for other renderers (`woven_fit::standard::{openpbr, gltf}`): the
//! documents parse, name the textures written beside them, declare what they use, carry each
//! family's fitted roughnesses through the renderer's own mapping and leave holes black. The
//! families here are given by hand (the projection itself is `projection.rs`'s and the CLI
//! test's): the layout is a real one, a gapped satin with tilted floats on a tiny table.

use std::collections::{HashMap, HashSet};
use std::path::Path;
use std::sync::Arc;
use woven::color::{srgb_encode, Rgb};
use woven::material::{Material, Weave};
use woven::surface::{SurfaceSpec, WovenSurface};
use woven::table::{Table, TableOptions};
use woven_fit::projection::StandardLobes;
use woven_fit::standard::gltf::{self, GltfOptions, GltfTexel, GltfTextures, EXTENSIONS};
use woven_fit::standard::openpbr::{self, OpenPbrSpecular};
use woven_fit::standard::textures::{LayoutImages, FACTOR_RANGE};
use woven_fit::standard::{StandardFamily, StandardSurface};

/// A satin-5 of gapped, tilted yarns (holes where both leave a gap) on a table small enough to
/// build in a moment.
fn gapped_satin() -> WovenSurface {
    let mut material = Material::preset("polyester-sateen").unwrap();
    material.weave = Some(Weave::named("satin-5").unwrap());
    let spec = SurfaceSpec {
        yarns_per_unit: [2000.0, 1000.0],
        u_max: 20f64.to_radians(),
        gap: 0.15,
        weft_color: Some(Rgb([0.8, 0.2, 0.1])),
        warp_color: Some(Rgb([0.1, 0.3, 0.7])),
        ..SurfaceSpec::new(material)
    };
    let yarn = spec.material.yarn_family();
    let options = TableOptions {
        n_theta: 3,
        n_phi: 2,
        n_h: 5,
        colour: true,
        ..TableOptions::default()
    };
    let table = Table::build(&yarn.build(550.0).unwrap(), &yarn, &options, &|_, _| {}).unwrap();
    WovenSurface::new(&spec, Arc::new(table)).unwrap()
}

fn family(alpha: [f64; 2], diffuse: [f64; 3], specular: [f64; 3], sheen: f64) -> StandardFamily {
    StandardFamily {
        lobes: StandardLobes {
            diffuse: Rgb(diffuse).luminance(),
            specular: Rgb(specular).luminance(),
            alpha,
            sheen,
            sheen_roughness: 0.4,
        },
        diffuse,
        specular,
        sheen: [sheen; 3],
        rms_log: 0.12,
        isotropic_rms_log: 0.35,
    }
}

/// Both families rougher across their yarns (as a cylinder's highlight is), so that the weft's
/// tangent is v's and the warp's u's; the weft's GGX weight above 1.
fn standard() -> StandardSurface {
    StandardSurface {
        weft: family([0.05, 0.4], [0.6, 0.15, 0.05], [1.4, 1.2, 1.0], 0.01),
        warp: family([0.1, 0.3], [0.05, 0.2, 0.5], [0.5, 0.6, 0.7], 0.004),
        yarns_per_unit: [2000.0, 1000.0],
        translucent: None,
    }
}

/// Each texel's `[weft, warp]` shares.
fn shares(images: &LayoutImages) -> Vec<[f64; 2]> {
    let unit = |x: u16| f64::from(x) / 65535.0;
    images
        .layout
        .iter()
        .map(|l| [unit(l[0]), unit(l[1])])
        .collect()
}

/// OpenPBR Surface 1.1's inputs (MaterialX 1.39's `ND_open_pbr_surface_surfaceshader`).
#[rustfmt::skip]
const OPENPBR_INPUTS: &[&str] = &[
    "base_weight", "base_color", "base_diffuse_roughness", "base_metalness",
    "specular_weight", "specular_color", "specular_roughness", "specular_ior",
    "specular_roughness_anisotropy", "transmission_weight", "transmission_color",
    "transmission_depth", "transmission_scatter", "transmission_scatter_anisotropy",
    "transmission_dispersion_scale", "transmission_dispersion_abbe_number", "subsurface_weight",
    "subsurface_color", "subsurface_radius", "subsurface_radius_scale",
    "subsurface_scatter_anisotropy", "fuzz_weight", "fuzz_color", "fuzz_roughness",
    "coat_weight", "coat_color", "coat_roughness", "coat_roughness_anisotropy", "coat_ior",
    "coat_darkening", "thin_film_weight", "thin_film_thickness", "thin_film_ior",
    "emission_luminance", "emission_color", "geometry_opacity", "geometry_thin_walled",
    "geometry_normal", "geometry_coat_normal", "geometry_tangent", "geometry_coat_tangent",
];

/// A node of the document: its element, and its inputs by name as `(type, value or
/// nodename, whether a nodename)`.
struct Node {
    kind: String,
    inputs: HashMap<String, (String, String, bool)>,
}

fn nodes(text: &str) -> HashMap<String, Node> {
    let doc = roxmltree::Document::parse(text).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "materialx");
    assert_eq!(root.attribute("version"), Some("1.39"));
    let mut out = HashMap::new();
    for e in root.children().filter(|n| n.is_element()) {
        let mut inputs = HashMap::new();
        for i in e.children().filter(|n| n.is_element()) {
            assert_eq!(i.tag_name().name(), "input");
            let ty = i.attribute("type").unwrap().to_string();
            let (value, link) = match (i.attribute("value"), i.attribute("nodename")) {
                (Some(v), None) => (v.to_string(), false),
                (None, Some(n)) => (n.to_string(), true),
                other => panic!("an input has a value or a nodename: {other:?}"),
            };
            let name = i.attribute("name").unwrap().to_string();
            assert!(inputs.insert(name, (ty, value, link)).is_none());
        }
        let name = e
            .attribute("name")
            .expect("every node is named")
            .to_string();
        let node = Node {
            kind: e.tag_name().name().to_string(),
            inputs,
        };
        assert!(out.insert(name.clone(), node).is_none(), "{name} twice");
    }
    out
}

fn number(node: &Node, input: &str) -> f64 {
    node.inputs[input].1.parse().unwrap()
}

#[test]
fn the_openpbr_document_parses_links_only_its_nodes_and_names_textures_beside_it() {
    let surface = gapped_satin();
    let images = LayoutImages::bake(&surface, 4).unwrap();
    let standard = standard();
    let dir = tempfile::tempdir().unwrap();
    let files = openpbr::write(&standard, &images, &dir.path().join("satin & co.mtlx")).unwrap();
    let text = std::fs::read_to_string(&files.document).unwrap();
    let nodes = nodes(&text);

    // Every link names a node of the document; every file is a texture written beside it.
    let mut files_named = HashSet::new();
    for node in nodes.values() {
        for (name, (ty, value, link)) in &node.inputs {
            if *link {
                assert!(nodes.contains_key(value), "{name} → {value}");
            }
            if ty == "filename" {
                assert!(dir.path().join(value).is_file(), "{value}");
                files_named.insert(value.clone());
            }
        }
    }
    // The layout and the factors (no normal map: the lobes hold the float's tilt).
    assert_eq!(files_named.len(), 2, "{files_named:?}");
    assert!(files_named.contains("satin & co-layout.png"));
    assert!(files_named.contains("satin & co-factors.png"));
    assert!(text.contains("satin &amp; co-layout.png"));

    // The two families and the hole, each an OpenPBR surface of OpenPBR's own inputs.
    let surfaces: Vec<&String> = nodes
        .iter()
        .filter(|(_, n)| n.kind == "open_pbr_surface")
        .map(|(k, _)| k)
        .collect();
    assert_eq!(surfaces.len(), 3);
    for name in surfaces {
        let n = &nodes[name];
        for input in n.inputs.keys() {
            assert!(OPENPBR_INPUTS.contains(&input.as_str()), "{name}.{input}");
        }
        assert_eq!(n.inputs["geometry_thin_walled"].1, "true");
        assert!(!n.inputs.contains_key("geometry_normal"), "{name}");
    }
    let hole = &nodes["hole_surface"];
    assert_eq!(number(hole, "base_weight"), 0.0);
    assert_eq!(number(hole, "specular_weight"), 0.0);
    // The material is the families' mix, then the mix toward the hole by the yarns' cover.
    let top = &nodes["woven_surface"];
    assert_eq!(top.inputs["bg"].1, "hole_surface");
    assert_eq!(nodes[&top.inputs["fg"].1].inputs["fg"].1, "weft_surface");
    let material: Vec<&Node> = nodes
        .values()
        .filter(|n| n.kind == "surfacematerial")
        .collect();
    assert_eq!(material.len(), 1);
    assert_eq!(material[0].inputs["surfaceshader"].1, "woven_surface");

    // One tile spans `cells` cells at the surface's thread count on a uv in metres.
    let scale: Vec<f64> = nodes["tile_uv"].inputs["in2"]
        .1
        .split(',')
        .map(|x| x.trim().parse().unwrap())
        .collect();
    assert_eq!(images.cells, [5, 5]);
    assert_eq!(scale, [400.0, 200.0]);

    // Each family's roughnesses through OpenPBR's own mapping, its tangent the rougher axis.
    for (name, f, tangent) in [
        ("weft_surface", &standard.weft, "v_tangent"),
        ("warp_surface", &standard.warp, "u_tangent"),
    ] {
        let n = &nodes[name];
        let written = OpenPbrSpecular {
            roughness: number(n, "specular_roughness"),
            anisotropy: number(n, "specular_roughness_anisotropy"),
            along_yarn: f.lobes.alpha[0] >= f.lobes.alpha[1],
        };
        let back = written.alpha();
        for k in 0..2 {
            let (got, want) = (back[k], f.lobes.alpha[k]);
            assert!(
                (got / want - 1.0).abs() < 1e-4,
                "{name}: α {got} against {want}"
            );
        }
        assert_eq!(n.inputs["geometry_tangent"].1, tangent, "{name}");
        assert_eq!(number(n, "specular_ior"), 1.5);
        let max = f.specular.iter().copied().fold(0.0, f64::max);
        assert!((number(n, "specular_weight") - max).abs() < 1e-6);
        assert!((number(n, "fuzz_weight") - f.sheen[0]).abs() < 1e-6);
    }
    assert_eq!(nodes["u_tangent"].kind, "tangent");
    assert_eq!(nodes["v_tangent"].kind, "bitangent");
}

#[test]
fn the_gltf_swatch_parses_declares_its_extensions_and_references_its_files() {
    let surface = gapped_satin();
    let images = LayoutImages::bake(&surface, 4).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("satin swatch.gltf");
    let options = GltfOptions { swatch_m: 0.02 };
    let files = gltf::write(&standard(), &images, &path, &options).unwrap();
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&files.gltf).unwrap()).unwrap();
    assert_eq!(doc["asset"]["version"], "2.0");

    // extensionsUsed lists exactly the material's extensions.
    let used: HashSet<&str> = doc["extensionsUsed"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    let material = &doc["materials"][0];
    let on_material: HashSet<&str> = material["extensions"]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    assert_eq!(used, on_material);
    assert_eq!(used, EXTENSIONS.into_iter().collect());
    assert_eq!(material["extensions"]["KHR_materials_ior"]["ior"], 1.5);
    assert_eq!(material["pbrMetallicRoughness"]["metallicFactor"], 0.0);

    // The buffer and every image are files beside the document, of the declared sizes.
    let uri = |v: &serde_json::Value| v.as_str().unwrap().replace("%20", " ");
    let bin = std::fs::read(dir.path().join(uri(&doc["buffers"][0]["uri"]))).unwrap();
    assert_eq!(doc["buffers"][0]["byteLength"], bin.len());
    let images_json = doc["images"].as_array().unwrap();
    assert_eq!(images_json.len(), 5);
    assert!(material.get("normalTexture").is_none());
    for image in images_json {
        let file = dir.path().join(uri(&image["uri"]));
        let png = image::open(&file).unwrap();
        assert_eq!(
            [png.width() as usize, png.height() as usize],
            images.size(),
            "{}",
            file.display()
        );
    }
    for texture in doc["textures"].as_array().unwrap() {
        assert!(texture["source"].as_u64().unwrap() < 5);
    }

    // The swatch: 2 cm across; its texture coordinates repeat the tile at the thread count.
    let floats = |view: usize| -> Vec<f32> {
        let v = &doc["bufferViews"][view];
        let (at, len) = (
            v["byteOffset"].as_u64().unwrap() as usize,
            v["byteLength"].as_u64().unwrap() as usize,
        );
        bin[at..at + len]
            .chunks(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    };
    let positions = floats(0);
    let uv = floats(3);
    let width = positions[3] - positions[0];
    assert!((width - 0.02).abs() < 1e-7, "{width}");
    // 2 cm at 2000 cells per metre is 40 cells: 8 tiles of 5.
    assert!((uv[2] - uv[0] - 8.0).abs() < 1e-5, "{uv:?}");
    // Tangents along +x with w = +1: the anisotropy's y, the bitangent, is +v (+y).
    assert_eq!(floats(2)[..4], [1.0, 0.0, 0.0, 1.0]);
    assert_eq!(floats(1)[..3], [0.0, 0.0, 1.0]);
}

#[test]
fn gltf_texels_carry_the_dominant_familys_roughnesses_and_holes_are_black() {
    let surface = gapped_satin();
    let images = LayoutImages::bake(&surface, 8).unwrap();
    let standard = standard();
    let textures = GltfTextures::bake(&standard, &images);
    let factor = |i: usize, k: usize| f64::from(images.factors[i][k]) / 65535.0 * FACTOR_RANGE;
    let (mut holes, mut weft, mut warp) = (0, 0, 0);
    for (i, [w, p]) in shares(&images).into_iter().enumerate() {
        let texel = GltfTexel::new(&standard, [w, p], [factor(i, 0), factor(i, 1)]);
        if w + p == 0.0 {
            holes += 1;
            assert_eq!(textures.base_color[i], [0, 0, 0], "texel {i}");
            assert_eq!(textures.specular[i][3], 0, "texel {i}");
            assert_eq!(textures.sheen[i][..3], [0, 0, 0], "texel {i}");
            continue;
        }
        // The family on top, its yarn along u (weft) or v (warp).
        let (f, along_u_is_along_yarn) = if p > w {
            warp += 1;
            (&standard.warp, false)
        } else {
            weft += 1;
            (&standard.weft, true)
        };
        let [along, across] = f.lobes.alpha;
        let want = if along_u_is_along_yarn {
            [along, across]
        } else {
            [across, along]
        };
        // Exactly, before 8 bits...
        let got = texel.alpha();
        for k in 0..2 {
            assert!((got[k] / want[k] - 1.0).abs() < 1e-12, "{got:?} {want:?}");
        }
        // ... and as a viewer decodes the textures, within their quantisation.
        let g = GltfTexel {
            roughness: f64::from(textures.metallic_roughness[i][1]) / 255.0,
            anisotropy_direction: [0, 1]
                .map(|k| f64::from(textures.anisotropy[i][k]) / 127.5 - 1.0),
            anisotropy_strength: f64::from(textures.anisotropy[i][2]) / 255.0,
            ..texel
        };
        let decoded = g.alpha();
        for k in 0..2 {
            assert!(
                (decoded[k] - want[k]).abs() < 0.02 * want[k] + 2e-3,
                "decoded α {decoded:?} against {want:?}"
            );
        }
        // The base colour is the shares' mix of the dyed Lambertian albedos.
        let r = w * f_diffuse(&standard.weft, factor(i, 0))
            + p * f_diffuse(&standard.warp, factor(i, 1));
        let stored = f64::from(textures.base_color[i][0]) / 255.0;
        assert!((stored - srgb_encode(r.min(1.0))).abs() <= 0.5 / 255.0 + 1e-12);
    }
    eprintln!("{weft} weft, {warp} warp texels and {holes} holes");
    assert!(holes > 0 && weft > 0 && warp > 0);
    // The weft's GGX weight above 1 is carried by specularColorFactor.
    assert!((textures.specular_color_factor - 1.4).abs() < 1e-12);
}

/// A family's red Lambertian albedo dyed by `factor`.
fn f_diffuse(f: &StandardFamily, factor: f64) -> f64 {
    f.diffuse[0] * factor
}

#[test]
fn bad_parameters_are_refused_by_name() {
    let surface = gapped_satin();
    for bad in [0, 65] {
        let e = LayoutImages::bake(&surface, bad).unwrap_err().to_string();
        assert!(
            e.contains("texels_per_cell") && e.contains("[1, 64]"),
            "{e}"
        );
    }
    let images = LayoutImages::bake(&surface, 2).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let e = gltf::write(
        &standard(),
        &images,
        &dir.path().join("s.gltf"),
        &GltfOptions { swatch_m: -0.1 },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("swatch_m") && e.contains("-0.1"), "{e}");
    let e = openpbr::write(&standard(), &images, Path::new("/"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("path"), "{e}");
    // A folder that does not exist: the error names the file, and nothing is written.
    let missing = dir.path().join("no/such/folder/s.mtlx");
    let e = openpbr::write(&standard(), &images, &missing)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no/such/folder"), "{e}");
    // A surface that lets light through: its transmission is Blender's alone, and the writers
    // say so before they write anything.
    let sheer = StandardSurface {
        translucent: Some([0.4, 0.3, 0.2]),
        ..standard()
    };
    let e = openpbr::write(&sheer, &images, &dir.path().join("s.mtlx"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("transmission"), "{e}");
    let e = gltf::write(
        &sheer,
        &images,
        &dir.path().join("s.gltf"),
        &GltfOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("transmission"), "{e}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
