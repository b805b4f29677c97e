//! relief studio: a local web application that authors terrain in the browser over the relief
//! crates. `relief serve` runs it; this crate is the server, its JSON API and the page it ships.
//!
//! Every paper behind relief is an interactive authoring system (the contours paper's §5
//! sketching session, the island paper's strokes and hills, the feature-curve editor, the vector
//! terrain tools, the orometry paper's divide-tree edits). The studio gives them one editor in the
//! browser. **The scene is the document**: every gesture edits the same scene JSON that
//! `relief generate` runs, the server generates it with the facade ([`relief::pipeline`]) and
//! sends the heightfield back for the 2D map and the 3D view.
//!
//! The page (`web/`: plain HTML, CSS and JavaScript, no front-end build) is compiled into the
//! binary, so a user needs nothing but `cargo run` and a browser.
//!
//! # Safety of a server left running
//! - It listens where it is told ([`serve`]); `relief serve` binds 127.0.0.1, and the studio
//!   refuses requests whose `Host` is not a loopback name ([`Config::loopback_only`]), so a web
//!   page cannot reach it through DNS rebinding.
//! - Other sites' pages cannot use it: an API request whose `Origin` is not the studio's own (or
//!   whose `Sec-Fetch-Site` says another site made it) gets 403, a request body must be declared
//!   `application/json` (415 otherwise; uploads excepted), which a page elsewhere cannot send
//!   without a CORS preflight the studio never grants, and no page may frame it.
//! - A studio other machines can reach asks for a secret ([`Config::token`], [`new_token`]):
//!   `relief serve --host 0.0.0.0` prints an address carrying it.
//! - Request bodies are capped ([`Config::max_body_bytes`]); scenes run under the same
//!   [`relief::Budget`] as the CLI's; an upload is checked by its header alone; heavy work runs on
//!   blocking threads under one cap ([`Config::max_jobs`]) and stops when its client goes; the
//!   generations running at once share the budget's memory ([`Config::memory_wait`]); kept
//!   results are capped in bytes ([`Config::kept_bytes`]).
//! - Connections are bounded ([`Config::max_connections`]) and closed when a request's header
//!   (or the next request on a kept-alive connection) does not arrive within
//!   [`Config::header_timeout`], so idle connections cannot lock the studio out.
//! - Files live in the workspace folder only: names are plain (`[A-Za-z0-9_.-]`, no leading dot,
//!   no separators), and a scene's input paths must be relative and stay inside it.
//! - Writes are atomic (a temporary file in the same folder, then a rename), so two sessions
//!   saving at once leave one whole file, never a mix.
//! - A malformed request gets a 4xx with a JSON body `{"error": …, "path": …}`, `path` being the
//!   scene's JSON path of the problem when there is one.
//!
//! # Example
//! ```no_run
//! # async fn run() -> Result<(), relief_studio::StudioError> {
//! let config = relief_studio::Config::new("studio-workspace");
//! let listener = tokio::net::TcpListener::bind("127.0.0.1:8737").await?;
//! relief_studio::serve(listener, config).await
//! # }
//! ```
//! The router alone serves tests and embedders:
//! ```
//! let dir = tempfile::tempdir().unwrap();
//! let router = relief_studio::router(&relief_studio::Config::new(dir.path())).unwrap();
//! # drop(router);
//! ```
#![forbid(unsafe_code)]

mod api;
mod assets;
mod connections;
mod edits;
mod error;
mod guard;
mod jobs;
mod memory;
mod results;
mod workspace;

use std::path::PathBuf;
use std::sync::Arc;

pub use error::StudioError;

/// How the studio runs.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Config {
    /// The folder scenes are saved to and inputs uploaded to (created if missing).
    pub workspace: PathBuf,
    /// The caps every generated scene and upload runs under (the CLI's `--max-cells`, …; by
    /// default [`relief::Budget::for_this_machine`], memory bounded at half the machine's).
    pub budget: relief::Budget,
    /// The largest request body accepted, bytes (default 64 MiB: a 4096² f32 DEM upload).
    pub max_body_bytes: usize,
    /// How many generated heightfields are kept for download (default 16).
    pub kept_results: usize,
    /// How many generations and other heavy requests (parsing a scene, checking an upload,
    /// opening a DEM, finding peaks, encoding a download) run at once; more get 503. Default
    /// twice the cores, at least 4.
    pub max_jobs: usize,
    /// Most connections open at once (default 256); more wait in the listen queue.
    pub max_connections: usize,
    /// Longest a request's header may take to arrive, the wait for the next request on a
    /// kept-alive connection included (default 10 s); the connection is closed then, so idle
    /// connections cannot hold every place.
    pub header_timeout: std::time::Duration,
    /// The most bytes of samples the kept heightfields take together (default an eighth of the
    /// machine's memory, 1 GiB where it cannot be told); the oldest go first, and the newest is
    /// always kept.
    pub kept_bytes: u64,
    /// How long a generation, export or peak search waits for its share of the memory budget
    /// while others hold it (default 30 s), before 503: the running work's estimates together
    /// never pass [`relief::Budget::max_bytes`].
    pub memory_wait: std::time::Duration,
    /// Answer only requests addressed to a loopback name (`localhost`, `127.x.x.x`, `[::1]`):
    /// a web page elsewhere cannot reach the studio by pointing its own domain at 127.0.0.1
    /// (DNS rebinding). Default `true`; `relief serve --host` with another address turns it off.
    pub loopback_only: bool,
    /// A secret every request must carry (`?token=` once, then a cookie, or
    /// `Authorization: Bearer`); 401 otherwise. Default none; `relief serve` sets one (from
    /// [`new_token`]) whenever it listens beyond loopback.
    pub token: Option<String>,
}

