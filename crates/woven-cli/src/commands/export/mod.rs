//! `woven export`: a material's BRDF in a renderer's file format (the MERL BRDF layout, or RGL's
//! `.bsdf` tensor file), or a woven surface on the standard lobes other renderers carry (a
//! MaterialX document of OpenPBR Surface, a glTF swatch: [`standard`]).

pub mod standard;

use crate::args::{self, material_help, parse_finite, MaterialSource, DEFAULT_WAVELENGTH_NM};
use crate::io;
use crate::numbers::{group_digits, megabytes, seconds};
use crate::progress::Progress;
use crate::tables::{build_table, Built};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;
use woven::bsdf::Bsdf;
use woven::export::merl::{self, MerlBrdf, MERL_BINS, PHI_D_RES};
use woven::export::rgl::{self, Channels, RglFile, RglOptions};
use woven::figures::words::short;
use woven::material::Material;
use woven::table::cache::Tables;
use woven::table::{Symmetry, Table, TableOptions};

/// The long help of `woven export`.
const LONG_ABOUT: &str = "Write a material's BRDF in a file format renderers read (--format \
merl, the default, or rgl), or a woven surface on the standard lobes other renderers carry \
(--format openpbr or gltf).

openpbr, gltf: each yarn family of the woven surface (--material with the surface keys a \
scene's woven material takes: --pattern, --yarns-per-unit, --weft-color, --warp-color, \
--u-max-deg, --gap, --irregularity) projected onto the standard lobes (Lambert + anisotropic GGX \
along the yarn, fitted to the family's whole float as the cloth shows it, its colours per \
channel; woven_fit::standard); the layout (which family is on top, holes, dye factors) baked \
into textures of one tile (--texels-per-cell along each cell's side). The yarn's table comes \
from the cache `woven render` shares, or is built there (tens of seconds; --draft-tables: a \
coarse grid, seconds); the projection takes seconds per family. openpbr writes a MaterialX 1.39 \
document (NAME.mtlx) of OpenPBR Surface 1.1: one open_pbr_surface per family mixed by the \
layout texture, and the layout's 16-bit textures beside it (NAME-layout.png, NAME-factors.png, \
and NAME-normal.png, which the document does not read), on a uv in metres at --yarns-per-unit \
cells per metre. gltf writes a glTF 2.0 swatch (NAME.gltf, NAME.bin, NAME-gltf-*.png): a square \
of --swatch-m metres whose one material carries the families texel by texel (base colour, \
roughness, KHR_materials_anisotropy, KHR_materials_sheen, KHR_materials_specular, \
KHR_materials_ior), the weave at --yarns-per-unit cells per metre. --also-output FILE writes \
the other of the two from the same projection. Both print each family's RMS log error beside \
the best single isotropic GGX + Lambert's. What the standard lobes cannot carry (the masking's \
dependence on the light, interreflection, the paper normalization's non-reciprocity, the fibre \
level) is in docs/export.md. Files are written whole or not at all, the textures before the \
document.

rgl: RGL's `.bsdf` format (Dupuy & Jakob 2018), which Mitsuba 3's `measured` plugin \
({\"type\": \"measured\", \"filename\": \"cloth.bsdf\"}) and pbrt-v4's `measured` material \
(\"string filename\" \"cloth.bsdf\") read natively. It holds anisotropic BRDFs (the incident \
azimuth spans the full circle) in colour: --rgb (the default; Mitsuba's RGB variants) or \
--spectral (Mitsuba's spectral variants and pbrt-v4, which reads only spectral files): the three \
channels laid on the spectrum, blue at 450 nm, green at 540 nm, red at 610 nm, linear between \
and constant beyond, which three wavelengths hold exactly as readers interpolate. It holds the cloth-level BRDF, the paper's Eq. (23) \
with the material's dyes, as `woven render` shades a cloth at `detail = \"cloth\"`: a woven \
material from its yarn's table (`woven tabulate`'s grid, kept in the table cache), a \
microcylinder fabric exactly. The weave's spatial structure (yarns, tilt, gaps, the fibre level) \
is not a BRDF and needs woven's renderer or its Mitsuba plugin. The resolution flags trade the \
file's size for its accuracy; the defaults keep f·cos within about 2 % (median) of the exact \
model up to 80°; the file is written atomically and its size stated.

merl: the binary layout of the MERL BRDF database (90 θh × 90 θd × 180 φd bins of f64 in three \
colour channels, 34,992,012 bytes), which Mitsuba, pbrt and most BRDF tools load. The layout \
has no half-vector azimuth, so it holds isotropic BRDFs only, the same at every azimuth: flat \
fiber surfaces and yarns with `isotropic = true` (the silk preset). Yarns whose fibers run along \
the weft and the warp (twisted or not) are anisotropic and are refused: tabulate them with \
`woven tabulate` instead, which keeps the azimuth. The \
BRDF is grey (the same in all three channels), sampled once at each bin's centre; bins whose \
centre lies below the horizon hold 0. The layout assumes reciprocity (a reader folds φd ≥ 180° \
onto φd − 180°), which the `paper` normalization holds only up to its factor β(θi).

Flat fibers are evaluated exactly (about a second for the 1,458,000 bins on two cores). Woven \
isotropic yarns take about a millisecond per exact evaluation — a quarter of an hour or more for \
the bins on two cores — so woven first builds a table of the material (as `woven tabulate` does, default grid; a \
progress bar shows on standard error when it is a terminal) and exports the table, and says \
so. --table exports a table you built with `woven tabulate` instead (then --material may be \
left out, or must name the table's material). Bins are evaluated in parallel; the file is \
written atomically.";

/// Arguments of `woven export`.
#[derive(Args, Debug)]
#[command(
    about = "Export a material for other renderers: MERL, RGL .bsdf, OpenPBR (MaterialX) or glTF",
    long_about = LONG_ABOUT,
    after_help = "Examples:
  woven export --material my-flat-fiber.toml -o fiber.binary
  woven export --material silk -o silk.binary
  woven tabulate --material silk -o silk.wtab --n-h-isotropic 241
  woven export --table silk.wtab -o silk.binary
  woven export --format openpbr -m silk-shot -o silk-shot.mtlx
  woven export --format gltf -m satin-charmeuse --yarns-per-unit 400 -o charmeuse.gltf"
)]
pub struct ExportArgs {
    #[arg(short, long, value_name = "PRESET|FILE", value_parser = MaterialSource::parse,
          help = material_help(), required_unless_present = "table")]
    pub material: Option<MaterialSource>,

    /// The file format.
    #[arg(long, value_enum, default_value_t = ExportFormat::Merl)]
    pub format: ExportFormat,

    /// The file to write, atomically.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,

    /// Wavelength at which the material is evaluated, in nanometres [default: 550]. With --table
    /// it may only repeat the table's own wavelength.
    #[arg(long, value_name = "NM", value_parser = parse_finite)]
    pub wavelength_nm: Option<f64>,

    /// Export this table (built by `woven tabulate`) instead of evaluating the material (merl
    /// only).
    #[arg(long, value_name = "FILE")]
    pub table: Option<PathBuf>,

    /// rgl: red, green and blue values (the default), for Mitsuba 3's RGB variants.
    #[arg(long, conflicts_with = "spectral")]
    pub rgb: bool,

    /// rgl: spectral values (450, 540 and 610 nm: blue, green and red, linear between), for
    /// Mitsuba 3's spectral variants and pbrt-v4.
    #[arg(long)]
    pub spectral: bool,

    /// rgl: incident polar nodes, from 0° to 87° (more: a larger file, closer at grazing views).
    #[arg(long, value_name = "N", default_value_t = RglOptions::default().n_theta_i)]
    pub n_theta_i: usize,

    /// rgl: incident azimuth nodes over the full circle (both ends included).
    #[arg(long, value_name = "N", default_value_t = RglOptions::default().n_phi_i)]
    pub n_phi_i: usize,

    /// rgl: nodes along each side of each incident direction's sample grid.
    #[arg(long, value_name = "N", default_value_t = RglOptions::default().n_grid)]
    pub n_grid: usize,

    /// openpbr, gltf: the weave laid on the surface in place of the material's own: a weave's
    /// name ("plain", "twill-2/1", "satin-5", …) or a WIF draft (FILE.wif).
    #[arg(long, value_name = "NAME|FILE.wif")]
    pub pattern: Option<String>,

    /// openpbr, gltf: pattern cells per metre of uv, one number for both directions or `N_U,N_V`
    /// [default: 40].
    #[arg(long, value_name = "N|N_U,N_V", allow_hyphen_values = true)]
    pub yarns_per_unit: Option<String>,

    /// openpbr, gltf: the weft's dyed fibre albedo per channel, linear RGB in [0, 1] [default:
    /// the material's].
    #[arg(long, value_name = "R,G,B")]
    pub weft_color: Option<String>,

    /// openpbr, gltf: the warp's dyed fibre albedo per channel, as --weft-color.
    #[arg(long, value_name = "R,G,B")]
    pub warp_color: Option<String>,

    /// openpbr, gltf: the yarns' tilt at the ends of each float, degrees [default: the
    /// material's].
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_finite)]
    pub u_max_deg: Option<f64>,

    /// openpbr, gltf: the fraction of each cell between yarns (holes where both leave one)
    /// [default: the material's, else 0].
    #[arg(long, value_name = "FRACTION", allow_hyphen_values = true, value_parser = parse_finite)]
    pub gap: Option<f64>,

    /// openpbr, gltf: whether light passes through the cloth. These formats carry no
    /// transmission yet, so a material that lets light through (`cotton-voile`) is refused unless
    /// this is false: its reflection is then written, its holes black [default: the material's].
    #[arg(long, value_name = "BOOL")]
    pub transmission: Option<bool>,

    /// openpbr, gltf: the spread of the log of each yarn's dye along its length, one number or
    /// `WEFT,WARP` [default: 0].
    #[arg(long, value_name = "SIGMA|WEFT,WARP", allow_hyphen_values = true)]
    pub irregularity: Option<String>,

    /// openpbr, gltf: texels along each pattern cell's side in the textures, in [1, 64].
    #[arg(long, value_name = "N", default_value_t = 16)]
    pub texels_per_cell: usize,

    /// openpbr, gltf: also write the other of the two formats, from the same projection, to this
    /// file (.mtlx: openpbr; .gltf: gltf).
    #[arg(long, value_name = "FILE")]
    pub also_output: Option<PathBuf>,

    /// gltf: the swatch's side in metres.
    #[arg(long, value_name = "M", default_value_t = woven_fit::standard::gltf::DEFAULT_SWATCH_M,
          allow_hyphen_values = true, value_parser = parse_finite)]
    pub swatch_m: f64,

    /// openpbr, gltf: tabulate the yarn on a coarse grid (seconds instead of tens of seconds;
    /// highlights lose detail), as `woven render --draft-tables`.
    #[arg(long)]
    pub draft_tables: bool,

    /// openpbr, gltf: build the yarn's table anew and keep none (default: kept in the user's
    /// cache folder, as `woven render` keeps them).
    #[arg(long)]
    pub no_cache: bool,
}

