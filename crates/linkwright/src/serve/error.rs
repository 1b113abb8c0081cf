//! The API's one error shape: a 4xx/5xx status with `{"error": "...", "issues": [{field, message}]}`,
//! and `more_issues`, how many problems were found beyond those listed, when there are any.

use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use linkwright_core::{Issue, IssueList, Severity};
use serde::Serialize;

/// One finding about a request, naming the field (a path such as `scene.moving_bodies[0].poses`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub(crate) struct IssueJson {
    pub field: String,
    pub message: String,
    /// `error` or `warning`.
    pub severity: Severity,
}

/// An error answer.
#[derive(Clone, Debug, Serialize)]
pub(crate) struct ApiError {
    #[serde(skip)]
    pub status: StatusCode,
    pub error: String,
    pub issues: Vec<IssueJson>,
    /// Problems found beyond the listed `issues` (the library lists the first ones only).
    #[serde(skip_serializing_if = "is_zero")]
    pub more_issues: usize,
    /// Seconds after which a refused job may be tried again (503/429 only).
    #[serde(skip)]
    pub retry_after: Option<u32>,
}

impl ApiError {
    pub(crate) fn new(status: StatusCode, error: impl Into<String>) -> ApiError {
        ApiError { status, error: error.into(), issues: Vec::new(), more_issues: 0, retry_after: None }
    }
    pub(crate) fn bad_request(error: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::BAD_REQUEST, error)
    }
    pub(crate) fn not_found(error: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::NOT_FOUND, error)
    }
    pub(crate) fn unprocessable(error: impl Into<String>) -> ApiError {
        ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, error)
    }
    /// One issue at `field`.
    pub(crate) fn with_issue(mut self, field: impl Into<String>, message: impl Into<String>) -> ApiError {
        self.issues.push(IssueJson { field: field.into(), message: message.into(), severity: Severity::Error });
        self
    }
    pub(crate) fn retry_after(mut self, seconds: u32) -> ApiError {
        self.retry_after = Some(seconds);
        self
    }

    /// A document that is not what the field needs (bad JSON, a missing field, a wrong type).
    /// `prefix` is the request field the document sits in (`scene`, `design`), or empty.
    pub(crate) fn parse(what: &str, prefix: &str, path: &str, message: &str) -> ApiError {
        let field = join_field(prefix, path);
        ApiError::bad_request(format!("{what} cannot be read: {field}: {message}")).with_issue(field, message)
    }

    /// A scene that fails validation: every listed issue, errors and warnings, and how many more.
    pub(crate) fn invalid_scene(prefix: &str, issues: &IssueList<Issue>) -> ApiError {
        let errors = issues.iter().filter(|i| i.severity == Severity::Error).count();
        let first = issues.iter().find(|i| i.severity == Severity::Error);
        let summary = match first {
            Some(i) if errors == 1 && issues.more() == 0 => {
                format!("the scene has a problem: {}: {}", i.field, i.message)
            }
            Some(i) => format!("the scene has {} problems; the first: {}: {}", issues.total(), i.field, i.message),
            None => "the scene is not valid".to_string(),
        };
        let mut e = ApiError::unprocessable(summary);
        e.issues = issues.iter().map(|i| issue_json(prefix, i)).collect();
        e.with_more(issues.more())
    }

    /// The error text with how many problems were found beyond the listed ones, as a person reads it.
    fn with_more(mut self, more: usize) -> ApiError {
        if more > 0 {
            self.error = format!("{} (... and {more} more)", self.error);
            self.more_issues = more;
        }
        self
    }

    /// A list of problems at fields under `prefix` (a design's, print settings'), with `error` the
    /// answer's text.
    pub(crate) fn listed<T>(
        mut self,
        issues: &IssueList<T>,
        field: impl Fn(&T) -> String,
        message: impl Fn(&T) -> &str,
    ) -> ApiError {
        for i in issues {
            self = self.with_issue(field(i), message(i));
        }
        self.with_more(issues.more())
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// An issue of the library, its field placed under `prefix`.
pub(super) fn issue_json(prefix: &str, i: &Issue) -> IssueJson {
    IssueJson { field: join_field(prefix, &i.field), message: i.message.clone(), severity: i.severity }
}

/// `path` placed under the request field `prefix` (`scene` + `moving_bodies[0]`, `alternatives` + `[2]`).
pub(super) fn join_field(prefix: &str, path: &str) -> String {
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
