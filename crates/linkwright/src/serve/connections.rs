//! Connections are bounded in number and in time, so clients that connect and say nothing, send half
//! a request, or announce a body they never send cannot hold the server's sockets and memory: the
//! accept loop serves at most [`MAX_CONNECTIONS`] at once; a request's head must arrive within
//! [`HEADER_READ_TIMEOUT`] (which also closes idle keep-alive connections); its body must arrive whole
//! within [`BODY_READ_TIMEOUT`]; a body announced larger than [`MAX_BODY`] is refused before any
//! of it is read; and an answer the client stops reading is dropped with its connection after
//! [`WRITE_TIMEOUT`], not kept in memory for as long as the client stays connected. `axum::serve`
//! has none of these knobs, hence the loop here over hyper's own builder.

use super::error::ApiError;
use axum::body::Body;
use axum::extract::{ConnectInfo, Request};
use axum::http::{header, HeaderValue, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::Router;
use http_body_util::{BodyExt, LengthLimitError, Limited};
use hyper_util::rt::{TokioIo, TokioTimer};
use std::sync::Arc;
use std::time::Duration;
use tokio::net::TcpListener;
use tokio::sync::Semaphore;
use tokio_io_timeout::TimeoutStream;
use tower::ServiceExt;

/// Largest request body accepted, bytes (the largest bundled scene is about 6 kB: `ls -l examples/`).
pub(super) const MAX_BODY: usize = 2 * 1024 * 1024;

/// Connections served at once; more wait in the kernel's backlog until one closes. A browser opens
/// at most six to one server, so 256 is room for dozens of tabs and scripts while staying far below the
/// usual limit of 1024 open files a process has.
pub(super) const MAX_CONNECTIONS: usize = 256;

/// How long a request's head (request line and headers) may take to arrive, counted from the moment
/// the server waits for it: on a new connection, and after each answer on a kept-alive one. A client on
/// this computer or a local network sends its head in milliseconds; 10 s tolerates a very slow one and
/// closes a connection that says nothing (an idle keep-alive, a half-sent head) soon. Browsers open a
/// new connection when a kept-alive one was closed.
pub(super) const HEADER_READ_TIMEOUT: Duration = Duration::from_secs(10);

/// How long a request's whole body may take to arrive once its head has. The largest body allowed
/// (2 MiB) arrives in this time even at 100 kB/s; a client that stops halfway gets a 408 and its
/// connection is closed.
pub(super) const BODY_READ_TIMEOUT: Duration = Duration::from_secs(30);

/// How long a write to a client may wait for the client to read. The answer stays in memory until
/// it is written, and the largest (a simulation, about 5 MB) leaves in well under a second on any
/// local link; a client that reads nothing for 30 s is not reading, and its connection is closed.
pub(super) const WRITE_TIMEOUT: Duration = Duration::from_secs(30);

/// Pause after a failed `accept` (out of file descriptors, say), so the loop waits for a connection to
/// close instead of spinning.
const ACCEPT_RETRY: Duration = Duration::from_millis(100);

/// Serves `app` on `listener` until the future is dropped. Each connection runs in its own task with
/// its peer's address as `ConnectInfo`, as `axum::serve` would give it.
pub(super) async fn serve(listener: TcpListener, app: Router) {
    let open = Arc::new(Semaphore::new(MAX_CONNECTIONS));
    loop {
        let Ok(permit) = open.clone().acquire_owned().await else { return };
        let (stream, peer) = match listener.accept().await {
            Ok(accepted) => accepted,
            Err(_) => {
                tokio::time::sleep(ACCEPT_RETRY).await;
                continue;
            }
        };
        // Small answers (status, progress) go out at once rather than waiting to fill a packet.
        let _ = stream.set_nodelay(true);
        let app = app.clone();
        let service = hyper::service::service_fn(move |mut request: Request<hyper::body::Incoming>| {
            request.extensions_mut().insert(ConnectInfo(peer));
            app.clone().oneshot(request.map(Body::new))
        });
        let mut stream = TimeoutStream::new(stream);
        stream.set_write_timeout(Some(WRITE_TIMEOUT));
        tokio::spawn(async move {
            let _permit = permit;
            let connection = hyper::server::conn::http1::Builder::new()
                .timer(TokioTimer::new())
                .header_read_timeout(HEADER_READ_TIMEOUT)
                .serve_connection(TokioIo::new(Box::pin(stream)), service);
            // A connection that ends in an error (the peer reset it, a head that timed out) only
            // concerns that client.
            let _ = connection.await;
        });
    }
}

/// Reads a request's whole body before any handler sees it: refuses at once one that announces more
/// than [`MAX_BODY`] bytes (413), refuses one that turns out larger while it arrives (413), and gives
/// up on one that has not arrived whole within [`BODY_READ_TIMEOUT`] (408). These answers close the
/// connection, since the rest of the body is never read.
pub(super) async fn read_body(request: Request, next: Next) -> Response {
    let announced = request
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    if let Some(length) = announced.filter(|&n| n > MAX_BODY as u64) {
        return closing(too_large(&format!("the request body ({length} bytes) is larger")));
    }
    let (parts, body) = request.into_parts();
    let bytes = match tokio::time::timeout(BODY_READ_TIMEOUT, Limited::new(body, MAX_BODY).collect()).await {
        Ok(Ok(collected)) => collected.to_bytes(),
        Ok(Err(e)) if e.downcast_ref::<LengthLimitError>().is_some() => {
            return closing(too_large("the request body is larger"))
        }
        Ok(Err(e)) => {
            return closing(ApiError::bad_request(format!("the request body could not be read: {e}")));
        }
        Err(_) => {
            let message = format!(
                "the request body did not arrive within {} s; send the whole body at once",
                BODY_READ_TIMEOUT.as_secs()
            );
            return closing(ApiError::new(StatusCode::REQUEST_TIMEOUT, message));
        }
    };
    next.run(Request::from_parts(parts, Body::from(bytes))).await
}

fn too_large(what: &str) -> ApiError {
    ApiError::new(StatusCode::PAYLOAD_TOO_LARGE, format!("{what} than the limit of {MAX_BODY} bytes"))
}

/// `error`, asking the connection to close after it.
fn closing(error: ApiError) -> Response {
    let mut response = error.into_response();
    response.headers_mut().insert(header::CONNECTION, HeaderValue::from_static("close"));
    response
}