/// `--format` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ExportFormat {
    /// The MERL BRDF database's binary layout (isotropic materials).
    Merl,
    /// RGL's `.bsdf` tensor file (anisotropic, RGB or spectral): Mitsuba 3's `measured`
    /// plugin, pbrt-v4's `measured` material.
    Rgl,
    /// A MaterialX 1.39 document of OpenPBR Surface 1.1 and its textures (a woven surface on
    /// the standard lobes).
    Openpbr,
    /// A glTF 2.0 swatch: .gltf, .bin and textures (a woven surface on the standard lobes).
    Gltf,
}

/// Where the exported values come from.
enum Source {
    /// The exact model: fast enough for flat fibers.
    Exact(woven::Model),
    /// A table the user gave (`--table`).
    GivenTable(Table),
    /// A table built for this export, and how long the build took.
    BuiltTable(Built),
}

impl Source {
    fn brdf(&self) -> &dyn Bsdf<Value = f64> {
        match self {
            Source::Exact(model) => model,
            Source::GivenTable(table) => table,
            Source::BuiltTable(built) => &built.table,
        }
    }
}

/// Runs `woven export`.
pub fn run(args: &ExportArgs) -> Result<()> {
    if matches!(args.format, ExportFormat::Merl | ExportFormat::Rgl) {
        let surface_flags = [
            ("--pattern", args.pattern.is_some()),
            ("--yarns-per-unit", args.yarns_per_unit.is_some()),
            ("--weft-color", args.weft_color.is_some()),
            ("--warp-color", args.warp_color.is_some()),
            ("--u-max-deg", args.u_max_deg.is_some()),
            ("--gap", args.gap.is_some()),
            ("--transmission", args.transmission.is_some()),
            ("--irregularity", args.irregularity.is_some()),
            ("--also-output", args.also_output.is_some()),
            ("--draft-tables", args.draft_tables),
            ("--no-cache", args.no_cache),
        ];
        if let Some((flag, _)) = surface_flags.iter().find(|f| f.1) {
            bail!(
                "{flag} is for --format openpbr and gltf (a woven surface); merl and rgl export \
                 the material's cloth-level BRDF"
            );
        }
    }
    match args.format {
        ExportFormat::Merl => export_merl(args),
        ExportFormat::Rgl => export_rgl(args),
        ExportFormat::Openpbr | ExportFormat::Gltf => standard::run(args),
    }
}

