//! The API's one error shape: a 4xx/5xx status with `{"error": "...", "issues": [{field, message}]}`.

use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use linkwright_core::{Issue, Severity};
use serde::Serialize;

/// One finding about a request, naming the field (a path such as `scene.moving_bodies[0].poses`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct IssueJson {
    pub field: String,
    pub message: String,
    /// `error` or `warning`.
    pub severity: Severity,
}

/// An error answer.
#[derive(Clone, Debug, Serialize)]
pub struct ApiError {
    #[serde(skip)]
    pub status: StatusCode,
    pub error: String,
    pub issues: Vec<IssueJson>,
    /// Seconds after which a refused job may be tried again (503/429 only).
    #[serde(skip)]
    pub retry_after: Option<u32>,
}

impl ApiError {
    pub fn new(status: StatusCode, error: impl Into<String>) -> ApiError {
        ApiError { status, error: error.into(), issues: Vec::new(), retry_after: None }
    }
    pub fn bad_request(error: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::BAD_REQUEST, error)
    }
    pub fn not_found(error: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::NOT_FOUND, error)
    }
    pub fn unprocessable(error: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, error)
    }
    /// One issue at `field`.
    pub fn with_issue(mut self, field: impl Into<String>, message: impl Into<String>) -> ApiError {
        self.issues.push(IssueJson { field: field.into(), message: message.into(), severity: Severity::Error });
        self
    }
    pub fn retry_after(mut self, seconds: u32) -> ApiError {
        self.retry_after = Some(seconds);
        self
    }

    /// A document that is not what the field needs (bad JSON, a missing field, a wrong type).
    /// `prefix` is the request field the document sits in (`scene`, `design`), or empty.
    pub fn parse(what: &str, prefix: &str, path: &str, message: &str) -> ApiError {
        let field = join_field(prefix, path);
        ApiError::bad_request(format!("{what} cannot be read: {field}: {message}")).with_issue(field, message)
    }

    /// A scene that fails validation: every issue, errors and warnings.
    pub fn invalid_scene(prefix: &str, issues: &[Issue]) -> ApiError {
        let errors = issues.iter().filter(|i| i.severity == Severity::Error).count();
        let first = issues.iter().find(|i| i.severity == Severity::Error);
        let summary = match first {
            Some(i) if errors == 1 => format!("the scene has a problem: {}: {}", i.field, i.message),
            Some(i) => format!("the scene has {errors} problems; the first: {}: {}", i.field, i.message),
            None => "the scene is not valid".to_string(),
        };
        let mut e = ApiError::unprocessable(summary);
        e.issues = issues.iter().map(|i| issue_json(prefix, i)).collect();
        e
    }
}

/// An issue of the library, its field placed under `prefix`.
pub fn issue_json(prefix: &str, i: &Issue) -> IssueJson {
    IssueJson { field: join_field(prefix, &i.field), message: i.message.clone(), severity: i.severity }
}

/// `path` placed under the request field `prefix` (`scene` + `moving_bodies[0]`, `alternatives` + `[2]`).
pub fn join_field(prefix: &str, path: &str) -> String {
    match (prefix.is_empty(), path.is_empty() || path == "." || path == "?") {
        (true, true) => ".".to_string(),
        (true, false) => path.to_string(),
        (false, true) => prefix.to_string(),
        (false, false) if path.starts_with('[') => format!("{prefix}{path}"),
        (false, false) => format!("{prefix}.{path}"),
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let status = self.status;
        let retry = self.retry_after;
        let mut response = (status, Json(self)).into_response();
        if let Some(seconds) = retry {
            if let Ok(v) = HeaderValue::from_str(&seconds.to_string()) {
                response.headers_mut().insert(header::RETRY_AFTER, v);
            }
        }
        response
    }
}

#[cfg(test)]
mod tests {
    use super::join_field;

    #[test]
    fn fields_join_under_their_request_field() {
        assert_eq!(join_field("scene", "moving_bodies[0].poses"), "scene.moving_bodies[0].poses");
        assert_eq!(join_field("scene", "."), "scene");
        assert_eq!(join_field("", "settings.seed"), "settings.seed");
        assert_eq!(join_field("", ""), ".");
        assert_eq!(join_field("alternatives", "[2]"), "alternatives[2]");
    }
}
