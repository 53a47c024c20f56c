//! `woven serve`: the explorer in the browser (the `woven-serve` crate).

use anyhow::{Context, Result};
use clap::Args;
use std::net::IpAddr;

/// Arguments of `woven serve`.
#[derive(Args, Debug)]
#[command(
    about = "Explore a material in the browser: live BRDF views, a rendered swatch, measured data",
    long_about = "Start the woven explorer: a local web page where you edit a material (every \
[fiber], [yarn] and [weave] parameter, presets, weave patterns, WIF drafts) and watch its BRDF \
change while a slider moves — over the view hemisphere for an incidence you pick by clicking, in \
the plane of incidence, on the paper's goniometer (Figs. 8–10: weft, 45°, warp) and on a \
progressively rendered swatch — and lay measured data (the fitter's CSV: theta_i, phi_i, \
theta_r, phi_r, value; radians, sr⁻¹) over the model with its error. Download the material \
TOML, the CSV behind every plot and PNGs of the plots.

The page is built into the binary and needs no network. The server listens on 127.0.0.1 only \
(--host changes that: the API has no authentication, so bind elsewhere only on a network you \
trust) and prints the address to open; Ctrl-C (or SIGTERM) stops it within a second, cancelling \
the computations under way. A computation whose page has gone (closed, reloaded, or asking \
anew) is stopped too. A client must send each request's headers, and then its body, within \
--read-timeout seconds, else its connection is closed. docs/serve.md describes the page and the \
HTTP API.",
    after_help = "Examples:
  woven serve                 # then open http://127.0.0.1:8321/
  woven serve --port 9000
  woven serve --port 0        # any free port (the address is printed)"
)]
pub struct ServeArgs {
    /// Port to listen on (0: any free port).
    #[arg(long, value_name = "N", default_value_t = woven_serve::DEFAULT_PORT)]
    pub port: u16,

    /// Address to listen on. The default, 127.0.0.1, reaches this machine only.
    #[arg(long, value_name = "ADDRESS", default_value = "127.0.0.1")]
    pub host: IpAddr,

    /// Seconds a client may take to send a request's headers, and then its body (an idle
    /// connection is closed after as long).
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = woven_serve::DEFAULT_READ_TIMEOUT.as_secs(),
        value_parser = clap::value_parser!(u64).range(1..=3600)
    )]
    pub read_timeout: u64,
}

/// Runs `woven serve`.
pub fn run(args: &ServeArgs) -> Result<()> {
    if !args.host.is_loopback() {
        eprintln!(
            "warning: listening on {}: anyone who can reach this address can use the explorer \
             (it has no authentication) and load this machine's cores",
            args.host
        );
    }
    let options = woven_serve::Options {
        host: args.host,
        port: args.port,
        read_timeout: std::time::Duration::from_secs(args.read_timeout),
        ..woven_serve::Options::default()
    };
    woven_serve::run(&options, |url| {
        println!("woven explorer: open {url} in a browser (Ctrl-C stops it)");
    })
    .with_context(|| format!("cannot serve on {}:{}", args.host, args.port))
}
