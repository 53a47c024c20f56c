//! `woven fit`: fits the woven-cloth model, or a baseline, to measured reflectance; `--compare`
//! fits every model to several datasets and prints one table. The fitting is the `woven-fit`
//! library's; this module parses, reports progress, writes files and draws the plot.

use crate::args::{parse_finite, MaterialSource};
use crate::io;
use crate::plotting::{plot_error, render_image, tick_label, Drawing, ImageFormat, COLORS, FONT};
use crate::progress::Progress;
use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;
use woven_fit::report::{comparison_table, in_plane_curves, Comparison};
use woven_fit::request::FitRequest;
use woven_fit::{fit, FitError, FitOptions, FitResult, ModelKind, ParamSet, Residual};

/// Arguments of `woven fit`.
#[derive(Args, Debug)]
#[command(
    about = "Fit the woven-cloth model, the microcylinder model, or a baseline, to measured reflectance",
    long_about = "Fit the woven-cloth model (--model cloth), the fiber BRDF alone (fiber), a \
Lambertian surface (lambert), a Beckmann microfacet + Lambert baseline (microfacet), the \
Charlie sheen over a Lambertian base (sheen, glTF's KHR_materials_sheen) or the microcylinder \
cloth model of Sadeghi et al. 2013 (microcylinder, with its energy guard, as it renders) to \
measurements, by a quasi-random multi-start and bounded Levenberg–Marquardt on log residuals. \
Deterministic for a --seed.

--data takes a measurement CSV (theta_i,phi_i,theta_r,phi_r,value, radians, BRDF in 1/sr; \
optional weight and value_r,value_g,value_b), the CSV `woven gonio` writes, or a CUReT, RGL or \
MERL-grid file of data/. Colour data fits the albedos per channel with the geometry shared.

Parameters (`--fix`, `--free`; short names such as `roughness` work): fiber.eta, \
fiber.roughness, fiber.diffuse, yarn.lateral_length, yarn.slope_mean, yarn.slope_std, \
yarn.interreflection, yarn.interreflection_albedo, yarn.twist_std, weave.weft_fraction, \
rotation (the weave's turn in the sample plane, radians), scale (free for relatively \
calibrated data); the baselines: diffuse, specular, alpha, eta (microfacet); diffuse, sheen \
(the sheen's colour, in [0, 1]) and roughness (glTF's sheenRoughness, in [0.1, 1]) (sheen); \
microcylinder: per thread (thread1 along x, the weft; thread2 along y) albedo (per channel), \
kd, gamma_s and gamma_v (radians), eta (held unless freed), and coverage (a1 + a2) and \
thread1.coverage_share (a1/(a1 + a2)), so each coverage is in [0, 1] with a1 + a2 <= 1. \
The yarn kind (one orientation, twisted, isotropic) is the --init material's; a \
microcylinder fit keeps the --init fabric's tangent curves (microcylinder-linen-plain by \
default).

The result: -o writes the fitted material (a material file for cloth and fiber, usable by \
woven eval, render and tabulate; a microcylinder file for microcylinder, usable by woven eval \
and render; the baselines' parameters as TOML), --report a Markdown \
report (values with standard errors, warnings for what the data cannot determine, residual \
statistics), --plot the data against the fit (SVG or PNG).",
    after_help = "Examples:
  woven fit --data sample.csv --model cloth -o fitted.toml --report fit.md --plot fit.png
  woven fit --data sample.csv --model cloth --init polyester-sateen --fix eta=1.6 --free twist_std
  woven fit --data sample.csv --model microfacet
  woven fit --data sample.csv --model sheen --report sheen.md
  woven fit --data sample.csv --model microcylinder --init microcylinder-silk-shot -o silk.toml
  woven fit --compare 'data/curet/abrdf.dat#linen' data/merl/beige-fabric.grid.csv"
)]
pub struct FitArgs {
    /// The measurements to fit.
    #[arg(
        long,
        value_name = "FILE",
        required_unless_present = "compare",
        conflicts_with = "compare"
    )]
    pub data: Option<PathBuf>,

    /// Fit every model of --models to each dataset and print one table of their errors.
    #[arg(long, value_name = "DATA", num_args = 1..)]
    pub compare: Vec<PathBuf>,

    /// The model: cloth, fiber, lambert, microfacet, sheen or microcylinder.
    #[arg(long, value_name = "MODEL", default_value = "cloth", value_parser = parse_model)]
    pub model: ModelKind,

    /// With --compare: the models, comma-separated (cloth, fiber, lambert, microfacet, sheen,
    /// microcylinder).
    #[arg(long, value_name = "MODELS", value_delimiter = ',', default_value = "lambert,microfacet,cloth",
          value_parser = parse_model)]
    pub models: Vec<ModelKind>,

    /// Hold a parameter at a value (repeatable): name=value.
    #[arg(long, value_name = "NAME=VALUE")]
    pub fix: Vec<String>,

    /// Let parameters vary (comma-separated names).
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    pub free: Vec<String>,

    /// The starting material: for cloth and fiber a woven preset or material file (belt-cloth by
    /// default); for microcylinder a microcylinder preset or file (microcylinder-linen-plain by
    /// default).
    #[arg(long, value_name = "PRESET|FILE", value_parser = MaterialSource::parse)]
    pub init: Option<MaterialSource>,

    /// Scrambles the quasi-random starts.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u32,

    /// Quasi-random starts screened.
    #[arg(long, value_name = "N", default_value_t = FitOptions::default().starts)]
    pub starts: usize,

    /// Levenberg–Marquardt iterations of the final run.
    #[arg(long, value_name = "N", default_value_t = FitOptions::default().max_iterations)]
    pub max_iterations: usize,

    /// The residual: log (default) or relative.
    #[arg(long, value_name = "KIND", default_value = "log", value_parser = parse_residual)]
    pub residual: Residual,

    /// Drop measurements at or above this value (saturated).
    #[arg(long, value_name = "VALUE", value_parser = parse_finite)]
    pub saturation: Option<f64>,

    /// The fitted material (TOML, written atomically).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,

    /// A Markdown report (--data), or the comparison table (--compare).
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,

    /// The data against the fit, SVG or PNG (by extension).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

