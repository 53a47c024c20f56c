//! The one error type of the explorer's API, and how it is answered: a JSON object
//! `{"error": message, "field": …, "value": …, "expected": …}` with the fitting status.

use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde::Serialize;

/// Everything a request can get wrong, and the server's own failures.
#[derive(Debug, thiserror::Error)]
pub enum ApiError {
    /// A parameter out of its range (the woven library's validation, or the API's own bounds):
    /// 422, with the field the page marks.
    #[error("invalid parameter `{field}` = {value}: expected {expected}")]
    Invalid {
        /// The parameter as the page names it (`fiber.roughness`, `theta_i_deg`).
        field: String,
        /// The offending value, formatted.
        value: String,
        /// The valid range or set, in words.
        expected: String,
    },
    /// Text the server could not read as what the endpoint takes (malformed JSON, a material
    /// the library cannot parse, a bad CSV or WIF file): 400, or 422 for files.
    #[error("{message}")]
    Malformed {
        /// What is wrong, with the line where known.
        message: String,
        /// 400 for a malformed request, 422 for a well-formed request with bad content.
        status: StatusCode,
    },
    /// A request body over the limit: 413.
    #[error("request body too large: at most {limit} bytes")]
    TooLarge {
        /// The limit, bytes.
        limit: usize,
    },
    /// No such route (the server serves its own assets and API, nothing else): 404.
    #[error("not found: {0}")]
    NotFound(String),
    /// A route called with the wrong method: 405.
    #[error("method {method} not allowed for {path}")]
    MethodNotAllowed {
        /// The method used.
        method: String,
        /// The path.
        path: String,
    },
    /// A request body that did not arrive within the read timeout: 408 (the connection is
    /// then closed).
    #[error("request body not received within the read timeout ({limit_ms} ms)")]
    Timeout {
        /// The read timeout, milliseconds.
        limit_ms: u128,
    },
    /// The server failed (a worker panicked): 500.
    #[error("internal error: {0}")]
    Internal(String),
}

/// The API's result type.
pub type ApiResult<T> = Result<T, ApiError>;

impl ApiError {
    /// An [`ApiError::Invalid`] from displayable parts.
    pub fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        ApiError::Invalid {
            field: field.into(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }

    /// A malformed request (400).
    pub fn bad_request(message: impl Into<String>) -> Self {
        ApiError::Malformed {
            message: message.into(),
            status: StatusCode::BAD_REQUEST,
        }
    }

    /// Well-formed request, unusable content (422): a file that does not parse, say.
    pub fn unprocessable(message: impl Into<String>) -> Self {
        ApiError::Malformed {
            message: message.into(),
            status: StatusCode::UNPROCESSABLE_ENTITY,
        }
    }

    /// The HTTP status of the error.
    pub fn status(&self) -> StatusCode {
        match self {
            ApiError::Invalid { .. } => StatusCode::UNPROCESSABLE_ENTITY,
            ApiError::Malformed { status, .. } => *status,
            ApiError::TooLarge { .. } => StatusCode::PAYLOAD_TOO_LARGE,
            ApiError::NotFound(_) => StatusCode::NOT_FOUND,
            ApiError::MethodNotAllowed { .. } => StatusCode::METHOD_NOT_ALLOWED,
            ApiError::Timeout { .. } => StatusCode::REQUEST_TIMEOUT,
            ApiError::Internal(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }

    /// The JSON body of the error.
    pub fn body(&self) -> ErrorBody {
        let (field, value, expected) = match self {
            ApiError::Invalid {
                field,
                value,
                expected,
            } => (
                Some(field.clone()),
                Some(value.clone()),
                Some(expected.clone()),
            ),
            _ => (None, None, None),
        };
        // A key or a name of megabytes, echoed from the request, is answered cut.
        let clip = |text: String| woven::error::clip_words(&text).into_owned();
        ErrorBody {
            error: clip(self.to_string()),
            field: field.map(clip),
            value: value.map(clip),
            expected,
        }
    }
}

/// The JSON an error is answered with.
#[derive(Debug, Serialize)]
pub struct ErrorBody {
    /// The whole message, for people.
    pub error: String,
    /// The offending parameter, when one is to blame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub field: Option<String>,
    /// Its value, formatted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub value: Option<String>,
    /// Its valid range or set, in words.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected: Option<String>,
}

impl From<woven::Error> for ApiError {
    fn from(e: woven::Error) -> Self {
        match e {
            woven::Error::InvalidParameter {
                name,
                value,
                expected,
            } => ApiError::Invalid {
                field: name,
                value,
                expected,
            },
            other => ApiError::unprocessable(other.to_string()),
        }
    }
}

impl From<woven_render::Error> for ApiError {
    fn from(e: woven_render::Error) -> Self {
        ApiError::unprocessable(e.to_string())
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (self.status(), Json(self.body())).into_response()
    }
}
