//! `woven export --format openpbr|gltf`: a woven surface on the standard lobes
//! (`woven_fit::standard`), written as a MaterialX document of OpenPBR Surface or as a glTF
//! swatch. This module reads the flags into the library's surface keys, runs the library and
//! prints what it wrote.

use super::{ExportArgs, ExportFormat};
use crate::io;
use crate::numbers::seconds;
use crate::progress::Progress;
use crate::tables;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;
use woven::catalog::AnyMaterial;
use woven::keys::{KeyValue, Keys};
use woven::surface::SurfaceSpec;
use woven_fit::standard::gltf::{self, GltfOptions};
use woven_fit::standard::openpbr;
use woven_fit::standard::textures::LayoutImages;
use woven_fit::standard::{check_spec, project_surface, StandardFamily, StandardSurface};
use woven_render::woven_material::{TableGrid, WovenMaterial};

/// The surface keys this command takes, each with its flag: `(key, flag)`.
const SURFACE_FLAGS: [(&str, &str); 8] = [
    ("pattern", "--pattern"),
    ("yarns_per_unit", "--yarns-per-unit"),
    ("weft_color", "--weft-color"),
    ("warp_color", "--warp-color"),
    ("u_max_deg", "--u-max-deg"),
    ("gap", "--gap"),
    ("transmission", "--transmission"),
    ("irregularity", "--irregularity"),
];

/// Runs `--format openpbr` or `--format gltf`.
pub fn run(args: &ExportArgs) -> Result<()> {
    let outputs = outputs(args)?;
    let paths: Vec<PathBuf> = outputs.iter().map(|o| o.1.clone()).collect();
    io::check_output_dirs(&paths)?;
    refuse_other_formats_flags(args)?;
    let Some(source) = &args.material else {
        bail!("--format {} needs --material", format_name(args.format));
    };
    let name = match source.load_any()? {
        AnyMaterial::Woven(m) => source.display_name(&m),
        AnyMaterial::Microcylinder(m) => bail!(
            "`{}` is a microcylinder fabric: --format openpbr and gltf project a woven \
             material's yarn families onto the standard lobes (give a woven preset or file; \
             `woven materials` lists them)",
            m.name
        ),
    };
    let options = GltfOptions {
        swatch_m: args.swatch_m,
    };
    options
        .validate()
        .map_err(|e| anyhow::anyhow!("{}", e.to_string().replace("`swatch_m`", "--swatch-m")))?;

    let built = build_surface(args, &source.to_string(), &name)?;
    let surface = built.surface();
    // The layout first: a bad --texels-per-cell is refused before the projection's seconds.
    let images = LayoutImages::bake(surface, args.texels_per_cell)
        .map_err(|e| anyhow::anyhow!("{}", flag_names(&e.to_string())))?;
    let start = Instant::now();
    eprintln!("projecting `{name}`'s weft and warp onto the standard lobes (seconds each)…");
    let standard = project_surface(surface)
        .with_context(|| format!("cannot project `{name}` onto the standard lobes"))?;
    let projection_time = start.elapsed();
    for (format, path) in &outputs {
        println!("{}.", write(*format, &standard, &images, path, &options)?);
    }
    println!(
        "`{name}` on the standard lobes: one tile of {}×{} pattern cells at {}×{} cells per unit \
         of uv; the projection took {}.",
        images.cells[0],
        images.cells[1],
        standard.yarns_per_unit[0],
        standard.yarns_per_unit[1],
        seconds(projection_time),
    );
    print_errors(&standard);
    Ok(())
}

/// The files to write and their formats: `--output` in `--format`, and `--also-output` in the
/// other standard-lobe format, which its extension names.
fn outputs(args: &ExportArgs) -> Result<Vec<(ExportFormat, PathBuf)>> {
    let mut out = vec![(args.format, args.output.clone())];
    if let Some(also) = &args.also_output {
        let ext = also
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        let format = match ext.as_deref() {
            Some("mtlx") => ExportFormat::Openpbr,
            Some("gltf") => ExportFormat::Gltf,
            _ => bail!(
                "--also-output `{}`: the extension chooses the format: .mtlx (openpbr) or .gltf",
                also.display()
            ),
        };
        if format == args.format {
            bail!(
                "--also-output `{}` is in --format {} too: give it a file of the other format",
                also.display(),
                format_name(format)
            );
        }
        out.push((format, also.clone()));
    }
    Ok(out)
}

