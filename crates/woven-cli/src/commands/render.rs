//! `woven render`: path-traced images of scenes with woven cloth (the `woven-render` crate).
//! Bare `woven` runs it on the built-in showcase.

use crate::args::parse_finite;
use crate::progress::Progress;
use crate::tables;
use anyhow::{bail, Context, Result};
use clap::Args;

use std::path::{Path, PathBuf};
use std::time::Instant;
use woven_render::output::{self, Format};
use woven_render::render::{render_with_progress, RenderOptions};
use woven_render::rng::SamplerKind;
use woven_render::scene::{
    FilmOverrides, Scene, SceneDescription, EXAMPLE_SCENE, MAX_FILM_SIDE, MAX_SPP, SHOWCASE_SCENE,
};
use woven_render::tonemap::ToneMap;
use woven_render::woven_material::TableGrid;

/// The folder images go to when `-o` is not given, relative to the current directory.
pub const OUT_DIR: &str = "woven-out";

/// Arguments of `woven render`.
#[derive(Args, Debug, Default)]
#[command(
    about = "Render a scene of woven cloth (path tracing) to OpenEXR and PNG",
    long_about = "Renders a scene file (TOML; `woven render --example` prints a complete, \
commented one; docs/render.md describes the format) with a path tracer: next-event estimation \
and BSDF sampling combined by MIS, woven materials tabulated from the model at 550 nm, the weave \
pattern deciding at every point whether the weft or the warp is on top.

Without a scene file it renders the built-in showcase: at real thread counts, a satin \
charmeuse thrown over a stool, a linen tablecloth on a round table, a shot-silk cushion and a \
denim twill cushion, under a low sun and a clear sky, with the twill's yarns resolved in a \
close-up inset (960×540, 12 spp, denoised; `woven render --example` prints another scene).

Writes a linear float32 OpenEXR and an sRGB PNG: by default both, as woven-out/<scene>.exr and \
.png; with -o, the one format its extension names (.exr or .png). Files are written atomically.",
    after_help = "Examples:
  woven render
  woven render --example > my.toml && woven render my.toml -o my.png --spp 16
  woven render scene.toml --width 320 --height 180 --threads 2 --exposure 1"
)]
pub struct RenderArgs {
    /// The scene file (TOML); none renders the built-in showcase.
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,

    /// Print a complete, commented example scene and exit.
    #[arg(long, conflicts_with_all = ["scene", "output"])]
    pub example: bool,

    /// Output image: .exr (linear float32 RGB) or .png (sRGB); default both, in woven-out/.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,

    /// Samples per pixel (overrides [film] spp).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=MAX_SPP as i64))]
    pub spp: Option<u32>,

    /// Image width in pixels (overrides [film] width).
    #[arg(long, value_name = "PIXELS", value_parser = clap::value_parser!(u32).range(1..=MAX_FILM_SIDE as i64))]
    pub width: Option<u32>,

    /// Image height in pixels (overrides [film] height).
    #[arg(long, value_name = "PIXELS", value_parser = clap::value_parser!(u32).range(1..=MAX_FILM_SIDE as i64))]
    pub height: Option<u32>,

    /// Random seed (overrides [film] seed); a seed always renders the same image.
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,

    /// Where the samples come from (overrides [film] sampler): Owen-scrambled Sobol points
    /// (less noise) or independent uniforms (Mitsuba's; exact standard errors).
    #[arg(long, value_parser = sampler_parser())]
    pub sampler: Option<SamplerKind>,

    /// Worker threads (default: all cores).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub threads: Option<u32>,

    /// Build woven tables on a coarse grid: seconds instead of tens of seconds per material, for
    /// previews (highlights lose detail).
    #[arg(long)]
    pub draft_tables: bool,

    /// Build every woven table anew and keep none (default: tables are kept in the user's cache
    /// folder, `$XDG_CACHE_HOME/woven` or `~/.cache/woven`, and loaded on later runs).
    #[arg(long)]
    pub no_cache: bool,

    /// Exposure of the PNG in stops (overrides [film] exposure): values are scaled by 2^EV
    /// before the tone map.
    #[arg(long, value_name = "EV", allow_hyphen_values = true, value_parser = parse_finite)]
    pub exposure: Option<f64>,

    /// How the PNG maps light to display values (overrides [film] tonemap): `filmic` rolls
    /// highlights off to white in the manner of film (the default), `clamp` clips each channel
    /// at 1. The EXR stays linear.
    #[arg(long, value_parser = tonemap_parser())]
    pub tonemap: Option<ToneMap>,

    /// Denoise the image before writing it (overrides [film] denoise): an edge-avoiding filter
    /// guided by each pixel's noise and by what its rays first met (normal, distance, albedo).
    #[arg(long, overrides_with = "no_denoise")]
    pub denoise: bool,

