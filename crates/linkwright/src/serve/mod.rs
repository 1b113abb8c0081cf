//! `linkwright serve`: the local web app. One binary serves the front-end it carries (`web/`, embedded)
//! and a small JSON API over the library (see `docs/api.md`). It listens on 127.0.0.1 unless told
//! otherwise, bounds connections, request sizes and heavy jobs (in number and in time), and stops a job
//! when its client goes away.

mod api;
mod assets;
mod bundles;
mod connections;
mod error;
mod fabricate;
mod jobs;
mod preview;

use crate::failure::Failure;
use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{header, HeaderValue, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use clap::Args;
use std::io::Write;
use std::net::SocketAddr;
use std::time::Duration;

use api::AppState;
use jobs::{Jobs, Limits};

#[derive(Args, Debug)]
pub(crate) struct ServeArgs {
    /// Address to listen on. The default serves this computer only; 0.0.0.0 serves the network.
    #[arg(long, default_value = "127.0.0.1")]
    host: String,
    /// Port to listen on; 0 picks a free one (the URL is printed).
    #[arg(long, default_value_t = 8080)]
    port: u16,
    /// Open the app in the default browser.
    #[arg(long)]
    open: bool,
    /// Worker threads for designs and fabrications (default: all cores). Results do not depend on it.
    #[arg(long, value_parser = crate::thread_count())]
    threads: Option<usize>,
    /// Designs, fabrications and other heavy requests that run at once; more wait in a short queue.
    #[arg(long, default_value_t = Limits::default().running)]
    jobs: usize,
    /// Seconds a heavy request may run (and may wait in line) before it is stopped and answered with
    /// an error saying what to change.
    #[arg(long, default_value_t = Limits::default().deadline.as_secs_f64())]
    job_seconds: f64,
}

/// The app: API routes, the embedded front-end, limits and security headers.
pub(crate) fn router(state: AppState) -> Router {
    Router::new()
        .route("/api/examples", get(api::examples))
        .route("/api/examples/{name}", get(api::example))
        .route("/api/status", get(api::status))
        .route("/api/families", get(api::families))
        .route("/api/units", get(api::units))
        .route("/api/design", post(api::design))
        .route("/api/design/stream", post(api::design_stream))
        .route("/api/check", post(api::check))
        .route("/api/simulate", post(api::simulate))
        .route("/api/edit", post(api::edit))
        .route("/api/balance", post(api::balance))
        .route("/api/render", post(api::render))
        .route("/api/fabricate", post(fabricate::fabricate))
        .route("/api/fabricate/settings", get(fabricate::default_settings))
        .route("/api/fabricate/{id}/{*path}", get(fabricate::download))
        .method_not_allowed_fallback(method_not_allowed)
        .fallback(fallback)
        .layer(DefaultBodyLimit::max(api::MAX_BODY))
        .layer(axum::middleware::from_fn(connections::read_body))
        .layer(axum::middleware::from_fn_with_state(state.clone(), same_origin))
        .layer(axum::middleware::map_response(security_headers))
        .with_state(state)
}

/// Refuses requests another web site makes the browser send: a `Host` that is not this computer while
/// the server listens on this computer only (DNS rebinding), and a cross-origin `Origin` on anything but
/// GET (a page elsewhere posting designs to run).
async fn same_origin(State(state): State<AppState>, request: Request, next: Next) -> Response {
    let host = header_text(request.headers(), header::HOST);
    let origin = header_text(request.headers(), header::ORIGIN);
    if state.loopback_only && !is_loopback_host(&host) {
        let message = format!("this server answers only to localhost, not to \"{host}\"");
        return error::ApiError::new(StatusCode::FORBIDDEN, message).into_response();
    }
    let read_only = request.method() == Method::GET || request.method() == Method::HEAD;
    if !read_only && !origin.is_empty() && origin != format!("http://{host}") {
        let message = format!("requests from another site ({origin}) are refused");
        return error::ApiError::new(StatusCode::FORBIDDEN, message).into_response();
    }
    next.run(request).await
}

fn header_text(headers: &axum::http::HeaderMap, name: header::HeaderName) -> String {
    headers.get(name).and_then(|v| v.to_str().ok()).unwrap_or("").to_string()
}

/// `localhost`, `127.x.y.z` or `[::1]`, with or without a port.
fn is_loopback_host(host: &str) -> bool {
    let name = match host.strip_prefix('[') {
        Some(v6) => v6.split(']').next().unwrap_or(""),
        None => host.rsplit_once(':').map_or(host, |(name, _)| name),
    };
    name.eq_ignore_ascii_case("localhost") || name.parse::<std::net::IpAddr>().is_ok_and(|ip| ip.is_loopback())
}

async fn method_not_allowed(method: Method) -> error::ApiError {
    error::ApiError::new(StatusCode::METHOD_NOT_ALLOWED, format!("{method} is not allowed here; see docs/api.md"))
}

/// Front-end files for GET and HEAD; anything else is not a route.
async fn fallback(method: Method, uri: axum::http::Uri, headers: axum::http::HeaderMap) -> Response {
    if method != Method::GET && method != Method::HEAD {
        return method_not_allowed(method).await.into_response();
    }
    assets::asset(uri, headers).await
}

/// The page may load only its own files and talk only to its own server.
async fn security_headers(mut response: Response) -> Response {
    let h = response.headers_mut();
    h.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(
            "default-src 'self'; img-src 'self' data: blob:; style-src 'self' 'unsafe-inline'; \
             connect-src 'self'; object-src 'none'; base-uri 'none'; frame-ancestors 'none'",
        ),
    );
    h.insert(header::X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff"));
    h.insert(header::REFERRER_POLICY, HeaderValue::from_static("no-referrer"));
    response
}

pub(crate) fn serve(args: ServeArgs) -> Result<(), Failure> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .thread_name(|i| format!("linkwright-design-{i}"))
        .build()
        .map_err(|e| Failure::Input(format!("error: --threads: {e}")))?;
    if args.jobs == 0 {
        return Err(Failure::Input("error: --jobs: must be at least 1".into()));
    }
    let deadline = Some(args.job_seconds)
        .filter(|s| s.is_finite() && *s > 0.0 && *s <= 86_400.0)
        .map(Duration::from_secs_f64)
        .ok_or_else(|| Failure::Input("error: --job-seconds: must be a number of seconds from 0 to 86400".into()))?;
    let limits = Limits { running: args.jobs, deadline, ..Limits::default() };
    let loopback_only = match args.host.parse::<std::net::IpAddr>() {
        Ok(ip) => ip.is_loopback(),
        Err(_) => args.host.eq_ignore_ascii_case("localhost"),
    };
    let state = AppState::new(Jobs::new(limits, pool), loopback_only);
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| Failure::Input(format!("error: cannot start the server: {e}")))?;
    let jobs = state.jobs.clone();
    let result = runtime.block_on(run(args, state));
    // Running designs stop at their next check; do not wait long for them.
    jobs.stop_all();
    runtime.shutdown_timeout(Duration::from_secs(2));
    result
}

