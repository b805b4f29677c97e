//! The studio's listener: HTTP/1.1 connections, at most [`crate::Config::max_connections`] open
//! at once, each closed when a request's header takes longer than
//! [`crate::Config::header_timeout`] to arrive, the wait for the next request on a kept-alive
//! connection included. A client that opens connections and sends nothing (or leaves them idle)
//! therefore holds a place for that long at most, and cannot lock the studio out.
//!
//! `axum::serve` sets no timer on its connections (so no timeout applies) and accepts without
//! bound; this is the same loop over hyper's HTTP/1 server with both. The studio needs no HTTP/2.

use std::future::Future;
use std::sync::Arc;
use std::time::Duration;

use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use tokio::net::TcpListener;
use tokio::sync::{Semaphore, mpsc, watch};

/// How connections are bounded.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Limits {
    /// Most connections open at once; the next waits in the listen queue until one closes.
    pub(crate) max_connections: usize,
    /// Longest a request's header may take, counted from the connection's opening or the end of
    /// its previous response.
    pub(crate) header_timeout: Duration,
}

/// Serves `routes` on `listener` within `limits` until `shutdown` completes, then lets the
/// connections finish the requests they are answering and returns.
pub(crate) async fn serve(
    listener: TcpListener,
    routes: axum::Router,
    limits: Limits,
    shutdown: impl Future<Output = ()> + Send + 'static,
) {
    let places = Arc::new(Semaphore::new(limits.max_connections.max(1)));
    let (stop, stopping) = watch::channel(false);
    // Every connection holds a sender; when the last one drops, all have ended.
    let (open, mut all_closed) = mpsc::channel::<()>(1);
    let mut shutdown = std::pin::pin!(shutdown);
    loop {
        let place = tokio::select! {
            place = Arc::clone(&places).acquire_owned() => place,
            () = &mut shutdown => break,
        };
        let Ok(place) = place else { break };
        let stream = tokio::select! {
            accepted = listener.accept() => accepted,
            () = &mut shutdown => break,
        };
        // Out of file descriptors, a connection reset before it was accepted: wait and go on.
        let Ok((stream, _)) = stream else {
            tokio::time::sleep(Duration::from_millis(50)).await;
            continue;
        };
        let (service, mut stopping, open) = (TowerToHyperService::new(routes.clone()), stopping.clone(), open.clone());
        tokio::spawn(async move {
            let mut builder = hyper::server::conn::http1::Builder::new();
            builder.timer(TokioTimer::new()).header_read_timeout(limits.header_timeout);
            let connection = builder.serve_connection(TokioIo::new(stream), service);
            let mut connection = std::pin::pin!(connection);
            // The guard `wait_for` returns is not `Send`: dropped here, before any other await.
            let stop = async move { stopping.wait_for(|stop| *stop).await.is_ok() };
            tokio::select! {
                _ = connection.as_mut() => {}
                true = stop => {
                    connection.as_mut().graceful_shutdown();
                    let _ = connection.await;
                }
            }
            drop((place, open));
        });
    }
    let _ = stop.send(true);
    drop(open);
    let _ = all_closed.recv().await;
}
