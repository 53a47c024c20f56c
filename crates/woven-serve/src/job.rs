//! Long computations: run on the blocking pool (never on the event loop), report as
//! newline-delimited JSON, and stop between chunks of work once their result is stale.
//!
//! A job is stale when its client has gone (the page aborted the request, or the server is
//! stopping and closed the connection: the response body is dropped and the channel closes) or
//! when a newer request on the same *channel* (a name the page chooses, one per view) has started
//! since: each request bumps its channel's generation and the job compares it with its own.

use axum::body::{Body, Bytes};
use axum::http::header;
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use std::collections::HashMap;
use std::convert::Infallible;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use tokio::sync::{mpsc, OwnedSemaphorePermit};
use tokio_stream::wrappers::ReceiverStream;
use tokio_stream::StreamExt;

/// The most channels remembered; beyond it the table starts afresh (old jobs then run to their
/// end or to their client's departure).
const MAX_CHANNELS: usize = 256;

/// Generations per channel name.
#[derive(Default)]
pub struct Channels {
    map: Mutex<HashMap<String, Arc<AtomicU64>>>,
}

impl Channels {
    /// Starts a new generation on `name` (superseding every job of an older one) and returns a
    /// token that tells whether it is still the newest.
    pub fn begin(&self, name: Option<&str>) -> Generation {
        let Some(name) = name else {
            return Generation {
                counter: None,
                mine: 0,
            };
        };
        let mut map = self.map.lock().unwrap_or_else(|e| e.into_inner());
        if map.len() >= MAX_CHANNELS && !map.contains_key(name) {
            map.clear();
        }
        let counter = map.entry(name.to_owned()).or_default().clone();
        let mine = counter.fetch_add(1, Ordering::SeqCst) + 1;
        Generation {
            counter: Some(counter),
            mine,
        }
    }
}

/// A job's generation on its channel.
pub struct Generation {
    counter: Option<Arc<AtomicU64>>,
    mine: u64,
}

impl Generation {
    /// Whether a newer request on the same channel has started.
    pub fn superseded(&self) -> bool {
        self.counter
            .as_ref()
            .is_some_and(|c| c.load(Ordering::SeqCst) != self.mine)
    }
}

/// What a running job writes to and asks whether to go on.
pub struct Emitter {
    tx: mpsc::Sender<Bytes>,
    generation: Generation,
}

impl Emitter {
    /// An emitter writing to `tx`, stale once `tx` closes or `generation` is superseded.
    pub fn new(tx: mpsc::Sender<Bytes>, generation: Generation) -> Self {
        Emitter { tx, generation }
    }

    /// Whether the job should stop: its client is gone or a newer request superseded it.
    pub fn cancelled(&self) -> bool {
        self.tx.is_closed() || self.generation.superseded()
    }

    /// Sends one JSON line; `false` when the job should stop.
    pub fn send(&self, message: &impl Serialize) -> bool {
        if self.cancelled() {
            return false;
        }
        let mut line = serde_json::to_vec(message).expect("messages serialize");
        line.push(b'\n');
        self.tx.blocking_send(Bytes::from(line)).is_ok()
    }
}

/// Answers with the lines `work` emits, running it on the blocking pool while holding `permit`
/// (the bound on simultaneous computations).
pub fn stream(
    generation: Generation,
    permit: OwnedSemaphorePermit,
    work: impl FnOnce(&Emitter) + Send + 'static,
) -> Response {
    // A few lines of slack: the worker rarely waits for the network.
    let (tx, rx) = mpsc::channel::<Bytes>(8);
    tokio::task::spawn_blocking(move || {
        let _permit = permit;
        let emitter = Emitter { tx, generation };
        work(&emitter);
    });
    let body = Body::from_stream(ReceiverStream::new(rx).map(Ok::<_, Infallible>));
    (
        [
            (header::CONTENT_TYPE, "application/x-ndjson"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        body,
    )
        .into_response()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_newer_request_on_a_channel_supersedes_the_older_only() {
        let c = Channels::default();
        let a = c.begin(Some("views"));
        let other = c.begin(Some("preview"));
        assert!(!a.superseded());
        let b = c.begin(Some("views"));
        assert!(a.superseded() && !b.superseded() && !other.superseded());
        assert!(!c.begin(None).superseded());
    }

    #[test]
    fn a_departed_client_cancels() {
        let (tx, rx) = mpsc::channel(4);
        let e = Emitter::new(tx, Channels::default().begin(None));
        assert!(!e.cancelled());
        assert!(e.send(&1));
        drop(rx);
        assert!(e.cancelled());
        assert!(!e.send(&2));
    }
}