/// Writes `standard` laid out by `images` as `format` to `path`; what was written, in words.
fn write(
    format: ExportFormat,
    standard: &StandardSurface,
    images: &LayoutImages,
    path: &Path,
    options: &GltfOptions,
) -> Result<String> {
    let [w, h] = images.size();
    let cannot = || format!("cannot write `{}`", path.display());
    Ok(match format {
        ExportFormat::Openpbr => {
            let files = openpbr::write(standard, images, path).with_context(cannot)?;
            format!(
                "Wrote {} (MaterialX 1.39, OpenPBR Surface 1.1) and its textures {} and {} \
                 ({w}×{h} texels, 16-bit)",
                files.document.display(),
                files.textures.layout.display(),
                files.textures.factors.display()
            )
        }
        ExportFormat::Gltf => {
            let files = gltf::write(standard, images, path, options).with_context(cannot)?;
            let names: Vec<String> = files
                .textures
                .iter()
                .map(|p| p.display().to_string())
                .collect();
            format!(
                "Wrote {} (glTF 2.0: a {} cm swatch; {}), {} and its textures {} ({w}×{h} \
                 texels, 8-bit)",
                files.gltf.display(),
                100.0 * options.swatch_m,
                gltf::EXTENSIONS.join(", "),
                files.bin.display(),
                names.join(", ")
            )
        }
        ExportFormat::Merl | ExportFormat::Rgl => bail!(
            "--format {}: not a standard-lobe format",
            format_name(format)
        ),
    })
}

/// The name of `format` as `--format` takes it.
fn format_name(format: ExportFormat) -> &'static str {
    match format {
        ExportFormat::Merl => "merl",
        ExportFormat::Rgl => "rgl",
        ExportFormat::Openpbr => "openpbr",
        ExportFormat::Gltf => "gltf",
    }
}

/// Refuses the flags of the other formats.
fn refuse_other_formats_flags(args: &ExportArgs) -> Result<()> {
    let format = format_name(args.format);
    if args.table.is_some() {
        bail!("--table exports MERL files only; --format {format} tabulates --material's yarn");
    }
    if args.rgb || args.spectral {
        bail!("--rgb and --spectral are for --format rgl; --format {format} writes RGB");
    }
    if args.wavelength_nm.is_some() {
        bail!(
            "--wavelength-nm is not taken by --format {format}: a woven surface's tables are \
             built at 550 nm, as `woven render` builds them"
        );
    }
    Ok(())
}

/// The surface the flags describe, its tables from the user's cache (or built there), as
/// `woven render` prepares a woven material.
fn build_surface(args: &ExportArgs, material: &str, name: &str) -> Result<WovenMaterial> {
    let keys = surface_keys(args, material);
    let read = SurfaceSpec::from_keys(&keys).map_err(|e| {
        let message = flag_names(&e.to_string());
        // The key's flag, where the library's words name a place within it (`weave.pattern`).
        match SURFACE_FLAGS.iter().find(|(key, _)| e.key.starts_with(key)) {
            Some((_, flag)) if !message.contains(flag) => anyhow::anyhow!("{flag}: {message}"),
            _ => anyhow::anyhow!("{message}"),
        }
    })?;
    // Refused before the tables' seconds.
    check_spec(&read.spec).map_err(|e| anyhow::anyhow!("{}", flag_names(&e.to_string())))?;
    let grid = if args.draft_tables {
        tables::draft_grid()
    } else {
        TableGrid::Default
    };
    let mut cache = tables::user_cache(args.no_cache);
    let bar = Progress::new(Some(0), "table rows", true);
    let start = Instant::now();
    let built = WovenMaterial::build(
        &read.spec,
        &grid,
        &mut cache,
        &|| {
            let kept = if args.no_cache {
                ""
            } else {
                "; kept for later runs"
            };
            eprintln!("tabulating `{name}`'s yarn (seconds{kept})…");
        },
        &|done: usize, total: usize| bar.set(done as u64, total as u64),
    )
    .with_context(|| format!("cannot prepare `{name}`'s surface"))?;
    bar.finish();
    let elapsed = start.elapsed();
    if elapsed.as_secs_f64() >= 1.0 {
        eprintln!("`{name}`'s tables ready in {}", seconds(elapsed));
    }
    Ok(built)
}

