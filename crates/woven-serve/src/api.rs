//! The HTTP API: routes, request types and their checks, handlers.
//!
//! Every request body is JSON (a WIF upload is its text) of at most [`MAX_BODY_BYTES`]; every
//! error is a JSON object ([`crate::error::ErrorBody`]). Computations stream newline-delimited
//! JSON ([`crate::job`]).

use crate::assets;
use crate::data;
use crate::error::{ApiError, ApiResult};
use crate::job::{self, Channels};
use crate::material::{self, PatternView};
use crate::models::ModelCache;
use crate::preview::{self, Preview, Shape};
use crate::views::{self, Which};
use axum::body::Bytes;
use axum::extract::rejection::BytesRejection;
use axum::extract::{DefaultBodyLimit, State};
use axum::http::{Method, Uri};
use axum::response::Response;
use axum::routing::{get, post};
use axum::{Json, Router};
use rayon::prelude::*;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::sync::Arc;
use tokio::sync::Semaphore;
use woven::keys::KeyValue;
use woven::material::Material;
use woven::weave::{Pattern, PatternSpec};
use woven::Model;

/// The largest request body, bytes: room for a CSV of [`data::MAX_ROWS`] rows or a WIF draft.
pub const MAX_BODY_BYTES: usize = 2 << 20;
/// Computations that may run at once; more wait for a slot (the page cancels stale ones, so
/// waiting is short).
pub const MAX_JOBS: usize = 4;
/// The wavelength the explorer evaluates at unless a request says otherwise, nm (the CLI's and
/// the renderer's default).
pub const DEFAULT_WAVELENGTH_NM: f64 = 550.0;
/// The most polar angle of the light, degrees: at 90° no light arrives.
pub const THETA_I_MAX_DEG: f64 = 89.0;
/// The longest channel name.
const MAX_CHANNEL_CHARS: usize = 64;

/// The server's shared state.
pub struct AppState {
    jobs: Arc<Semaphore>,
    channels: Channels,
    models: Arc<ModelCache>,
}

impl AppState {
    /// The jobs running now (holding a worker slot; those waiting for one are not counted).
    pub fn running_jobs(&self) -> usize {
        MAX_JOBS.saturating_sub(self.jobs.available_permits())
    }
}

impl Default for AppState {
    fn default() -> Self {
        AppState {
            jobs: Arc::new(Semaphore::new(MAX_JOBS)),
            channels: Channels::default(),
            models: Arc::default(),
        }
    }
}

type Shared = State<Arc<AppState>>;

/// The router: the page's assets and the API; anything else is a JSON 404.
pub fn router() -> Router {
    router_with(Arc::new(AppState::default()))
}

/// [`router`] on the shared state `app` (which [`crate::server::serve`] watches to stop).
pub fn router_with(app: Arc<AppState>) -> Router {
    Router::new()
        .route("/", get(assets::index))
        .route("/index.html", get(assets::index))
        .route("/app.js", get(assets::script))
        .route("/style.css", get(assets::style))
        .route("/favicon.svg", get(assets::icon))
        .route("/api/presets", get(presets))
        .route("/api/material", post(material_info))
        .route("/api/pattern", post(pattern))
        .route("/api/wif", post(wif))
        .route("/api/views", post(views_stream))
        .route("/api/preview", post(preview_stream))
        .route("/api/compare", post(compare_stream))
        .route("/api/datasets", get(datasets))
        .route("/api/fit", post(fit_stream))
        .route("/api/status", get(status))
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed)
        .layer(DefaultBodyLimit::max(MAX_BODY_BYTES))
        .with_state(app)
}

/// `GET /api/status`: the jobs running now and the most that run at once.
async fn status(State(app): Shared) -> Json<Value> {
    Json(json!({"jobs": app.running_jobs(), "max_jobs": MAX_JOBS}))
}