fn parse_model(s: &str) -> Result<ModelKind, String> {
    ModelKind::parse(s).map_err(|e| e.to_string())
}

fn parse_residual(s: &str) -> Result<Residual, String> {
    Residual::parse(s).map_err(|e| e.to_string())
}

/// Runs `woven fit`.
pub fn run(args: &FitArgs) -> Result<()> {
    for path in args.output.iter().chain(&args.report).chain(&args.plot) {
        io::check_output_dirs(std::slice::from_ref(path))?;
    }
    if let Some(plot) = &args.plot {
        ImageFormat::from_path(plot).map_err(|_| {
            anyhow!(
                "--plot `{}`: the file name must end in .svg or .png",
                plot.display()
            )
        })?;
    }
    let options = FitOptions {
        residual: args.residual,
        seed: args.seed,
        starts: args.starts,
        max_iterations: args.max_iterations,
        saturation: args.saturation,
        ..FitOptions::default()
    };
    if !args.compare.is_empty() {
        return compare(args, &options);
    }
    let path = args
        .data
        .as_ref()
        .expect("clap requires --data without --compare");
    let dataset = load(path)?;
    let set = param_set(args, args.model, &dataset)?;
    let start = Instant::now();
    let result = run_fit(&dataset, &set, &options)?;
    let seconds = start.elapsed().as_secs_f64();
    eprintln!(
        "{}: {} fit to {} measurements in {seconds:.1} s: RMS log error {:.4}, relative RMS {:.4}",
        dataset.name,
        result.model,
        result.observations.len(),
        result.rms_log,
        result.relative_rms
    );
    for e in &result.estimates {
        eprintln!(
            "  {} = {} ± {}",
            e.name,
            woven_fit::report::fmt(e.value),
            woven_fit::report::fmt(e.std_error)
        );
    }
    for w in &result.warnings {
        eprintln!("warning: {w}");
    }
    // Every output made before any is written, then all written or none (a full disk).
    let mut files: Vec<(&Path, Vec<u8>)> = Vec::new();
    if let Some(out) = &args.output {
        let text = result
            .material_toml()
            .unwrap_or_else(|| result.params_toml());
        files.push((out, text.into_bytes()));
    }
    if let Some(report) = &args.report {
        files.push((report, result.to_markdown().into_bytes()));
    }
    if let Some(plot) = &args.plot {
        let bytes =
            draw_plot(&result, plot).with_context(|| format!("drawing `{}`", plot.display()))?;
        files.push((plot, bytes));
    }
    let files: Vec<(&Path, &[u8])> = files.iter().map(|(p, b)| (*p, b.as_slice())).collect();
    io::write_all_atomically(&files)
}

fn load(path: &Path) -> Result<woven_fit::data::Dataset> {
    woven_fit::data::load(path).with_context(|| format!("cannot load --data `{}`", path.display()))
}