/// `--format rgl`.
fn export_rgl(args: &ExportArgs) -> Result<()> {
    io::check_output_dirs(std::slice::from_ref(&args.output))?;
    if args.table.is_some() {
        bail!("--table exports MERL files only; --format rgl evaluates --material");
    }
    let Some(source) = &args.material else {
        bail!("--format rgl needs --material");
    };
    let options = RglOptions {
        n_theta_i: args.n_theta_i,
        n_phi_i: args.n_phi_i,
        n_grid: args.n_grid,
        channels: if args.spectral {
            Channels::Spectral(rgl::default_wavelengths())
        } else {
            Channels::Rgb
        },
        ..RglOptions::default()
    };
    options
        .validate()
        .map_err(|e| anyhow::anyhow!("{}", flag_names(&e.to_string())))?;
    let nm = args.wavelength_nm.unwrap_or(DEFAULT_WAVELENGTH_NM);
    let any = source.load_any()?;
    let name = any
        .name()
        .map_or_else(|| source.to_string(), str::to_string);
    let mut tables = match woven::table::cache::Cache::user() {
        Ok(disk) => Tables::with_disk(disk).with_notes(|m| eprintln!("note: {m}")),
        Err(_) => Tables::default(),
    };
    let build_start = Instant::now();
    let bar = Progress::new(Some(0), "table rows", true);
    let brdf = rgl::material_brdf(
        &any,
        nm,
        &mut tables,
        &|path| match path {
            Some(p) => eprintln!("tabulating `{name}`'s yarn (kept in {})", p.display()),
            None => eprintln!("tabulating `{name}`'s yarn"),
        },
        &|done, total| bar.set(done as u64, total as u64),
    )
    .with_context(|| format!("cannot prepare `{name}` at --wavelength-nm {nm}"))?;
    bar.finish();
    let table_time = build_start.elapsed();

    let start = Instant::now();
    let bar = Progress::new(Some(0), "incident directions", true);
    let description = format!(
        "woven {}: `{name}`, the Yang–Ikeuchi cloth-level BRDF at {} nm",
        env!("CARGO_PKG_VERSION"),
        short(nm)
    );
    let file = RglFile::build(&*brdf, &description, &options, &|d, t| {
        bar.set(d as u64, t as u64)
    })?;
    bar.finish();
    io::write_atomically(&args.output, |out| Ok(file.write(out)?))
        .with_context(|| format!("cannot write `{}`", args.output.display()))?;
    let channels = match &options.channels {
        Channels::Rgb => "RGB".to_string(),
        Channels::Spectral(nm) => format!(
            "spectral at {} nm",
            nm.iter().map(|l| short(*l)).collect::<Vec<_>>().join(", ")
        ),
    };
    println!(
        "Wrote {} ({}): `{name}` in RGL's .bsdf format, {} θi × {} φi incident directions × \
         {n}² samples, {channels}; built in {} (the yarn's table took {}). Mitsuba 3: \
         {{\"type\": \"measured\", \"filename\": \"{}\"}}; pbrt-v4: Material \"measured\" \
         \"string filename\" \"{}\".",
        args.output.display(),
        megabytes(file.len()),
        options.n_theta_i,
        options.n_phi_i,
        seconds(start.elapsed()),
        seconds(table_time),
        args.output.display(),
        args.output.display(),
        n = options.n_grid,
    );
    Ok(())
}