async fn not_found(uri: Uri) -> ApiError {
    ApiError::NotFound(uri.path().to_owned())
}

async fn method_not_allowed(method: Method, uri: Uri) -> ApiError {
    ApiError::MethodNotAllowed {
        method: method.to_string(),
        path: uri.path().to_owned(),
    }
}

/// The body's bytes, or the JSON error for one too large, too slow or unreadable.
fn body_bytes(body: Result<Bytes, BytesRejection>) -> ApiResult<Bytes> {
    body.map_err(|r| {
        let mut cause: Option<&(dyn std::error::Error + 'static)> = Some(&r);
        while let Some(e) = cause {
            if let Some(t) = e.downcast_ref::<crate::server::BodyTimeout>() {
                return ApiError::Timeout {
                    limit_ms: t.limit.as_millis(),
                };
            }
            cause = e.source();
        }
        if r.status() == axum::http::StatusCode::PAYLOAD_TOO_LARGE {
            ApiError::TooLarge {
                limit: MAX_BODY_BYTES,
            }
        } else {
            ApiError::bad_request(format!("unreadable request body: {}", r.body_text()))
        }
    })
}

/// Parses a JSON request body.
fn parse<T: DeserializeOwned>(body: Result<Bytes, BytesRejection>) -> ApiResult<T> {
    let bytes = body_bytes(body)?;
    serde_json::from_slice(&bytes)
        .map_err(|e| ApiError::bad_request(format!("malformed JSON request: {e}")))
}

/// Checks `lo ≤ x ≤ hi`.
fn check_range(field: &str, x: f64, lo: f64, hi: f64) -> ApiResult<f64> {
    if x.is_finite() && (lo..=hi).contains(&x) {
        Ok(x)
    } else {
        Err(ApiError::invalid(
            field,
            x,
            format!("a number in [{lo}, {hi}]"),
        ))
    }
}

/// Checks a channel name.
fn check_channel(channel: &Option<String>) -> ApiResult<Option<&str>> {
    match channel {
        Some(c) if c.is_empty() || c.chars().count() > MAX_CHANNEL_CHARS => Err(ApiError::invalid(
            "channel",
            format!("{c:?}"),
            format!("a name of 1 to {MAX_CHANNEL_CHARS} characters"),
        )),
        c => Ok(c.as_deref()),
    }
}

/// Builds `material` at `wavelength_nm` on the blocking pool (or finds it built).
async fn build(app: &AppState, material: Material, wavelength_nm: f64) -> ApiResult<Arc<Model>> {
    let models = app.models.clone();
    tokio::task::spawn_blocking(move || models.build(&material, wavelength_nm))
        .await
        .map_err(|e| ApiError::Internal(format!("model build: {e}")))?
        .map_err(ApiError::from)
}

/// `GET /api/presets`: the built-in materials (as the JSON the other endpoints take) and the
/// named weave patterns.
async fn presets() -> ApiResult<Json<Value>> {
    let mut list = Vec::new();
    for name in Material::preset_names() {
        let m = Material::preset(name)?;
        list.push(json!({"name": name, "material": material::to_json(&m)}));
    }
    Ok(Json(json!({
        "presets": list,
        "patterns": ["plain", "twill-2/1", "twill-2/2", "twill-3/1", "satin-5", "sateen-5", "satin-8", "sateen-8"],
        "wavelength_nm": DEFAULT_WAVELENGTH_NM,
        "limits": {
            "max_body_bytes": MAX_BODY_BYTES,
            "max_csv_rows": data::MAX_ROWS,
            "theta_i_max_deg": THETA_I_MAX_DEG,
        },
    })))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FitRequest {
    material: Value,
    #[serde(default)]
    csv: Option<String>,
    #[serde(default)]
    dataset: Option<String>,
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    seed: Option<u32>,
    #[serde(default)]
    channel: Option<String>,
}

/// One line of a fit's stream.
#[derive(Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
enum FitMessage {
    Progress {
        done: usize,
        total: usize,
    },
    Fit {
        material: Value,
        rms_log: f64,
        relative_rms: f64,
        warnings: Vec<String>,
        report: String,
    },
    Failed {
        error: String,
    },
}

/// `POST /api/fit`: the cloth model fitted to measured data (`woven fit --model cloth`, the
/// fitter's defaults), starting from the page's material, one channel (colour data as the mean
/// of its channels); streams the fitter's progress, then the fitted material. A fit takes tens of
/// seconds for a twisted or isotropic yarn; it stops within a step of the fitter once its client
/// has gone or a newer request on its channel has started (the progress given to
/// [`woven_fit::fit()`] answers whether to stop).
async fn fit_stream(
    State(app): Shared,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<Response> {
    let req: FitRequest = parse(body)?;
    let m = material::from_json(&req.material)?;
    let dataset = data::mono(data::source(
        req.csv.as_deref(),
        req.name.as_deref(),
        req.dataset.as_deref(),
    )?);
    let set = woven_fit::ParamSet::new(woven_fit::ModelKind::Cloth, Some(&m), 1, dataset.relative)
        .map_err(|e| ApiError::unprocessable(e.to_string()))?;
    let options = woven_fit::FitOptions {
        seed: req.seed.unwrap_or(1),
        ..woven_fit::FitOptions::default()
    };
    let channel = check_channel(&req.channel)?;
    start_job(&app, channel, move |out| {
        let progress = woven::progress::Hooks {
            update: |done: usize, total: usize| {
                out.send(&FitMessage::Progress { done, total });
            },
            cancelled: || out.cancelled(),
        };
        let message = match woven_fit::fit(&dataset, &set, &options, &progress) {
            Ok(r) => match r.material() {
                Some(fitted) => FitMessage::Fit {
                    material: material::to_json(&fitted),
                    rms_log: r.rms_log,
                    relative_rms: r.relative_rms,
                    warnings: r.warnings.clone(),
                    report: r.to_markdown(),
                },
                None => FitMessage::Failed {
                    error: "the fit gave no material".into(),
                },
            },
            // The client has gone (or a newer fit on the channel superseded this one).
            Err(woven_fit::FitError::Cancelled) => return,
            Err(e) => FitMessage::Failed {
                error: e.to_string(),
            },
        };
        out.send(&message);
    })
    .await
}

/// Starts `work` as a streamed job on `channel` (superseding the channel's older jobs) once a
/// worker slot is free.
async fn start_job(
    app: &AppState,
    channel: Option<&str>,
    work: impl FnOnce(&job::Emitter) + Send + 'static,
) -> ApiResult<Response> {
    let generation = app.channels.begin(channel);
    let permit = app
        .jobs
        .clone()
        .acquire_owned()
        .await
        .map_err(|e| ApiError::Internal(e.to_string()))?;
    Ok(job::stream(generation, permit, work))
}

/// `GET /api/datasets`: the real measurements bundled in `data/` the page can lay over the
/// model.
async fn datasets() -> Json<Value> {
    let list: Vec<Value> = data::bundled()
        .iter()
        .map(|b| {
            json!({
                "name": b.name,
                "family": b.family.name(),
                "samples": b.samples,
                "relative": b.relative,
                "textile": b.textile,
            })
        })
        .collect();
    Json(json!({ "datasets": list }))
}

/// A request that carries a material.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialRequest {
    material: Value,
}

/// `POST /api/material`: validates a material and answers its TOML file, `γ` and pattern.
async fn material_info(body: Result<Bytes, BytesRejection>) -> ApiResult<Json<Value>> {
    let req: MaterialRequest = parse(body)?;
    let m = material::from_json(&req.material)?;
    let pattern = match &m.weave {
        Some(woven::material::Weave::Pattern { pattern, .. }) => Some(PatternView::of(pattern)),
        _ => None,
    };
    Ok(Json(json!({
        "toml": m.to_toml_string(),
        "weft_fraction": m.weft_fraction(),
        "pattern": pattern,
        "summary": woven::figures::words::Summary::of(&m).one_line(),
    })))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PatternRequest {
    pattern: KeyValue,
}

/// `POST /api/pattern`: a named weave or a 0/1 matrix (the library's reader of a pattern value,
/// `PatternSpec`), as its matrix and `γ`. A `{ wif = … }` would read a file on the server:
/// drafts come through `/api/wif`.
async fn pattern(body: Result<Bytes, BytesRejection>) -> ApiResult<Json<PatternView>> {
    let req: PatternRequest = parse(body)?;
    let spec = PatternSpec::from_value(&req.pattern, "weave.pattern")?;
    if let PatternSpec::Wif(_) = spec {
        return Err(ApiError::invalid(
            "weave.pattern",
            req.pattern.to_string(),
            "a pattern name or a 0/1 matrix (upload a WIF draft to /api/wif for its matrix)",
        ));
    }
    let p = spec.pattern(std::path::Path::to_path_buf)?;
    Ok(Json(PatternView::of(&p)))
}

/// `POST /api/wif`: a WIF draft (the body is its text), as its matrix and `γ`.
async fn wif(body: Result<Bytes, BytesRejection>) -> ApiResult<Json<PatternView>> {
    let bytes = body_bytes(body)?;
    let text = std::str::from_utf8(&bytes)
        .map_err(|e| ApiError::unprocessable(format!("<upload>.wif: not UTF-8 text: {e}")))?;
    let p = Pattern::from_wif_str(text, "<upload>.wif")?;
    Ok(Json(PatternView::of(&p)))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ViewsRequest {
    material: Value,
    theta_i_deg: f64,
    #[serde(default)]
    phi_i_deg: f64,
    #[serde(default)]
    views: Option<Vec<String>>,
    #[serde(default)]
    wavelength_nm: Option<f64>,
    #[serde(default)]
    channel: Option<String>,
}

/// `POST /api/views`: the hemisphere map, the in-plane curve and the goniometer curves,
/// streamed ([`views::Message`]).
async fn views_stream(
    State(app): Shared,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<Response> {
    let req: ViewsRequest = parse(body)?;
    let m = material::from_json(&req.material)?;
    let theta_i = check_range("theta_i_deg", req.theta_i_deg, 0.0, THETA_I_MAX_DEG)?.to_radians();
    let phi_i = check_range("phi_i_deg", req.phi_i_deg, -360.0, 360.0)?.to_radians();
    let mut which = Which {
        hemisphere: true,
        plane: true,
        gonio: true,
    };
    if let Some(list) = &req.views {
        which = Which {
            hemisphere: false,
            plane: false,
            gonio: false,
        };
        for v in list {
            match v.as_str() {
                "hemisphere" => which.hemisphere = true,
                "plane" => which.plane = true,
                "gonio" => which.gonio = true,
                other => {
                    return Err(ApiError::invalid(
                        "views",
                        format!("{other:?}"),
                        "a list of \"hemisphere\", \"plane\", \"gonio\"",
                    ))
                }
            }
        }
    }
    let channel = check_channel(&req.channel)?;
    let model = build(&app, m, req.wavelength_nm.unwrap_or(DEFAULT_WAVELENGTH_NM)).await?;
    start_job(&app, channel, move |out| {
        views::compute(&model, theta_i, phi_i, which, out)
    })
    .await
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PreviewRequest {
    material: Value,
    #[serde(default = "default_shape")]
    shape: Shape,
    #[serde(default = "default_size")]
    size: usize,
    #[serde(default = "default_passes")]
    passes: usize,
    #[serde(default)]
    weft_color: Option<[f64; 3]>,
    #[serde(default)]
    warp_color: Option<[f64; 3]>,
    #[serde(default = "default_cells")]
    cells: f64,
    #[serde(default)]
    channel: Option<String>,
}

fn default_shape() -> Shape {
    Shape::Sphere
}
fn default_size() -> usize {
    96
}
fn default_passes() -> usize {
    64
}
fn default_cells() -> f64 {
    24.0
}

/// `POST /api/preview`: a progressively refined render of the material ([`preview::Message`]).
async fn preview_stream(
    State(app): Shared,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<Response> {
    let req: PreviewRequest = parse(body)?;
    let material = material::from_json(&req.material)?;
    let (lo, hi) = preview::SIZE_RANGE;
    if !(lo..=hi).contains(&req.size) {
        return Err(ApiError::invalid(
            "size",
            req.size,
            format!("pixels in [{lo}, {hi}]"),
        ));
    }
    let (lo, hi) = preview::PASSES_RANGE;
    if !(lo..=hi).contains(&req.passes) {
        return Err(ApiError::invalid(
            "passes",
            req.passes,
            format!("an integer in [{lo}, {hi}]"),
        ));
    }
    let cells = check_range("cells", req.cells, 1.0, 200.0)?;
    let colors = [
        req.weft_color
            .map(|c| preview::check_color("weft_color", c))
            .transpose()?,
        req.warp_color
            .map(|c| preview::check_color("warp_color", c))
            .transpose()?,
    ];
    let channel = check_channel(&req.channel)?;
    let p = Preview {
        material,
        shape: req.shape,
        size: req.size,
        passes: req.passes,
        colors,
        cells,
    };
    start_job(&app, channel, move |out| preview::run(&p, out)).await
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CompareRequest {
    material: Value,
    /// The fitter's CSV, or …
    #[serde(default)]
    csv: Option<String>,
    /// … the name of a bundled dataset (`GET /api/datasets`).
    #[serde(default)]
    dataset: Option<String>,
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    wavelength_nm: Option<f64>,
    #[serde(default)]
    channel: Option<String>,
}

/// One line of a comparison stream.
#[derive(Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
enum CompareMessage {
    Progress {
        done: usize,
        total: usize,
    },
    Compare {
        samples: Vec<data::Sample>,
        model: Vec<f64>,
        error: data::ErrorSummary,
    },
}

/// `POST /api/compare`: measured data (the fitter's CSV) against the model at the same
/// directions, with the error.
async fn compare_stream(
    State(app): Shared,
    body: Result<Bytes, BytesRejection>,
) -> ApiResult<Response> {
    let req: CompareRequest = parse(body)?;
    let m = material::from_json(&req.material)?;
    let samples = data::samples_of(&data::source(
        req.csv.as_deref(),
        req.name.as_deref(),
        req.dataset.as_deref(),
    )?);
    let channel = check_channel(&req.channel)?;
    let model = build(&app, m, req.wavelength_nm.unwrap_or(DEFAULT_WAVELENGTH_NM)).await?;
    start_job(&app, channel, move |out| {
        let total = samples.len();
        let done = std::sync::atomic::AtomicUsize::new(0);
        let values: Option<Vec<f64>> = samples
            .par_iter()
            .with_max_len(16)
            .map(|s| {
                if out.cancelled() {
                    return None;
                }
                let f = model.eval(
                    woven::Vec3::from_spherical(s.theta_i, s.phi_i),
                    woven::Vec3::from_spherical(s.theta_r, s.phi_r),
                );
                let k = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                if k % 256 == 0 {
                    out.send(&CompareMessage::Progress { done: k, total });
                }
                Some(f)
            })
            .collect();
        let Some(values) = values else { return };
        let measured: Vec<f64> = samples.iter().map(|s| s.value).collect();
        let error = data::summarize(&measured, &values);
        out.send(&CompareMessage::Compare {
            samples,
            model: values,
            error,
        });
    })
    .await
}