async fn run(args: ServeArgs, state: AppState) -> Result<(), Failure> {
    let address = format!("{}:{}", args.host, args.port);
    let listener = tokio::net::TcpListener::bind(&address)
        .await
        .map_err(|e| Failure::Input(format!("error: cannot listen on {address}: {e}")))?;
    let local = listener.local_addr().map_err(|e| Failure::Input(format!("error: {e}")))?;
    let url = match local {
        SocketAddr::V6(a) => format!("http://[{}]:{}/", a.ip(), a.port()),
        SocketAddr::V4(a) => format!("http://{}:{}/", a.ip(), a.port()),
    };
    println!("Linkwright is running at {url}  (Ctrl+C to stop)");
    let _ = std::io::stdout().flush();
    if !local.ip().is_loopback() {
        eprintln!("warning: listening on {local}: other computers on the network can use this server");
    }
    if args.open {
        open_browser(&url);
    }
    tokio::select! {
        () = connections::serve(listener, router(state)) => Err(Failure::Input("error: the server stopped".into())),
        _ = tokio::signal::ctrl_c() => {
            println!("stopping");
            Ok(())
        }
    }
}

/// Opens `url` in the default browser; failing to is a warning, not an error.
fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        ("open", vec![url])
    } else if cfg!(windows) {
        ("cmd", vec!["/C", "start", "", url])
    } else {
        ("xdg-open", vec![url])
    };
    let spawned = std::process::Command::new(opener.0)
        .args(&opener.1)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
    if let Err(e) = spawned {
        eprintln!("warning: could not open a browser ({}: {e}); open {url} yourself", opener.0);
    }
}

#[cfg(test)]
mod tests {
    use super::is_loopback_host;

    #[test]
    fn loopback_hosts() {
        for host in ["localhost:8080", "127.0.0.1:1", "127.0.0.1", "[::1]:8080", "LOCALHOST"] {
            assert!(is_loopback_host(host), "{host}");
        }
        for host in ["evil.example:8080", "10.0.0.1:8080", "", "localhost.evil.example", "[::2]:80"] {
            assert!(!is_loopback_host(host), "{host}");
        }
    }
}
