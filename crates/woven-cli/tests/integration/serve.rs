//! `woven serve` as a process: SIGINT (Ctrl-C) and SIGTERM stop it within a second, a fit
//! running or not. (woven-serve's `tests/integration/server.rs` tests the server in-process.)
#![cfg(unix)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use woven::material::Material;
use woven::Vec3;

/// `woven serve --port 0` and the address it listens on.
fn serve() -> (Child, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_woven"))
        .args(["serve", "--port", "0"])
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let url = line
        .split_whitespace()
        .find(|w| w.starts_with("http://"))
        .unwrap_or_else(|| panic!("no address in {line:?}"));
    let addr = url.trim_start_matches("http://").trim_end_matches('/');
    (child, addr.to_owned())
}

/// Sends `signal` (a `kill` name) to `child`; the time it took to exit, or `None` past `limit`
/// (then it is killed).
fn signal_and_wait(child: &mut Child, signal: &str, limit: Duration) -> Option<Duration> {
    let sent = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let t = Instant::now();
    while t.elapsed() < limit {
        if child.try_wait().unwrap().is_some() {
            return Some(t.elapsed());
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    None
}

/// Starts a fit of the twisted `belt-cloth` to 200 measurements of itself (a minute and more of
/// CPU) and waits for its first progress line; returns the connection.
fn start_slow_fit(addr: &str) -> TcpStream {
    let belt = Material::preset("belt-cloth").unwrap();
    let model = belt.build(550.0).unwrap();
    let mut csv = String::from("theta_i,phi_i,theta_r,phi_r,value\n");
    for k in 0..200 {
        let (ti, pi) = (0.1 + 0.006 * k as f64, 0.031 * k as f64);
        let (tr, pr) = (0.2 + 0.005 * k as f64, 2.5 + 0.017 * k as f64);
        let f = model.eval(Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr));
        csv.push_str(&format!("{ti},{pi},{tr},{pr},{f}\n"));
    }
    let material = woven_serve::material::to_json(&belt);
    let body = serde_json::json!({"material": material, "csv": csv}).to_string();
    let mut s = TcpStream::connect(addr).unwrap();
    write!(
        s,
        "POST /api/fit HTTP/1.1\r\nHost: test\r\nContent-Type: application/json\r\n\
         Content-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    let mut seen = Vec::new();
    let mut buf = [0u8; 4096];
    while !String::from_utf8_lossy(&seen).contains("\"progress\"") {
        let n = s
            .read(&mut buf)
            .expect("the fit's first progress within a minute");
        assert!(n > 0, "closed: {}", String::from_utf8_lossy(&seen));
        seen.extend_from_slice(&buf[..n]);
    }
    s
}

#[test]
fn sigint_stops_the_server_within_a_second_while_a_fit_runs() {
    let (mut child, addr) = serve();
    let _fit = start_slow_fit(&addr);
    let took = signal_and_wait(&mut child, "INT", Duration::from_secs(1));
    let took = took.expect("woven serve still running 1 s after SIGINT with a fit running");
    eprintln!("SIGINT during a fit: exited after {took:?}");
}

#[test]
fn sigterm_stops_an_idle_server_within_a_second() {
    let (mut child, _) = serve();
    let took = signal_and_wait(&mut child, "TERM", Duration::from_secs(1));
    let took = took.expect("woven serve still running 1 s after SIGTERM");
    eprintln!("SIGTERM: exited after {took:?}");
}
