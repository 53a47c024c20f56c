//! The server on a real socket ([`woven_serve::server::serve`]): a fit whose client goes away
//! stops, stopping the server stops its fits, and slow clients are cut off by the read timeout.
//! `woven-cli`'s `tests/integration/serve.rs` sends SIGINT to the `woven serve` process itself.

use serde_json::{json, Value};
use std::net::SocketAddr;
use std::time::{Duration, Instant};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::oneshot;
use woven::material::Material;
use woven::Vec3;

/// A server on a free port with `read_timeout`; sending on the channel stops it, and the task
/// ends when it has stopped, with the jobs still running then.
async fn start(
    read_timeout: Duration,
) -> (
    SocketAddr,
    oneshot::Sender<()>,
    tokio::task::JoinHandle<usize>,
) {
    let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let options = woven_serve::Options {
        read_timeout,
        // The whole second the test allows for stopping: on a loaded machine the fit's step in
        // flight can take most of it.
        shutdown_grace: Duration::from_millis(900),
        ..woven_serve::Options::default()
    };
    let (stop, stopped) = oneshot::channel::<()>();
    let task = tokio::spawn(async move {
        woven_serve::server::serve(listener, &options, async {
            let _ = stopped.await;
        })
        .await
        .unwrap()
    });
    (addr, stop, task)
}

/// A request's bytes.
fn request(method: &str, path: &str, body: &str) -> Vec<u8> {
    format!(
        "{method} {path} HTTP/1.1\r\nHost: test\r\nContent-Type: application/json\r\n\
         Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .into_bytes()
}

/// `GET /api/status`'s running jobs.
async fn running_jobs(addr: SocketAddr) -> u64 {
    let mut s = TcpStream::connect(addr).await.unwrap();
    s.write_all(&request("GET", "/api/status", ""))
        .await
        .unwrap();
    let mut answer = String::new();
    s.read_to_string(&mut answer).await.unwrap();
    let body = answer.split("\r\n\r\n").nth(1).expect("a body");
    let v: Value = serde_json::from_str(body).unwrap();
    v["jobs"].as_u64().unwrap()
}

/// A fit of the twisted `belt-cloth` to 200 measurements of itself: a minute and more of CPU
/// (1–2 ms an evaluation), started on `addr`; returns the connection once the fit has streamed
/// its first progress line.
async fn start_slow_fit(addr: SocketAddr) -> TcpStream {
    let belt = Material::preset("belt-cloth").unwrap();
    let model = belt.build(550.0).unwrap();
    let mut csv = String::from("theta_i,phi_i,theta_r,phi_r,value\n");
    for k in 0..200 {
        let (ti, pi) = (0.1 + 0.006 * k as f64, 0.031 * k as f64);
        let (tr, pr) = (0.2 + 0.005 * k as f64, 2.5 + 0.017 * k as f64);
        let f = model.eval(Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr));
        csv.push_str(&format!("{ti},{pi},{tr},{pr},{f}\n"));
    }
    let body = json!({"material": woven_serve::material::to_json(&belt), "csv": csv});
    let mut s = TcpStream::connect(addr).await.unwrap();
    s.write_all(&request("POST", "/api/fit", &body.to_string()))
        .await
        .unwrap();
    let mut seen = Vec::new();
    let mut buf = [0u8; 4096];
    let wait = Instant::now();
    while !String::from_utf8_lossy(&seen).contains("\"progress\"") {
        let n = tokio::time::timeout(Duration::from_secs(60), s.read(&mut buf))
            .await
            .expect("the fit's first progress within a minute")
            .unwrap();
        assert!(n > 0, "closed: {}", String::from_utf8_lossy(&seen));
        seen.extend_from_slice(&buf[..n]);
    }
    let text = String::from_utf8_lossy(&seen);
    assert!(text.starts_with("HTTP/1.1 200"), "{text}");
    eprintln!("first progress after {:?}", wait.elapsed());
    s
}

/// Polls `/api/status` until no job runs; the time that took.
async fn until_idle(addr: SocketAddr, limit: Duration) -> Duration {
    let t = Instant::now();
    while running_jobs(addr).await > 0 {
        assert!(t.elapsed() < limit, "a job still runs after {limit:?}");
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    t.elapsed()
}

/// A fit whose client goes away stops: the server is idle within a second of the drop (the fit
/// alone would run for a minute).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_fit_whose_client_has_gone_stops() {
    let (addr, stop, task) = start(Duration::from_secs(10)).await;
    let fit = start_slow_fit(addr).await;
    assert_eq!(running_jobs(addr).await, 1);
    drop(fit);
    let idle = until_idle(addr, Duration::from_secs(1)).await;
    eprintln!("idle {idle:?} after the client went");
    stop.send(()).unwrap();
    assert_eq!(task.await.unwrap(), 0);
}