/// A library message about [`RglOptions`] with its fields named as this command's flags.
fn flag_names(message: &str) -> String {
    ["n_theta_i", "n_phi_i", "n_grid"]
        .iter()
        .fold(message.to_string(), |m, field| {
            m.replace(
                &format!("`{field}`"),
                &format!("--{}", field.replace('_', "-")),
            )
        })
}

fn export_merl(args: &ExportArgs) -> Result<()> {
    if args.rgb || args.spectral {
        bail!("--rgb and --spectral are for --format rgl; a MERL file is grey");
    }
    io::check_output_dirs(std::slice::from_ref(&args.output))?;
    let table = match &args.table {
        Some(path) => Some(args::load_table(path, args.wavelength_nm)?),
        None => None,
    };
    let (material, name) = material_of(args, table.as_ref())?;
    merl::check_isotropic(&material)
        .with_context(|| format!("cannot export `{name}` in the MERL layout"))?;
    let wavelength_nm = match &table {
        Some(t) => t.wavelength_nm(),
        None => args.wavelength_nm.unwrap_or(DEFAULT_WAVELENGTH_NM),
    };

    let source = match table {
        Some(table) => {
            if table.symmetry() != Symmetry::Isotropic {
                bail!(
                    "--table `{}` is not an isotropic table; the MERL layout holds isotropic \
                     BRDFs only",
                    table_name(args)
                );
            }
            Source::GivenTable(table)
        }
        None => {
            let model = material.build(wavelength_nm).with_context(|| {
                format!("cannot prepare material `{name}` at --wavelength-nm {wavelength_nm}")
            })?;
            if material.yarn.is_some() {
                let built = build_table(&material, &model, &TableOptions::for_model(&model))?;
                let (n_theta, _, n_h) = built.table.dims();
                eprintln!(
                    "note: `{name}` has isotropic yarns: an exact evaluation takes about a millisecond, \
                     far too slow for {} bins, so woven tabulated it first ({n_theta} θi × {n_h}² \
                     half-vector nodes, in {}) and exports the table. `woven tabulate -m {name} \
                     --report` states a table's accuracy; build one there (finer with \
                     --n-h-isotropic) and pass it with --table to reuse it.",
                    group_digits(MERL_BINS as u64),
                    seconds(built.elapsed)
                );
                Source::BuiltTable(built)
            } else {
                Source::Exact(model)
            }
        }
    };

    let start = Instant::now();
    let mono = eval_bins(source.brdf());
    let brdf = MerlBrdf::from_values(&mono)
        .with_context(|| format!("cannot export `{name}` in the MERL layout"))?;
    // The CLI's atomic writer rather than `MerlBrdf::save`: a device such as /dev/null is
    // written, not replaced.
    io::write_atomically(&args.output, |out| Ok(brdf.write(out)?))
        .with_context(|| format!("cannot write `{}`", args.output.display()))?;
    let from = match &source {
        Source::Exact(_) => "the exact model".to_string(),
        Source::GivenTable(_) => format!("the table `{}`", table_name(args)),
        Source::BuiltTable(_) => "its table".to_string(),
    };
    println!(
        "Wrote {} ({}): `{name}` at {} nm in the MERL BRDF layout, 90 θh × 90 θd × 180 φd = {} \
         bins, grey (the same BRDF in all three channels), from {from}; the bins took {}.",
        args.output.display(),
        megabytes(merl::FILE_SIZE as u64),
        short(wavelength_nm),
        group_digits(MERL_BINS as u64),
        seconds(start.elapsed()),
    );
    Ok(())
}

