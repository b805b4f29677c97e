//! The studio's errors: [`StudioError`] for the library's callers, [`ApiError`] for a request
//! (a status and a JSON body naming the problem).

use axum::Json;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use relief::ReliefError;
use serde::Serialize;

/// Why the studio could not start or keep serving.
#[derive(Debug, thiserror::Error)]
pub enum StudioError {
    /// The workspace folder cannot be created or resolved.
    #[error("workspace {}: {source}", path.display())]
    Workspace {
        /// The folder.
        path: std::path::PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// An I/O error of the server's own (binding its listener, say).
    #[error("serving: {0}")]
    Serve(#[from] std::io::Error),
    /// No random secret could be drawn for [`crate::Config::token`].
    #[error("drawing a random token: {0}")]
    Token(String),
}

/// A request that failed: its status, what is wrong, and the scene's JSON path of the problem.
#[derive(Debug, Serialize)]
pub(crate) struct ApiError {
    #[serde(skip)]
    status: StatusCode,
    error: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    path: Option<String>,
}

impl ApiError {
    /// A client error with `status`.
    pub(crate) fn new(status: StatusCode, error: impl std::fmt::Display) -> Self {
        Self { status, error: error.to_string(), path: None }
    }

    /// The status it answers with.
    #[cfg(test)]
    pub(crate) fn status(&self) -> StatusCode {
        self.status
    }

    /// What is wrong.
    #[cfg(test)]
    pub(crate) fn message(&self) -> &str {
        &self.error
    }

    /// 400: the request itself is malformed.
    pub(crate) fn bad_request(error: impl std::fmt::Display) -> Self {
        Self::new(StatusCode::BAD_REQUEST, error)
    }

    /// 404: nothing by that name.
    pub(crate) fn not_found(error: impl std::fmt::Display) -> Self {
        Self::new(StatusCode::NOT_FOUND, error)
    }

    /// 500: the server failed on valid input.
    pub(crate) fn internal(error: impl std::fmt::Display) -> Self {
        Self::new(StatusCode::INTERNAL_SERVER_ERROR, error)
    }

    /// 422 at a scene's JSON path.
    pub(crate) fn at(path: impl Into<String>, error: impl std::fmt::Display) -> Self {
        Self { status: StatusCode::UNPROCESSABLE_ENTITY, error: error.to_string(), path: Some(path.into()) }
    }
}

impl From<ReliefError> for ApiError {
    fn from(error: ReliefError) -> Self {
        match &error {
            ReliefError::Scene { path, .. } | ReliefError::OverBudget { path, .. } => Self::at(path.clone(), &error),
            ReliefError::Io(_) | ReliefError::File { .. } => Self::new(StatusCode::UNPROCESSABLE_ENTITY, &error),
            _ => Self::internal(&error),
        }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (self.status, Json(&self)).into_response()
    }
}