/// The library's surface keys of `material` and the flags given.
fn surface_keys(args: &ExportArgs, material: &str) -> Keys {
    let mut keys = Keys::new().with("material", KeyValue::Text(material.to_string()));
    if let Some(p) = &args.pattern {
        // A WIF draft is a file; anything else a weave's name.
        let value = if p.to_ascii_lowercase().ends_with(".wif") {
            KeyValue::Table(vec![("wif".into(), KeyValue::Text(p.clone()))])
        } else {
            KeyValue::Text(p.clone())
        };
        keys.insert("pattern", value);
    }
    for (key, value) in [
        ("yarns_per_unit", &args.yarns_per_unit),
        ("irregularity", &args.irregularity),
    ] {
        if let Some(v) = value {
            // The library reads one number or two from words ("40", "40,60").
            keys.insert(key, KeyValue::Text(v.clone()));
        }
    }
    for (key, value) in [
        ("weft_color", &args.weft_color),
        ("warp_color", &args.warp_color),
    ] {
        if let Some(v) = value {
            keys.insert(key, numbers(v));
        }
    }
    for (key, value) in [("u_max_deg", args.u_max_deg), ("gap", args.gap)] {
        if let Some(v) = value {
            keys.insert(key, KeyValue::Float(v));
        }
    }
    if let Some(on) = args.transmission {
        keys.insert("transmission", KeyValue::Bool(on));
    }
    keys
}

/// `R,G,B` as a list of numbers; words that are not numbers are handed on as they are, for the
/// key's reader to refuse with its range.
fn numbers(text: &str) -> KeyValue {
    let parts: Option<Vec<KeyValue>> = text
        .split(',')
        .map(|p| p.trim().parse::<f64>().ok().map(KeyValue::Float))
        .collect();
    parts.map_or_else(|| KeyValue::Text(text.to_string()), KeyValue::List)
}

/// A library message with the keys and parameters named as this command's flags.
fn flag_names(message: &str) -> String {
    let mut out = message.to_string();
    for (key, flag) in SURFACE_FLAGS
        .iter()
        .chain(&[("texels_per_cell", "--texels-per-cell")])
    {
        out = out.replace(&format!("`{key}`"), flag);
    }
    out
}

/// The mixture's RMS log error per family beside the isotropic baseline's.
fn print_errors(standard: &StandardSurface) {
    let line = |which: &str, f: &StandardFamily| {
        let [along, across] = f.lobes.alpha;
        println!(
            "  {which}: RMS log error {:.3} (one isotropic GGX + Lambert: {:.3}); GGX α {:.3} \
             along the yarn, {:.3} across; sheen {:.4}",
            f.rms_log, f.isotropic_rms_log, along, across, f.lobes.sheen
        );
    };
    line("weft", &standard.weft);
    line("warp", &standard.warp);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_are_lists_and_other_words_pass_through() {
        assert_eq!(
            numbers("0.5, 1,0"),
            KeyValue::List(vec![
                KeyValue::Float(0.5),
                KeyValue::Float(1.0),
                KeyValue::Float(0.0)
            ])
        );
        assert_eq!(numbers("red"), KeyValue::Text("red".into()));
        assert_eq!(
            flag_names("`gap` = 2: expected a fraction"),
            "--gap = 2: expected a fraction"
        );
    }
}