/// The material to export and its display name: `--material`, else the one recorded in
/// `--table`; when both are given they must be the same material.
fn material_of(args: &ExportArgs, table: Option<&Table>) -> Result<(Material, String)> {
    let recorded = |table: &Table| -> Result<Material> {
        let name = table_name(args).to_string();
        table
            .material()
            .cloned()
            .with_context(|| format!("--table `{name}` records no material"))
    };
    match (&args.material, table) {
        (Some(source), table) => {
            let material = source.load()?;
            let name = source.display_name(&material);
            if let Some(table) = table {
                let theirs = recorded(table)?;
                if theirs.to_self_contained_toml_string()
                    != material.to_self_contained_toml_string()
                {
                    bail!(
                        "--table `{}` was built from another material than --material `{source}` \
                         (`woven tabulate` records it); leave --material out to export the \
                         table's material, or tabulate `{source}`",
                        table_name(args)
                    );
                }
            }
            Ok((material, name))
        }
        (None, Some(table)) => {
            let material = recorded(table)?;
            let name = material
                .name
                .clone()
                .unwrap_or_else(|| table_name(args).to_string());
            Ok((material, name))
        }
        // clap requires --material unless --table is given.
        (None, None) => bail!("give --material or --table"),
    }
}

/// The `--table` path for messages (empty when there is none).
fn table_name(args: &ExportArgs) -> std::path::Display<'_> {
    args.table.as_deref().unwrap_or(Path::new("")).display()
}

/// The BRDF at every MERL bin's sample directions ([`merl::eval_bin`]), in bin order, in
/// parallel, with a progress bar.
pub fn eval_bins(brdf: &dyn Bsdf<Value = f64>) -> Vec<f64> {
    let bar = Progress::new(Some(MERL_BINS as u64), "bins", true);
    let mut mono = vec![0.0; MERL_BINS];
    // One task per (θh, θd) row of 180 φd bins: rows below the horizon cost nothing, so small
    // tasks keep the cores balanced.
    mono.par_chunks_mut(PHI_D_RES)
        .enumerate()
        .for_each(|(row, values)| {
            for (k, value) in values.iter_mut().enumerate() {
                *value = merl::eval_bin(row * PHI_D_RES + k, |s, v| brdf.eval(s, v));
            }
            bar.inc(values.len() as u64);
        });
    bar.finish();
    mono
}