/// Stopping the server (what Ctrl-C and SIGTERM do) while a fit runs returns within a second,
/// the fit stopped.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn stopping_the_server_stops_its_fits() {
    let (addr, stop, task) = start(Duration::from_secs(10)).await;
    let mut fit = start_slow_fit(addr).await;
    let t = Instant::now();
    stop.send(()).unwrap();
    let still_running = tokio::time::timeout(Duration::from_secs(1), task)
        .await
        .expect("the server stopped within a second")
        .unwrap();
    eprintln!("stopped in {:?}", t.elapsed());
    assert_eq!(still_running, 0, "the fit did not stop");
    // The fit's connection was closed without its result.
    let mut rest = String::new();
    let _ = tokio::time::timeout(Duration::from_secs(1), fit.read_to_string(&mut rest))
        .await
        .expect("the fit's connection closed");
    assert!(!rest.contains("\"kind\":\"fit\""), "{rest}");
}

/// Reads until the peer closes or `limit` passes; the bytes and the time to close (`None` if
/// it did not close).
async fn read_until_closed(s: &mut TcpStream, limit: Duration) -> (String, Option<Duration>) {
    let t = Instant::now();
    let mut got = Vec::new();
    let mut buf = [0u8; 1024];
    loop {
        match tokio::time::timeout(limit.saturating_sub(t.elapsed()), s.read(&mut buf)).await {
            Err(_) => return (String::from_utf8_lossy(&got).into(), None),
            Ok(Ok(0)) | Ok(Err(_)) => {
                return (String::from_utf8_lossy(&got).into(), Some(t.elapsed()));
            }
            Ok(Ok(n)) => got.extend_from_slice(&buf[..n]),
        }
    }
}

/// Half a header, then nothing: the connection is closed once the read timeout (200 ms here)
/// has passed; an idle keep-alive connection too; a prompt client is answered as before.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_slow_header_is_cut_off_by_the_read_timeout() {
    let timeout = Duration::from_millis(200);
    let (addr, stop, task) = start(timeout).await;
    let mut slow = TcpStream::connect(addr).await.unwrap();
    slow.write_all(b"GET /api/status HTTP/1.1\r\nHost: te")
        .await
        .unwrap();
    let (got, closed) = read_until_closed(&mut slow, Duration::from_secs(3)).await;
    let closed = closed.expect("the slow client's connection closed");
    assert!(closed >= Duration::from_millis(150), "{closed:?}");
    assert!(!got.contains("200 OK"), "{got}");
    eprintln!("half a header: closed after {closed:?}");
    // A connection that sends nothing is closed alike.
    let mut idle = TcpStream::connect(addr).await.unwrap();
    let (_, closed) = read_until_closed(&mut idle, Duration::from_secs(3)).await;
    assert!(closed.is_some(), "an idle connection stays open");
    assert_eq!(running_jobs(addr).await, 0);
    stop.send(()).unwrap();
    assert_eq!(task.await.unwrap(), 0);
}

/// A body that does not arrive within the read timeout of its headers is answered 408 (a JSON
/// error naming the timeout) and its connection closed, however it trickles in.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_slow_body_is_answered_408() {
    let timeout = Duration::from_millis(200);
    let (addr, stop, task) = start(timeout).await;
    let mut slow = TcpStream::connect(addr).await.unwrap();
    slow.write_all(
        b"POST /api/material HTTP/1.1\r\nHost: test\r\nContent-Type: application/json\r\n\
          Content-Length: 100\r\n\r\n{\"mat",
    )
    .await
    .unwrap();
    let t = Instant::now();
    // A byte every 50 ms: each read is prompt, the whole body is not.
    let mut answer = String::new();
    let mut buf = [0u8; 1024];
    for _ in 0..40 {
        if slow.write_all(b" ").await.is_err() {
            break;
        }
        match tokio::time::timeout(Duration::from_millis(50), slow.read(&mut buf)).await {
            Ok(Ok(0)) | Ok(Err(_)) => break,
            Ok(Ok(n)) => answer.push_str(&String::from_utf8_lossy(&buf[..n])),
            Err(_) => {}
        }
    }
    let (rest, closed) = read_until_closed(&mut slow, Duration::from_secs(2)).await;
    answer.push_str(&rest);
    assert!(closed.is_some(), "the connection stays open: {answer}");
    let elapsed = t.elapsed();
    assert!(answer.starts_with("HTTP/1.1 408"), "{answer}");
    assert!(answer.contains("read timeout (200 ms)"), "{answer}");
    assert!(elapsed < Duration::from_secs(2), "{elapsed:?}");
    eprintln!("trickled body: 408 and closed after {elapsed:?}");
    stop.send(()).unwrap();
    assert_eq!(task.await.unwrap(), 0);
}