impl Config {
    /// The defaults, saving to `workspace`.
    pub fn new(workspace: impl Into<PathBuf>) -> Self {
        Self {
            workspace: workspace.into(),
            budget: relief::Budget::for_this_machine(),
            max_body_bytes: 64 << 20,
            kept_results: 16,
            kept_bytes: relief::budget::physical_memory().map_or(1 << 30, |bytes| bytes / 8),
            memory_wait: std::time::Duration::from_secs(30),
            max_jobs: jobs::default_max_jobs(),
            max_connections: 256,
            header_timeout: std::time::Duration::from_secs(10),
            loopback_only: true,
            token: None,
        }
    }

    /// The same configuration under `budget`.
    #[must_use]
    pub fn with_budget(mut self, budget: relief::Budget) -> Self {
        self.budget = budget;
        self
    }
}

/// The studio's routes: the page at `/`, the JSON API under `/api/` (`docs/studio.md` in the
/// repository lists them).
///
/// # Errors
/// [`StudioError::Workspace`] when the workspace folder cannot be created or resolved.
pub fn router(config: &Config) -> Result<axum::Router, StudioError> {
    Ok(build(config)?.0)
}

/// The routes and the state they share.
fn build(config: &Config) -> Result<(axum::Router, Arc<api::App>), StudioError> {
    let workspace = workspace::Workspace::open(&config.workspace)?;
    let state = Arc::new(api::App::new(workspace, config));
    // The last layer added runs first: framing headers on every answer, then the host, the
    // token and the origin checks.
    let mut routes =
        api::routes(Arc::clone(&state), config.max_body_bytes).layer(axum::middleware::from_fn(guard::same_origin));
    if let Some(secret) = &config.token {
        let secret: Arc<str> = secret.as_str().into();
        routes = routes
            .layer(axum::middleware::from_fn(move |request, next| guard::token(Arc::clone(&secret), request, next)));
    }
    if config.loopback_only {
        routes = routes.layer(axum::middleware::from_fn(guard::loopback_only));
    }
    Ok((routes.layer(axum::middleware::from_fn(guard::headers)), state))
}

/// A new secret for [`Config::token`]: 32 random bytes from the operating system, in hex.
///
/// # Errors
/// [`StudioError::Token`] when the operating system has no randomness to give.
pub fn new_token() -> Result<String, StudioError> {
    guard::new_token().map_err(|e| StudioError::Token(e.to_string()))
}

/// Serves the studio on `listener` until Ctrl-C.
///
/// # Errors
/// As [`router`]. A connection that cannot be accepted (out of file descriptors) is waited
/// out, not returned.
pub async fn serve(listener: tokio::net::TcpListener, config: Config) -> Result<(), StudioError> {
    serve_until(listener, config, async {
        // Without a signal handler the server runs until the process is killed.
        if tokio::signal::ctrl_c().await.is_err() {
            std::future::pending::<()>().await;
        }
    })
    .await
}

/// Serves the studio on `listener` until `shutdown` completes, then finishes the requests in
/// flight and returns. Open progress streams (a page left open) end at once rather than holding
/// the shutdown.
///
/// # Errors
/// As [`router`]. A connection that cannot be accepted (out of file descriptors) is waited
/// out, not returned.
pub async fn serve_until(
    listener: tokio::net::TcpListener,
    config: Config,
    shutdown: impl std::future::Future<Output = ()> + Send + 'static,
) -> Result<(), StudioError> {
    let (routes, state) = build(&config)?;
    let limits = connections::Limits { max_connections: config.max_connections, header_timeout: config.header_timeout };
    connections::serve(listener, routes, limits, async move {
        shutdown.await;
        state.close();
    })
    .await;
    Ok(())
}

/// The crate README's example, compiled and run as a doc test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;
