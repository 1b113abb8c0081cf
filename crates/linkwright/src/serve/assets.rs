//! The files the binary carries: the front-end (`web/`) and the bundled example scenes (`examples/`).
//! Only these are ever served: a request names an embedded file or gets a 404, so no path reaches
//! the disk.

use super::error::ApiError;
use axum::http::{header, HeaderMap, HeaderValue, StatusCode, Uri};
use axum::response::{IntoResponse, Response};
use linkwright_core::Scene;
use rust_embed::RustEmbed;
use serde::Serialize;

#[derive(RustEmbed)]
#[folder = "web/"]
struct Web;

#[derive(RustEmbed)]
#[folder = "../../examples/"]
struct Examples;

/// One entry of the example gallery.
#[derive(Clone, Debug, Serialize)]
pub(crate) struct ExampleSummary {
    /// The name to fetch it by (`GET /api/examples/NAME`).
    pub name: String,
    /// The scene's own name.
    pub title: String,
    /// Number of moving bodies K.
    pub bodies: usize,
    /// Number of fixed bodies.
    pub fixed_bodies: usize,
    /// Number of poses N.
    pub poses: usize,
}

/// The gallery, sorted by name (examples that do not parse are left out: a test keeps them parsing).
pub(super) fn example_summaries() -> Vec<ExampleSummary> {
    let mut out: Vec<ExampleSummary> = Examples::iter()
        .filter_map(|file| {
            let name = file.strip_suffix(".json")?.to_string();
            let text = example_text(&name)?;
            let scene = Scene::from_json(&text).ok()?;
            Some(ExampleSummary {
                title: if scene.name.is_empty() { name.replace('_', " ") } else { scene.name.clone() },
                name,
                bodies: scene.moving_bodies.len(),
                fixed_bodies: scene.fixed_bodies.len(),
                poses: scene.moving_bodies.first().map_or(0, |b| b.poses.len()),
            })
        })
        .collect();
    out.sort_by(|a, b| a.name.cmp(&b.name));
    out
}

/// The text of example `name` (a plain file stem: no slashes, no dots).
pub(super) fn example_text(name: &str) -> Option<String> {
    let plain = !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if !plain {
        return None;
    }
    let file = Examples::get(&format!("{name}.json"))?;
    String::from_utf8(file.data.into_owned()).ok()
}

/// The content type of an asset, by extension.
fn content_type(path: &str) -> &'static str {
    match path.rsplit('.').next().unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "svg" => "image/svg+xml",
        "png" => "image/png",
        "json" => "application/json",
        "ico" => "image/x-icon",
        _ => "application/octet-stream",
    }
}

/// Serves an embedded front-end file (`/` is `index.html`), with an ETag so reloads are cheap.
pub(super) async fn asset(uri: Uri, headers: HeaderMap) -> Response {
    let path = uri.path().trim_start_matches('/');
    if path.starts_with("api/") || path == "api" {
        return ApiError::not_found(format!("no API endpoint {}; see docs/api.md", uri.path())).into_response();
    }
    let path = if path.is_empty() { "index.html" } else { path };
    let Some(file) = Web::get(path) else {
        return (StatusCode::NOT_FOUND, [(header::CONTENT_TYPE, "text/plain; charset=utf-8")], "not found\n")
            .into_response();
    };
    let etag = format!("\"{}\"", hex(&file.metadata.sha256_hash()[..12]));
    if headers.get(header::IF_NONE_MATCH).and_then(|v| v.to_str().ok()) == Some(etag.as_str()) {
        return StatusCode::NOT_MODIFIED.into_response();
    }
    let mut response = file.data.into_owned().into_response();
    let h = response.headers_mut();
    h.insert(header::CONTENT_TYPE, HeaderValue::from_static(content_type(path)));
    h.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-cache"));
    if let Ok(v) = HeaderValue::from_str(&etag) {
        h.insert(header::ETAG, v);
    }
    response
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_bundled_example_is_listed_and_the_front_end_is_embedded() {
        let list = example_summaries();
        assert_eq!(list.len(), Examples::iter().count(), "every example parses");
        assert!(list.iter().any(|e| e.name == "k1_garbage_truck" && e.title == "garbage truck" && e.poses == 3));
        assert!(Web::get("index.html").is_some());
    }

    #[test]
    fn example_names_cannot_leave_the_folder() {
        assert!(example_text("k1_garbage_truck").is_some());
        for bad in ["../Cargo", "k1_garbage_truck.json", "", "a/b", "..", "%2e%2e"] {
            assert!(example_text(bad).is_none(), "{bad}");
        }
    }
}
