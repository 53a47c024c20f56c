//! The socket side: accepting connections, the read timeouts, and stopping.
//!
//! Each connection is served by hyper's HTTP/1 server on its own task:
//! - a request's headers must arrive within the read timeout ([`Options::read_timeout`]) of the
//!   connection opening or of the previous answer (hyper's `header_read_timeout`; an idle
//!   keep-alive connection is closed after it too), else the connection is closed;
//! - its body within the read timeout of its headers ([`DeadlineBody`]), else the answer is a
//!   408 and the connection is closed.
//!
//! A client that goes away while its job streams is noticed by hyper (it reads the socket while
//! it writes the answer: the end of the stream ends the connection), which drops the answer; the
//! job sees its channel closed and stops ([`crate::job`]; a fit through
//! [`woven_fit::fit()`]). Stopping the server closes every connection the same way and
//! waits up to [`Options::shutdown_grace`] for the jobs to stop.

use crate::api::{self, AppState};
use crate::Options;
use axum::body::{Body, Bytes};
use http_body::{Frame, SizeHint};
use hyper::body::Incoming;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use std::future::Future;
use std::pin::{pin, Pin};
use std::sync::Arc;
use std::task::{Context, Poll};
use std::time::Duration;
use tokio::net::{TcpListener, TcpStream};
use tokio::task::JoinSet;
use tokio::time::{Instant, Sleep};

/// Serves the API on `listener` until `signal` resolves, then closes every connection (which
/// cancels their jobs) and waits up to `options.shutdown_grace` for the jobs to stop; returns how
/// many were still running when it stopped waiting (0 when all stopped).
///
/// # Errors
/// None yet: a failed `accept` (a connection reset before it was taken, too many open files) is
/// waited out, not returned; the result leaves room for listeners that can fail.
pub async fn serve(
    listener: TcpListener,
    options: &Options,
    signal: impl Future<Output = ()>,
) -> std::io::Result<usize> {
    let state = Arc::new(AppState::default());
    let app = api::router_with(state.clone());
    let read_timeout = options.read_timeout;
    let mut connections = JoinSet::new();
    let mut signal = pin!(signal);
    loop {
        tokio::select! {
            () = &mut signal => break,
            accepted = listener.accept() => match accepted {
                Ok((stream, _)) => {
                    connections.spawn(connection(stream, app.clone(), read_timeout));
                }
                // Out of file descriptors, say: wait for some to be freed rather than spin.
                Err(_) => tokio::time::sleep(Duration::from_millis(50)).await,
            },
            // Finished connections are reaped as they end.
            Some(_) = connections.join_next(), if !connections.is_empty() => {}
        }
    }
    drop(listener);
    // Aborting a connection drops its answer: the job streaming it sees its client gone.
    connections.shutdown().await;
    let deadline = Instant::now() + options.shutdown_grace;
    while state.running_jobs() > 0 && Instant::now() < deadline {
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    Ok(state.running_jobs())
}

/// Serves one connection with the header and body read timeouts.
async fn connection(stream: TcpStream, app: axum::Router, read_timeout: Duration) {
    let app = TowerToHyperService::new(app);
    let service = hyper::service::service_fn(move |request: hyper::Request<Incoming>| {
        let request = request.map(|body| DeadlineBody::new(Body::new(body), read_timeout));
        hyper::service::Service::call(&app, request)
    });
    let mut builder = hyper::server::conn::http1::Builder::new();
    builder
        .timer(TokioTimer::new())
        .header_read_timeout(read_timeout);
    // A connection's errors (a reset, a timeout, a malformed request) end that connection only.
    let _ = builder
        .serve_connection(TokioIo::new(stream), service)
        .await;
}

/// The error a request body gives when it has not arrived by its deadline
/// ([`crate::ApiError::Timeout`], 408, once a handler reads it).
#[derive(Debug, thiserror::Error)]
#[error("the request body did not arrive within the read timeout of {} ms", .limit.as_millis())]
pub struct BodyTimeout {
    /// The read timeout.
    pub limit: Duration,
}

/// A request body that fails with [`BodyTimeout`] once `limit` has passed since it was made
/// (when the request's headers were read), however its bytes trickle in.
pub struct DeadlineBody {
    inner: Body,
    deadline: Pin<Box<Sleep>>,
    limit: Duration,
}

impl DeadlineBody {
    /// `inner`, due within `limit` from now.
    pub fn new(inner: Body, limit: Duration) -> Self {
        DeadlineBody {
            inner,
            deadline: Box::pin(tokio::time::sleep(limit)),
            limit,
        }
    }
}

impl http_body::Body for DeadlineBody {
    type Data = Bytes;
    type Error = axum::BoxError;

    fn poll_frame(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
    ) -> Poll<Option<Result<Frame<Bytes>, Self::Error>>> {
        if self.deadline.as_mut().poll(cx).is_ready() {
            return Poll::Ready(Some(Err(Box::new(BodyTimeout { limit: self.limit }))));
        }
        Pin::new(&mut self.inner)
            .poll_frame(cx)
            .map(|frame| frame.map(|f| f.map_err(Into::into)))
    }

    fn is_end_stream(&self) -> bool {
        self.inner.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.inner.size_hint()
    }
}