/// The parameter set of `model` for `dataset` with the command line's --init, --fix and --free:
/// the library's [`FitRequest`], its errors in the flags' words.
fn param_set(
    args: &FitArgs,
    model: ModelKind,
    dataset: &woven_fit::data::Dataset,
) -> Result<ParamSet> {
    let request = FitRequest {
        init: init_for(args, model),
        fix: args.fix.clone(),
        free: args.free.clone(),
        ..FitRequest::new(model)
    };
    request
        .param_set(dataset)
        .with_context(|| match &request.init {
            Some(init) => format!("--model {model} --init {init}"),
            None => format!("--model {model}"),
        })
}

/// --init as `model`'s start. A single fit takes it as given (a baseline given one is an error:
/// the library says so). With --compare it is shared: each model takes it where it is of that
/// model's kind (a microcylinder preset or file for microcylinder, a woven material for cloth
/// and fiber), and the others start at their defaults.
fn init_for(args: &FitArgs, model: ModelKind) -> Option<String> {
    let init = args.init.as_ref()?.to_string();
    if args.compare.is_empty() {
        return Some(init);
    }
    let fabric = woven_fit::microcylinder::Fabric::from_preset_or_path(&init).is_ok();
    let fits = if model == ModelKind::Microcylinder {
        fabric
    } else {
        model.is_material() && !fabric
    };
    fits.then_some(init)
}

fn run_fit(
    dataset: &woven_fit::data::Dataset,
    set: &ParamSet,
    options: &FitOptions,
) -> Result<FitResult> {
    let progress = Progress::new(None, "steps", true);
    let result = fit(dataset, set, options, &|done, total| {
        progress.set(done as u64, total as u64)
    });
    progress.finish();
    result.map_err(|e| {
        // The library names its fixed parameters; here they are the --fix flag, shown on the
        // first parameter the data leaves undetermined (else the first free one), at its start.
        let example = match &e {
            FitError::Underdetermined { undetermined, .. } => Some(
                undetermined
                    .first()
                    .and_then(|name| set.params.iter().find(|p| &p.name == name))
                    .or_else(|| set.free_indices().first().map(|&i| &set.params[i]))
                    .map_or("name=value".into(), |p| {
                        format!("{}={}", p.name, woven_fit::report::fmt(p.value))
                    }),
            ),
            _ => None,
        };
        let e = anyhow::Error::from(e);
        match example {
            Some(example) => e.context(format!(
                "the data cannot determine this fit: hold parameters at a value with \
                 --fix name=value (e.g. --fix {example}), or measure more geometries"
            )),
            None => e,
        }
    })
}

/// `--compare`: every model on every dataset, one table.
fn compare(args: &FitArgs, options: &FitOptions) -> Result<()> {
    let mut rows = Vec::new();
    for path in &args.compare {
        let dataset = load(path)?;
        let mut fits = Vec::new();
        for &model in &args.models {
            let start = Instant::now();
            let outcome = param_set(args, model, &dataset)
                .and_then(|set| run_fit(&dataset, &set, options))
                .map(|r| (r.rms_log, r.relative_rms))
                .map_err(|e| format!("{e:#}"));
            eprintln!(
                "{} / {model}: {} ({:.1} s)",
                dataset.name,
                match &outcome {
                    Ok((log, rel)) => format!("RMS log {log:.4}, relative RMS {rel:.4}"),
                    Err(e) => format!("failed: {e}"),
                },
                start.elapsed().as_secs_f64()
            );
            fits.push((model.name().to_string(), outcome));
        }
        // MERL materials: the published SGD and ABC fits, scored alike.
        fits.extend(woven_fit::report::published_errors(&dataset));
        let points = dataset.samples.len();
        rows.push(Comparison {
            dataset: dataset.name.clone(),
            points,
            fits,
        });
    }
    let table = comparison_table(&rows);
    print!("{table}");
    if let Some(report) = &args.report {
        io::write_atomically(report, |w| Ok(w.write_all(table.as_bytes())?))?;
    }
    if args.output.is_some() || args.plot.is_some() {
        bail!(
            "-o and --plot are for a single fit (--data); --compare writes its table with --report"
        );
    }
    Ok(())
}

/// The plot: in-plane curves of the data and the fit (left, where the data has them) and the
/// fitted against the measured values (right), channel 0 (mono) or the channels' mean.
fn draw_plot(result: &FitResult, path: &Path) -> Result<Vec<u8>> {
    struct Plot<'a>(&'a FitResult);
    impl Drawing for Plot<'_> {
        fn draw_on<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
            draw(root, self.0)
        }
    }
    render_image(&Plot(result), ImageFormat::from_path(path)?, (1400, 650))
}

