//! # woven-serve — the woven explorer in the browser
//!
//! `woven serve` starts this server: a page (embedded in the binary, vanilla JavaScript and
//! canvas, no network needed) where a user edits a material and watches its BRDF change — over
//! the view hemisphere, in the plane of incidence, on the paper's goniometer, on a rendered
//! swatch — and lays measured data over it. `docs/serve.md` describes the page and the API.
//!
//! ```no_run
//! // Serve on 127.0.0.1:8321 until Ctrl-C, printing the address to open.
//! let options = woven_serve::Options::default();
//! woven_serve::run(&options, |url| println!("open {url}"))?;
//! # Ok::<(), std::io::Error>(())
//! ```
//!
//! The router alone ([`router`]) is what most tests call, without a socket; [`server::serve`]
//! serves it on a listener until a signal, as [`run`] does.
//!
//! ## Modules
//! - [`api`]: routes, request checks, handlers; [`error`]: every error as JSON.
//! - [`views`]: hemisphere map, in-plane and goniometer curves; [`preview`]: the render.
//! - [`data`]: measured CSVs and the model's error on them; [`material`]: the page's materials;
//!   [`models`]: built models kept for the next request.
//! - [`job`]: computations off the event loop, streamed, cancelled when stale; [`assets`]: the
//!   embedded page.
//! - [`server`]: connections, read timeouts, stopping.

pub mod api;
pub mod assets;
pub mod data;
pub mod error;
pub mod job;
pub mod material;
pub mod models;
pub mod preview;
pub mod server;
pub mod views;

pub use api::router;
pub use error::{ApiError, ApiResult};

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::time::Duration;

/// The default port.
pub const DEFAULT_PORT: u16 = 8321;

/// The default read timeout ([`Options::read_timeout`]): room for the largest body
/// ([`api::MAX_BODY_BYTES`]) at 70 kB/s.
pub const DEFAULT_READ_TIMEOUT: Duration = Duration::from_secs(30);

/// The default [`Options::shutdown_grace`]: with the rest of stopping, well within a second.
pub const DEFAULT_SHUTDOWN_GRACE: Duration = Duration::from_millis(500);

/// Where to listen.
#[derive(Clone, Debug)]
pub struct Options {
    /// The address (127.0.0.1 unless asked: the API has no authentication).
    pub host: IpAddr,
    /// The port; 0 picks a free one.
    pub port: u16,
    /// How long a client may take to send a request's headers (from the connection's opening or
    /// the previous answer: an idle connection is closed after it) and, again, its body (from
    /// its headers); [`server`] describes both.
    pub read_timeout: Duration,
    /// How long stopping waits for the running jobs, once their connections are closed, to stop
    /// (a fit stops within a pass of the model over its measurements); then it returns anyway.
    pub shutdown_grace: Duration,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            host: IpAddr::V4(Ipv4Addr::LOCALHOST),
            port: DEFAULT_PORT,
            read_timeout: DEFAULT_READ_TIMEOUT,
            shutdown_grace: DEFAULT_SHUTDOWN_GRACE,
        }
    }
}

/// Serves until Ctrl-C or SIGTERM; `ready` hears the page's URL once the socket listens.
///
/// On the signal every connection is closed, which cancels the jobs (a fit included), and the
/// function returns within a second: after at most [`Options::shutdown_grace`] for the jobs to
/// stop, and without waiting for work that cannot be stopped (a model build on the blocking
/// pool).
///
/// # Errors
/// The runtime cannot start, or the address cannot be bound (in use, say).
pub fn run(options: &Options, ready: impl FnOnce(&str)) -> std::io::Result<()> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        // The event loop only moves bytes; the work runs on the blocking pool and rayon.
        .worker_threads(2)
        .enable_all()
        .build()?;
    let served = runtime.block_on(async {
        let listener =
            tokio::net::TcpListener::bind(SocketAddr::new(options.host, options.port)).await?;
        let addr = listener.local_addr()?;
        let host = match addr.ip() {
            IpAddr::V6(ip) => format!("[{ip}]"),
            ip => ip.to_string(),
        };
        ready(&format!("http://{host}:{}/", addr.port()));
        server::serve(listener, options, shutdown()).await
    });
    let served = served.map(|_still_running| ());
    // Blocking work still running (a model build) is left to the process's exit.
    runtime.shutdown_timeout(Duration::from_millis(50));
    served
}

/// Resolves on Ctrl-C or (on Unix) SIGTERM.
async fn shutdown() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let term = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! {
        _ = ctrl_c => {},
        _ = term => {},
    }
}