    /// Write the raw, noisy estimate (overrides [film] denoise).
    #[arg(long, overrides_with = "denoise")]
    pub no_denoise: bool,
}

/// Runs `woven render`.
pub fn run(args: &RenderArgs) -> Result<()> {
    if args.example {
        print!("{EXAMPLE_SCENE}");
        return Ok(());
    }
    let start = Instant::now();
    let (desc, stem) = match &args.scene {
        Some(path) => (
            SceneDescription::from_path(path)?,
            path.file_stem()
                .map_or("render".into(), |s| s.to_string_lossy().into_owned()),
        ),
        None => (
            SceneDescription::from_str(SHOWCASE_SCENE, "<built-in showcase>", Path::new("."))?,
            "showcase".to_string(),
        ),
    };
    let desc = desc.with_overrides(&FilmOverrides {
        spp: args.spp.map(|n| n as usize),
        width: args.width.map(|w| w as usize),
        height: args.height.map(|h| h as usize),
        seed: args.seed,
        sampler: args.sampler,
        exposure: args.exposure,
        tonemap: args.tonemap,
        denoise: (args.denoise || args.no_denoise).then_some(args.denoise),
    })?;
    let outputs: Vec<PathBuf> = match &args.output {
        Some(path) => {
            if Format::of(path).is_none() {
                bail!(
                    "-o `{}`: the extension chooses the format: .exr (linear float32 RGB) or .png \
                     (sRGB)",
                    path.display()
                );
            }
            vec![path.clone()]
        }
        None => {
            std::fs::create_dir_all(OUT_DIR)
                .with_context(|| format!("cannot create the output folder `{OUT_DIR}`"))?;
            let dir = Path::new(OUT_DIR);
            vec![
                dir.join(format!("{stem}.exr")),
                dir.join(format!("{stem}.png")),
            ]
        }
    };

    // Tables: one per woven material, built on first use.
    let table_bar = std::sync::Mutex::new(None::<Progress>);
    let on_table = |name: &str| {
        eprintln!("building the table of material `{name}` (seconds; kept for later runs)…");
        let mut bar = table_bar.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(b) = bar.take() {
            b.finish();
        }
        *bar = Some(Progress::new(None, "table nodes", true));
    };
    let progress = |done: usize, total: usize| {
        if let Some(b) = table_bar.lock().unwrap_or_else(|e| e.into_inner()).as_ref() {
            b.set(done as u64, total as u64);
        }
    };
    let grid = if args.draft_tables {
        tables::draft_grid()
    } else {
        TableGrid::Default
    };
    let cache = tables::user_cache(args.no_cache);
    let scene = Scene::build_with(&desc, &grid, cache, &on_table, &progress)?;
    if let Some(b) = table_bar.lock().unwrap_or_else(|e| e.into_inner()).take() {
        b.finish();
    }

    // The renderer reports samples done; the bar shows once the render turns out to be long.
    let film = &scene.film;
    let bar = Progress::with_rate(
        (film.width * film.height * film.spp) as u64,
        "samples",
        true,
    );
    let image = render_with_progress(
        &scene,
        &RenderOptions {
            threads: args.threads.map(|n| n as usize),
        },
        &|done, total| bar.set(done, total),
    )?;
    bar.finish();
    for path in &outputs {
        // Encoded here, written by the command line's atomic writer: an interruption while
        // writing removes the temporary file.
        let format = output::format_of(path)?;
        let bytes = output::encode(&image, format, &desc.film.display, path)?;
        crate::io::write_atomically(path, |w| Ok(w.write_all(&bytes)?))?;
    }
    println!(
        "rendered {} ({}×{}, {} spp{}) in {:.2} s ({:.2} M samples/s; {:.2} s in all):",
        desc.origin,
        image.width,
        image.height,
        image.spp,
        if image.noisy.is_some() {
            ", denoised"
        } else {
            ""
        },
        image.seconds,
        image.samples_per_second() / 1e6,
        start.elapsed().as_secs_f64()
    );
    for path in &outputs {
        println!("  {}", path.display());
    }
    if image.invalid_samples > 0 {
        eprintln!(
            "warning: {} samples were NaN, infinite or negative and counted as black",
            image.invalid_samples
        );
    }
    Ok(())
}

/// `--sampler`'s values, as `[film] sampler` names them.
fn tonemap_parser() -> impl clap::builder::TypedValueParser<Value = ToneMap> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(ToneMap::NAMES)
        .map(|s| ToneMap::parse(&s).expect("a listed name"))
}

fn sampler_parser() -> impl clap::builder::TypedValueParser<Value = SamplerKind> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(["sobol", "independent"]).map(|s| match s.as_str() {
        "independent" => SamplerKind::Independent,
        _ => SamplerKind::Sobol,
    })
}