fn mean(v: &[f64; 3], channels: usize) -> f64 {
    v[..channels].iter().sum::<f64>() / channels as f64
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, result: &FitResult) -> Result<()> {
    root.fill(&WHITE).map_err(plot_error)?;
    let (left, right) = root.split_horizontally(root.dim_in_pixel().0 * 6 / 10);
    let ch = result.channels;
    let measured: Vec<f64> = result
        .observations
        .iter()
        .map(|o| mean(&o.value, ch))
        .collect();
    let fitted: Vec<f64> = result.predicted.iter().map(|p| mean(p, ch)).collect();
    let positive = measured.iter().chain(&fitted).copied().filter(|&x| x > 0.0);
    let lo = positive.clone().fold(f64::INFINITY, f64::min).max(1e-6);
    let hi = positive.fold(0.0f64, f64::max).max(lo * 10.0);
    let (lo, hi) = (lo / 1.5, hi * 1.5);

    // Left: in-plane curves (at most six incidences).
    let curves = in_plane_curves(&result.observations, 5);
    let mut chart = ChartBuilder::on(&left)
        .caption(
            format!("{}: {} fit, in-plane", result.dataset, result.model),
            (FONT, 22),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(-90.0..90.0, (lo..hi).log_scale())
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc("θr, degrees (> 0: specular side)")
        .y_desc("BRDF, 1/sr")
        .x_label_formatter(&|x| format!("{x:.0}"))
        .light_line_style(WHITE.mix(0.0))
        .y_label_formatter(&|y| tick_label(*y))
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .draw()
        .map_err(plot_error)?;
    // Six curves at most, in the palette's first six colours (black is left out).
    for (k, c) in curves.iter().take(COLORS.len() - 1).enumerate() {
        let color = COLORS[k];
        let label = format!(
            "θi {:.0}°, φi {:.0}°",
            c.theta_i.to_degrees(),
            c.phi_i.to_degrees()
        );
        chart
            .draw_series(c.points.iter().map(|&(t, i)| {
                Circle::new((t.to_degrees(), measured[i].max(lo)), 4, color.filled())
            }))
            .map_err(plot_error)?
            .label(label)
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, color.filled()));
        // The fit along the plane, finely.
        let (t0, t1) = (c.points[0].0, c.points[c.points.len() - 1].0);
        let dirs: Vec<(f64, f64, f64, f64)> = (0..=120)
            .map(|j| {
                let t = t0 + (t1 - t0) * j as f64 / 120.0;
                let phi_r = if t >= 0.0 {
                    c.phi_i + std::f64::consts::PI
                } else {
                    c.phi_i
                };
                (c.theta_i, c.phi_i, t.abs(), phi_r)
            })
            .collect();
        let values = result.predict_many(&dirs);
        chart
            .draw_series(LineSeries::new(
                dirs.iter().zip(&values).map(|(d, v)| {
                    let t = if d.3 == c.phi_i { -d.2 } else { d.2 };
                    (t.to_degrees(), mean(v, ch).max(lo))
                }),
                color.stroke_width(2),
            ))
            .map_err(plot_error)?;
    }
    if curves.is_empty() {
        left.draw_text(
            "no in-plane measurements in this dataset",
            &(FONT, 18).into_font().color(&BLACK),
            (120, 300),
        )
        .map_err(plot_error)?;
    } else {
        chart
            .configure_series_labels()
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(plot_error)?;
    }

    // Right: fitted against measured.
    let mut chart = ChartBuilder::on(&right)
        .caption(
            format!(
                "RMS log error {:.3}, relative RMS {:.3}",
                result.rms_log, result.relative_rms
            ),
            (FONT, 20),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((lo..hi).log_scale(), (lo..hi).log_scale())
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc("measured, 1/sr")
        .y_desc("fitted, 1/sr")
        .light_line_style(WHITE.mix(0.0))
        .x_label_formatter(&|y| tick_label(*y))
        .y_label_formatter(&|y| tick_label(*y))
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .draw()
        .map_err(plot_error)?;
    chart
        .draw_series(LineSeries::new(
            [(lo, lo), (hi, hi)],
            BLACK.mix(0.5).stroke_width(1),
        ))
        .map_err(plot_error)?;
    chart
        .draw_series(
            measured.iter().zip(&fitted).map(|(&m, &f)| {
                Circle::new((m.max(lo), f.max(lo)), 3, COLORS[0].mix(0.7).filled())
            }),
        )
        .map_err(plot_error)?;
    if measured.is_empty() {
        bail!("nothing to plot");
    }
    Ok(())
}
