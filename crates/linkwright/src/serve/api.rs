//! The API handlers (documented in `docs/api.md`). Every request body is read as text, parsed with
//! path-aware errors and validated before any work starts; heavy work runs as a job (see
//! [`super::jobs`]) on the job table's pool, never on the async threads.

use super::assets::{example_summaries, example_text, ExampleSummary};
use super::bundles::{Bundles, Limits as BundleLimits};
use super::error::{issue_json, join_field, ApiError};
use super::jobs::{JobEnd, JobObserver, Jobs, Kind, StopFlag, StopOnDrop, StopReason, Work};
use axum::body::Bytes;
use axum::extract::rejection::{BytesRejection, PathRejection};
use axum::extract::{ConnectInfo, FromRequestParts, Path, State};
use axum::http::request::Parts;
use axum::http::{header, StatusCode};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::Json;
use linkwright_core::analysis::{analyze, AnalysisError, AnalysisOptions, Replay, Which, MAX_STEPS};
use linkwright_core::balance::{Balance, Balanced, SpringSearch};
use linkwright_core::fab::{model_scale, BuildPlan, PrintSettings};
use linkwright_core::geom::Point;
use linkwright_core::statics::Masses;
use linkwright_core::{
    animation_svg, design_svg, DesignFile, EditError, Mechanism, MechanismType, Options, Problem, Progress, Reject,
    RenderInput, Scene, Start, Status, Units,
};
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::convert::Infallible;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::mpsc;

pub(super) use super::connections::MAX_BODY;

/// What every handler shares.
#[derive(Clone)]
pub(crate) struct AppState {
    pub jobs: Arc<Jobs>,
    /// Fabrications kept for download.
    pub bundles: Arc<Bundles>,
    pub examples: Arc<Vec<ExampleSummary>>,
    /// The server listens on this computer only, so requests must name it as their host.
    pub loopback_only: bool,
}

impl AppState {
    pub(crate) fn new(jobs: Jobs, loopback_only: bool) -> AppState {
        AppState {
            jobs: Arc::new(jobs),
            bundles: Arc::new(Bundles::new(BundleLimits::default())),
            examples: Arc::new(example_summaries()),
            loopback_only,
        }
    }
}

/// Who asks: the `X-Linkwright-Client` header the app sends (one id per browser tab), or else the
/// peer's address. One heavy job per client.
pub(super) struct Client(pub String);

impl<S: Send + Sync> FromRequestParts<S> for Client {
    type Rejection = Infallible;
    async fn from_request_parts(parts: &mut Parts, _state: &S) -> Result<Self, Self::Rejection> {
        let header = parts.headers.get("x-linkwright-client").and_then(|v| v.to_str().ok()).filter(|id| {
            !id.is_empty() && id.len() <= 64 && id.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        });
        let id = match header {
            Some(id) => format!("id:{id}"),
            None => match parts.extensions.get::<ConnectInfo<SocketAddr>>() {
                Some(ConnectInfo(addr)) => format!("ip:{}", addr.ip()),
                None => "ip:unknown".to_string(),
            },
        };
        Ok(Client(id))
    }
}

/// `GET /api/examples`: the gallery.
pub(super) async fn examples(State(state): State<AppState>) -> Json<Vec<ExampleSummary>> {
    Json(state.examples.as_ref().clone())
}

/// `GET /api/examples/{name}`: one example scene, as its file.
pub(super) async fn example(name: Result<Path<String>, PathRejection>) -> Result<Response, ApiError> {
    let Path(name) = name.map_err(|e| ApiError::bad_request(e.body_text()))?;
    let text = example_text(&name)
        .ok_or_else(|| ApiError::not_found(format!("no example called \"{name}\"; GET /api/examples lists them")))?;
    Ok(([(header::CONTENT_TYPE, "application/json")], text).into_response())
}

/// `GET /api/families`: the mechanism families the engine designs, in the order an automatic choice
/// tries them: each one's `id` (the scene's `mechanism` word), `label`, a menu `description` and
/// `max_bodies` (null: any number of moving bodies).
pub(super) async fn families() -> Json<Value> {
    Json(Value::Array(
        MechanismType::ALL
            .iter()
            .map(|f| {
                json!({"id": f.id(), "label": f.label(), "description": f.description(), "max_bodies": f.max_bodies()})
            })
            .collect(),
    ))
}

/// `GET /api/units`: the length units a scene may be drawn in, as the engine reads them: each one's
/// `symbol`, every word read for it (`words`, matched trimmed and with ASCII letters lowered) and the
/// `millimetres` in one unit.
pub(super) async fn units() -> Json<Value> {
    Json(Value::Array(
        Units::known()
            .iter()
            .map(|u| json!({"symbol": u.symbol, "words": u.words, "millimetres": u.millimetres}))
            .collect(),
    ))
}

/// `GET /api/status`: the job table and the limits.
pub(super) async fn status(State(state): State<AppState>) -> Json<Value> {
    let jobs = &state.jobs;
    let limits = jobs.limits();
    Json(json!({
        "version": env!("CARGO_PKG_VERSION"),
        "running": jobs.running(),
        "queued": jobs.waiting(),
        "reading": jobs.reading(),
        "threads": jobs.pool.current_num_threads(),
        "memory_bytes": crate::memory::live_bytes(),
        "limits": {
            "running": limits.running,
            "queued": limits.queued,
            "job_seconds": limits.deadline.as_secs_f64(),
            "body_bytes": MAX_BODY,
            "printed_body_mm": MAX_PRINTED_BODY_MM,
            "body_seconds": super::connections::BODY_READ_TIMEOUT.as_secs_f64(),
            "header_seconds": super::connections::HEADER_READ_TIMEOUT.as_secs_f64(),
            "write_seconds": super::connections::WRITE_TIMEOUT.as_secs_f64(),
            "memory_bytes": limits.memory,
            "joint_steps": linkwright_core::analysis::MAX_JOINT_STEPS,
            "connections": super::connections::MAX_CONNECTIONS,
            "poses_per_body": linkwright_core::limits::MAX_POSES,
            "moving_bodies": linkwright_core::limits::MAX_MOVING_BODIES,
        },
    }))
}

/// The request body read by `parse`, off the async threads and within the job deadline
/// ([`super::jobs::Jobs::read`]): validating a scene or a design is work like any other.
pub(super) async fn parsed<T: Send + 'static>(
    state: &AppState,
    body: Result<Bytes, BytesRejection>,
    parse: fn(&str) -> Result<T, ApiError>,
) -> Result<T, ApiError> {
    let text = body_text(body)?;
    state.jobs.read(move || parse(&text)).await
}

/// The request body as text; a body over [`MAX_BODY`] is a 413.
fn body_text(body: Result<Bytes, BytesRejection>) -> Result<String, ApiError> {
    let bytes = body.map_err(|r| match r.status() {
        StatusCode::PAYLOAD_TOO_LARGE => ApiError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            format!("the request body is larger than the limit of {} bytes", MAX_BODY),
        ),
        status => ApiError::new(status, r.body_text()),
    })?;
    String::from_utf8(bytes.to_vec()).map_err(|_| ApiError::bad_request("the request body is not UTF-8 text"))
}

/// Parses and validates a scene; `prefix` is the request field it sits in (empty for a bare scene).
fn scene_of(text: &str, prefix: &str) -> Result<Problem, ApiError> {
    let scene = Scene::from_json(text).map_err(|e| ApiError::parse("the scene", prefix, &e.path, &e.message))?;
    Problem::new(&scene).map_err(|issues| ApiError::invalid_scene(prefix, &issues))
}

/// The largest body the server builds printable parts or the print pre-check for, millimetres across.
/// Their cost grows with the length of the outlines in millimetres (sampled every few millimetres):
/// parts for a body 100 m across, printed at 1:1, take under 20 s (the garbage truck drawn 315 times
/// as large: `/usr/bin/time linkwright fabricate SCENE DESIGN -o DIR --build model:1:1`), within a
/// job's deadline, while a body far larger can ask for more memory than the computer has, and the
/// failed allocation aborts the process, which no deadline can stop. 100 m is far beyond anything a
/// printer makes.
const MAX_PRINTED_BODY_MM: f64 = 100_000.0;

/// Refuses a scene with a body too large for the print computations ([`MAX_PRINTED_BODY_MM`]).
/// `prefix` is the request field of the scene.
pub(super) fn printable_size(problem: &Problem, settings: &PrintSettings, prefix: &str) -> Result<(), ApiError> {
    // What is printed is the model, at its scale.
    let mm = problem.units.model_millimetres(model_scale(problem, None, settings));
    let across = |points: &mut dyn Iterator<Item = &linkwright_core::geom::Point>| {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            lo = [lo[0].min(p.x), lo[1].min(p.y)];
            hi = [hi[0].max(p.x), hi[1].max(p.y)];
        }
        (hi[0] - lo[0]).max(hi[1] - lo[1]).max(0.0) * mm
    };
    // The fixed bodies are printed as one ground piece; each moving body on its own.
    let ground = across(&mut problem.fixed.iter().flat_map(|p| p.vertices()));
    let largest = problem.bodies.iter().map(|b| across(&mut b.outline.vertices().iter())).fold(ground, f64::max);
    if largest <= MAX_PRINTED_BODY_MM {
        return Ok(());
    }
    let message = format!(
        "a body is {largest:.0} mm across in the printed model; this server makes printable designs of bodies \
         up to {MAX_PRINTED_BODY_MM:.0} mm (100 m) across: check the scene's units and sizes, or choose a smaller \
         model scale (build)"
    );
    let field = if prefix.is_empty() { "units".to_string() } else { format!("{prefix}.units") };
    Err(ApiError::unprocessable(format!("the scene is too large to print: {message}")).with_issue(field, message))
}

/// What a design request carries: the scene, the mechanisms of an earlier design to start from, and
/// the print settings its designs must be printable with.
struct DesignInput {
    problem: Problem,
    previous: Vec<Mechanism>,
    settings: PrintSettings,
    /// Whether the design's motion analysis is wanted with it (`"analysis": true`).
    analysis: bool,
    /// Whether the design follows `from`'s design, as a live redesign does (`"follow": true`): the
    /// design nearest it rather than the cheapest ([`Start::Follow`]).
    follow: bool,
}

impl DesignInput {
    /// A bare `scene/1` document, or `{"scene": scene/1, "from": design/1, "print_settings": {...}}`:
    /// `from` (optional) warm-starts from an earlier design of a similar scene (its mechanism and
    /// alternatives); `print_settings` (optional, as `POST /api/fabricate` takes them) are what the
    /// designs must be printable with (default: the default print settings).
    fn parse(text: &str) -> Result<DesignInput, ApiError> {
        let value: Value = serde_json::from_str(text)
            .map_err(|e| ApiError::bad_request(format!("the body is not valid JSON: {e}")))?;
        let wrapped = value.get("scene").filter(|_| value.get("linkwright").is_none());
        let Some(scene) = wrapped else {
            let problem = scene_of(text, "")?;
            let settings = PrintSettings::default();
            printable_size(&problem, &settings, "")?;
            return Ok(DesignInput { problem, previous: Vec::new(), settings, analysis: false, follow: false });
        };
        let problem = scene_of(&scene.to_string(), "scene")?;
        let settings = print_settings(value.get("print_settings"), "print_settings")?;
        printable_size(&problem, &settings, "scene")?;
        let previous = match value.get("from") {
            None | Some(Value::Null) => Vec::new(),
            Some(from) => {
                let file = DesignFile::from_json(&from.to_string())
                    .map_err(|e| ApiError::parse("the earlier design", "from", &e.path, &e.message))?;
                // Mechanisms that do not fit the scene are left out by the engine; unusable ones here.
                file.usable_mechanisms()
            }
        };
        let flag = |name: &str| match value.get(name) {
            None => Ok(false),
            Some(Value::Bool(b)) => Ok(*b),
            // `null` too: the field is a boolean, and a client sending null has a bug worth hearing of.
            Some(_) => Err(ApiError::bad_request(format!("{name} must be true or false"))
                .with_issue(name, "must be true or false (or left out, for false)")),
        };
        let (analysis, follow) = (flag("analysis")?, flag("follow")?);
        Ok(DesignInput { problem, previous, settings, analysis, follow })
    }

    /// The motion analysis of `file`'s design when it was asked for and there is one.
    fn analysis_of(&self, file: &DesignFile) -> Option<Value> {
        if !self.analysis || file.status != Status::Ok {
            return None;
        }
        analyze(&self.problem, file, Which::Best, &AnalysisOptions::default())
            .ok()
            .and_then(|a| serde_json::to_value(a).ok())
    }

    /// Designs the scene, as a job: it stops at its next check once `flag` is set. Designs start from
    /// the earlier design when there is one, and must be printable (for a printed model).
    fn design(&self, flag: &Arc<StopFlag>, on_progress: impl Fn(&Progress) + Sync) -> Result<DesignFile, ApiError> {
        // The print pre-check is built here, inside the job, not while the request is parsed: for a
        // large scene it is heavy, and it has no cancellation hook, so it must not run on the async
        // threads that answer every other request.
        let plan = BuildPlan::new(&self.problem, &self.settings);
        let start = match (self.previous.is_empty(), self.follow) {
            (true, _) => Start::Cold,
            (false, false) => Start::Warm(&self.previous),
            (false, true) => Start::Follow(&self.previous),
        };
        let options = Options { start, printable: None };
        let observer = JobObserver { flag: flag.clone(), on_progress };
        let (plan, outcome) = plan
            .synthesize(&self.problem, &self.settings, &options, &observer)
            .map_err(|_| ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "the design was cancelled"))?;
        Ok(plan.design_file(&self.problem, &outcome))
    }
}

/// A request that carries a scene and a design, with options.
pub(super) struct Compound {
    pub problem: Problem,
    pub design: DesignFile,
    pub fields: Map<String, Value>,
}

impl Compound {
    pub(super) fn parse(text: &str) -> Result<Compound, ApiError> {
        let value: Value = serde_json::from_str(text)
            .map_err(|e| ApiError::bad_request(format!("the body is not valid JSON: {e}")))?;
        let Value::Object(fields) = value else {
            return Err(ApiError::bad_request("the body must be a JSON object with \"scene\" and \"design\""));
        };
        let member = |name: &str| {
            fields.get(name).ok_or_else(|| {
                ApiError::bad_request(format!("the body has no \"{name}\"")).with_issue(name, "is required")
            })
        };
        let problem = scene_of(&member("scene")?.to_string(), "scene")?;
        let design = DesignFile::from_json(&member("design")?.to_string())
            .map_err(|e| ApiError::parse("the design", "design", &e.path, &e.message))?;
        let issues = design.validate(&problem);
        if let Some(first) = issues.first() {
            let error = format!("the design is not valid: design.{first}");
            let status =
                if first.field == "linkwright" { StatusCode::BAD_REQUEST } else { StatusCode::UNPROCESSABLE_ENTITY };
            let answer = ApiError::new(status, error);
            return Err(answer.listed(&issues, |i| format!("design.{}", i.field), |i| &i.message));
        }
        Ok(Compound { problem, design, fields })
    }

    /// `alternative`: absent or null for the design itself, an index into its alternatives otherwise.
    pub(super) fn which(&self) -> Result<Which, ApiError> {
        match self.fields.get("alternative") {
            None | Some(Value::Null) => Ok(Which::Best),
            Some(v) => v.as_u64().and_then(|i| usize::try_from(i).ok()).map(Which::Alternative).ok_or_else(|| {
                ApiError::bad_request("alternative must be null or an index into design.alternatives")
                    .with_issue("alternative", "must be null or a non-negative integer")
            }),
        }
    }

    /// An optional yes-or-no option (absent or null: no).
    pub(super) fn flag(&self, name: &str) -> Result<bool, ApiError> {
        flag(&self.fields, name)
    }

    /// An optional positive integer option, at most `max`.
    fn count(&self, name: &str, default: usize, max: usize) -> Result<usize, ApiError> {
        match self.fields.get(name) {
            None | Some(Value::Null) => Ok(default),
            Some(v) => v.as_u64().filter(|&n| n >= 1 && n <= max as u64).map(|n| n as usize).ok_or_else(|| {
                let message = format!("must be an integer from 1 to {max}");
                ApiError::bad_request(format!("{name} {message}")).with_issue(name, message)
            }),
        }
    }

    /// The mechanism asked for, simulated in `steps` crank steps.
    fn replay(&self, steps: usize) -> Result<Replay, ApiError> {
        Replay::new(&self.problem, &self.design, self.which()?, steps)
            .map_err(|e| unreplayable("the design cannot be shown", &e))
    }

    /// The mechanism asked for, simulated in `steps` crank steps, or in as many as a linkage of its
    /// joints may have when that is fewer (for a picture, whose fineness nobody asked for).
    fn replay_up_to(&self, steps: usize) -> Result<Replay, ApiError> {
        let which = self.which()?;
        match Replay::new(&self.problem, &self.design, which, steps) {
            Err(AnalysisError::TooManySteps { most, .. }) => Replay::new(&self.problem, &self.design, which, most),
            replayed => replayed,
        }
        .map_err(|e| unreplayable("the design cannot be shown", &e))
    }
}

/// A 422 for a design that cannot be replayed, under the field at fault: `steps` when more were asked
/// for than its joints allow, `design` otherwise.
fn unreplayable(what: &str, e: &AnalysisError) -> ApiError {
    let field = if matches!(e, AnalysisError::TooManySteps { .. }) { "steps" } else { "design" };
    ApiError::unprocessable(format!("{what}: {e}")).with_issue(field, e.to_string())
}

/// `POST /api/design`: scene/1 (or `{scene, from}`) in, design/1 out (a `no_solution` design is a 200
/// too).
pub(super) async fn design(
    State(state): State<AppState>,
    Client(client): Client,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<DesignFile>, ApiError> {
    let input = parsed(&state, body, DesignInput::parse).await?;
    let file = state.jobs.run(Kind::Design, &client, Work::DESIGN, move |flag| input.design(flag, |_| {})).await?;
    Ok(Json(file))
}

/// What the design stream says, in order: accepted, maybe queued, started, progress..., then one of
/// design, cancelled, error.
enum Note {
    Accepted(Vec<Value>),
    Queued,
    Started,
    Progress(Progress),
    Analysis(Value),
    Design(Box<DesignFile>),
    Cancelled(&'static str),
    Failed(String),
}

impl Note {
    fn is_final(&self) -> bool {
        matches!(self, Note::Design(_) | Note::Cancelled(_) | Note::Failed(_))
    }
    fn event(&self) -> Event {
        let (name, data) = match self {
            Note::Accepted(warnings) => ("accepted", json!({ "warnings": warnings })),
            Note::Queued => ("queued", json!({"message": "waiting for a free slot"})),
            Note::Started => ("started", json!({})),
            Note::Progress(p) => ("progress", serde_json::to_value(p).unwrap_or(Value::Null)),
            Note::Analysis(a) => ("analysis", a.clone()),
            Note::Design(d) => ("design", serde_json::to_value(d.as_ref()).unwrap_or(Value::Null)),
            Note::Cancelled(reason) => ("cancelled", json!({ "reason": reason })),
            Note::Failed(error) => ("error", json!({ "error": error })),
        };
        Event::default().event(name).data(data.to_string())
    }
}

/// `POST /api/design/stream`: the same job as `/api/design`, answered as server-sent events. Closing
/// the connection cancels the job.
pub(super) async fn design_stream(
    State(state): State<AppState>,
    Client(client): Client,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    let input = parsed(&state, body, DesignInput::parse).await?;
    let warnings: Vec<Value> =
        input.problem.warnings.iter().filter_map(|w| serde_json::to_value(issue_json("", w)).ok()).collect();
    let ticket = state.jobs.admit(Kind::Design, &client)?;
    let flag = ticket.flag.clone();
    let (tx, rx) = mpsc::channel::<Note>(64);
    let jobs = state.jobs.clone();
    tokio::spawn(async move {
        let _ = tx.send(Note::Accepted(warnings)).await;
        if !ticket.can_start_now() {
            let _ = tx.send(Note::Queued).await;
        }
        let flag = ticket.flag.clone();
        let deadline = jobs.limits().deadline;
        let running = match ticket.start_within(deadline).await {
            Ok(running) => running,
            Err(end) => {
                let _ = tx.send(ended_note(end, deadline)).await;
                return;
            }
        };
        let _ = tx.send(Note::Started).await;
        let progress_tx = tx.clone();
        let on_progress = move |p: &Progress| {
            // A lagging client misses a report, never blocks the run.
            let _ = progress_tx.try_send(Note::Progress(*p));
        };
        let result = jobs
            .execute(running, flag.clone(), move |flag| {
                let file = input.design(flag, on_progress)?;
                let analysis = input.analysis_of(&file);
                Ok::<_, ApiError>((file, analysis))
            })
            .await;
        let note = match (result, flag.reason()) {
            (Ok(Ok((file, analysis))), _) => {
                if let Some(analysis) = analysis {
                    let _ = tx.send(Note::Analysis(analysis)).await;
                }
                Note::Design(Box::new(file))
            }
            (Ok(Err(_)), Some(reason)) => ended_note(JobEnd::Stopped(reason), deadline),
            (Ok(Err(e)), None) => Note::Failed(e.error),
            (Err(end), _) => ended_note(end, deadline),
        };
        let _ = tx.send(note).await;
    });
    let stream = futures_util::stream::unfold((rx, StopOnDrop(flag), false), |(mut rx, guard, done)| async move {
        if done {
            return None;
        }
        let note = rx.recv().await?;
        let last = note.is_final();
        Some((Ok::<Event, Infallible>(note.event()), (rx, guard, last)))
    });
    Ok(Sse::new(stream).keep_alive(KeepAlive::new().interval(Duration::from_secs(1))).into_response())
}

/// The last event of a design job that ended without a design: `cancelled` when the client replaced it
/// or left, `error` (with what to change) when it ran out of time or failed.
fn ended_note(end: JobEnd, deadline: Duration) -> Note {
    match end {
        JobEnd::Stopped(StopReason::Superseded) => Note::Cancelled("superseded by a newer design request"),
        JobEnd::Stopped(StopReason::ClientGone) => Note::Cancelled("cancelled"),
        end => Note::Failed(Work::DESIGN.error(end, deadline).error),
    }
}

/// `POST /api/check`: `{scene, design}` in, `{ok, violations}` out.
pub(super) async fn check(
    State(state): State<AppState>,
    Client(client): Client,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<Value>, ApiError> {
    let request = parsed(&state, body, Compound::parse).await?;
    let check = move |_: &Arc<StopFlag>| Ok(request.design.violations(&request.problem));
    let violations = state.jobs.run(Kind::Analysis, &client, Work::CHECK, check).await?;
    Ok(Json(json!({"ok": violations.is_empty(), "violations": violations})))
}

/// `POST /api/simulate`: `{scene, design, alternative?, steps?}` in, the motion analysis out.
pub(super) async fn simulate(
    State(state): State<AppState>,
    Client(client): Client,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<Value>, ApiError> {
    let request = parsed(&state, body, Compound::parse).await?;
    let which = request.which()?;
    let steps = request.count("steps", AnalysisOptions::default().steps, MAX_STEPS)?;
    let simulation = move |_: &Arc<StopFlag>| {
        analyze(&request.problem, &request.design, which, &AnalysisOptions::default().with_steps(steps))
            .map(|a| serde_json::to_value(a).unwrap_or(Value::Null))
            .map_err(|e| unreplayable("the design cannot be simulated", &e))
    };
    let analysis = state.jobs.run(Kind::Analysis, &client, Work::SIMULATION, simulation).await?;
    Ok(Json(analysis))
}

/// `POST /api/balance`: `{scene, design, alternative?, steps?}` in: the torque the crank needs along the
/// motion (the printed model's parts at the design's scale, with the default settings; or a full-size
/// build's real masses: the scene's `mass_kg`, `material` and `thickness`), the
/// counterbalance springs and the torque with them, at the rows of `/api/simulate`'s frames for the
/// same `steps`.
pub(super) async fn balance(
    State(state): State<AppState>,
    Client(client): Client,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<Value>, ApiError> {
    let request = parsed(&state, body, Compound::parse).await?;
    let masses = Masses::for_design(&request.problem, Some(&request.design), &PrintSettings::default())
        .map_err(|e| ApiError::unprocessable(e.to_string()).with_issue("scene", e.to_string()))?;
    let steps = request.count("steps", AnalysisOptions::default().steps, MAX_STEPS)?;
    let work = move |flag: &Arc<StopFlag>| {
        let replay = request.replay(steps)?;
        counterbalanced(&request.problem, &replay, &masses, flag).map(|(_, answer)| answer)
    };
    let answer = state.jobs.run(Kind::Analysis, &client, Work::BALANCE, work).await?;
    Ok(Json(answer))
}

/// The torque `replay`'s motion needs with `masses` and the springs that lower its peak: the springs,
/// and both as `POST /api/balance` answers them. The search stops when the job does (its deadline, or
/// the client gone): the answer then says why (`Jobs::run`).
pub(super) fn counterbalanced(
    problem: &Problem,
    replay: &Replay,
    masses: &Masses,
    flag: &Arc<StopFlag>,
) -> Result<(Balance, Value), ApiError> {
    let torque = replay.torque(problem, masses).map_err(|e| {
        ApiError::unprocessable(format!("the torque cannot be computed: {e}")).with_issue("design", e.to_string())
    })?;
    let observer = JobObserver { flag: flag.clone(), on_progress: |_: &Progress| {} };
    let balance = replay
        .balancing(problem, masses, &torque)
        .best(SpringSearch::ANALYSIS, &observer)
        .map_err(|_| ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "the spring search was cancelled"))?;
    let answer = serde_json::to_value(Balanced { torque: &torque, balance: &balance }).unwrap_or(Value::Null);
    Ok((balance, answer))
}

/// `POST /api/edit`: `{scene, design, alternative?, joints: {name: [x, y], ...}}` in: the design with
/// those joints moved (first-pose places), re-derived ([`DesignFile::with_joints_moved`]), its
/// violations and its motion analysis out; or, when the moved linkage no longer makes the motion,
/// which check it fails and what to do.
pub(super) async fn edit(
    State(state): State<AppState>,
    Client(client): Client,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<Value>, ApiError> {
    let request = parsed(&state, body, Compound::parse).await?;
    let alternative = match request.which()? {
        Which::Best => None,
        Which::Alternative(i) => Some(i),
    };
    let moves = joint_places(request.fields.get("joints"))?;
    let edit = move |_: &Arc<StopFlag>| match request.design.with_joints_moved(&request.problem, alternative, &moves) {
        Ok(design) => {
            let violations = design.violations(&request.problem);
            let analysis = analyze(&request.problem, &design, Which::Best, &AnalysisOptions::default())
                .map(|a| serde_json::to_value(a).unwrap_or(Value::Null))
                .unwrap_or(Value::Null);
            Ok(json!({"design": design, "violations": violations, "analysis": analysis, "rejected": null}))
        }
        Err(EditError::Rejected(reject)) => {
            let (check, message) = rejected_words(reject);
            Ok(json!({"design": null, "violations": [], "analysis": null,
                      "rejected": {"check": check, "message": message}}))
        }
        Err(e) => {
            Err(ApiError::unprocessable(format!("the joints cannot be moved: {e}")).with_issue("joints", e.to_string()))
        }
    };
    let answer = state.jobs.run(Kind::Analysis, &client, Work::SIMULATION, edit).await?;
    Ok(Json(answer))
}

/// `joints` of an edit: an object of joint names to `[x, y]`.
fn joint_places(value: Option<&Value>) -> Result<BTreeMap<String, Point>, ApiError> {
    let bad = |message: &str| ApiError::bad_request(format!("joints: {message}")).with_issue("joints", message);
    let Some(Value::Object(joints)) = value else {
        return Err(bad("must be an object of joint names to [x, y]"));
    };
    joints
        .iter()
        .map(|(name, v)| match v.as_array().map(|a| a.iter().map(Value::as_f64).collect::<Vec<_>>()).as_deref() {
            Some([Some(x), Some(y)]) => Ok((name.clone(), Point::new(*x, *y))),
            _ => Err(bad(&format!("{name} must be [x, y], two numbers"))),
        })
        .collect()
}

/// What the app says of a moved linkage that fails a kinematic check: the check's word and what to do.
fn rejected_words(reject: Reject) -> (&'static str, &'static str) {
    match reject {
        Reject::JointsTooClose => {
            ("joints_too_close", "two joints of one part are too close to build: move them apart")
        }
        Reject::Order => {
            ("order", "the crank can no longer pass the poses in order: move the joint back, or towards where it was")
        }
        Reject::Branch => {
            ("branch", "the linkage would have to be taken apart between two poses: move the joint back a little")
        }
        Reject::Assembly => (
            "assembly",
            "the linkage locks up before it reaches the last pose: a link is too short or too long for the motion",
        ),
        Reject::MissedPose => ("missed_pose", "the body no longer reaches a pose it must hit: move the joint back"),
        Reject::Transmission => ("transmission", "a link comes too close to a dead point: move the joint back"),
        Reject::AvoidRegion => ("avoid_region", "a link enters an avoid region: move the joint away from it"),
        Reject::Collision => ("collision", "a part hits another: move the joint away from it"),
        Reject::Unprintable => ("unprintable", "the linkage cannot be printed: move the joints apart"),
        Reject::Outclassed => ("outclassed", "the linkage costs more than the designs kept"),
    }
}

/// `POST /api/render`: `{scene, design, alternative?, kind: "design" | "animation", seconds?}` in,
/// the picture (SVG) out, as a download.
pub(super) async fn render(
    State(state): State<AppState>,
    Client(client): Client,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    let request = parsed(&state, body, Compound::parse).await?;
    let kind = match request.fields.get("kind").and_then(Value::as_str).unwrap_or("animation") {
        "design" => "design",
        "animation" => "animation",
        other => {
            let message = format!("\"{other}\" is not a picture; use \"design\" or \"animation\"");
            return Err(ApiError::bad_request(format!("kind: {message}")).with_issue("kind", message));
        }
    };
    let seconds = match request.fields.get("seconds") {
        None | Some(Value::Null) => 3.0,
        Some(v) => v.as_f64().filter(|s| s.is_finite() && *s > 0.0 && *s <= 600.0).ok_or_else(|| {
            ApiError::bad_request("seconds must be a number of seconds from 0 to 600")
                .with_issue("seconds", "must be a number from 0 to 600")
        })?,
    };
    let picture = move |_: &Arc<StopFlag>| {
        let replay = request.replay_up_to(720)?;
        let input = RenderInput {
            problem: &request.problem,
            mechanism: &replay.mechanism,
            trace: &replay.trace,
            pose_steps: &replay.pose_rows,
        };
        Ok(if kind == "design" { design_svg(&input) } else { animation_svg(&input, seconds) })
    };
    let svg = state.jobs.run(Kind::Analysis, &client, Work::PICTURE, picture).await?;
    let disposition = format!("attachment; filename=\"{kind}.svg\"");
    Ok(([(header::CONTENT_TYPE, "image/svg+xml".to_string()), (header::CONTENT_DISPOSITION, disposition)], svg)
        .into_response())
}

/// The print settings in request field `name`: absent or null for the defaults, otherwise an object
/// whose missing fields keep their defaults. Every problem is named by its field.
pub(super) fn print_settings(value: Option<&Value>, name: &str) -> Result<PrintSettings, ApiError> {
    let Some(value) = value.filter(|v| !v.is_null()) else { return Ok(PrintSettings::default()) };
    if !value.is_object() {
        let message = "must be an object of print settings in millimetres (GET /api/fabricate/settings lists them)";
        return Err(ApiError::bad_request(format!("{name} {message}")).with_issue(name, message));
    }
    let settings = PrintSettings::from_json(&value.to_string()).map_err(|e| {
        let field = join_field(name, &e.field);
        // The position is in the text re-serialised here, not in anything the client sent.
        let message = e.message.split(" at line ").next().unwrap_or_default();
        ApiError::bad_request(format!("print settings: {field}: {message}")).with_issue(field, message)
    })?;
    let issues = settings.validate();
    let Some(first) = issues.first() else { return Ok(settings) };
    let field = |path: &str| join_field(name, path);
    let error = match issues.len() {
        1 => format!("print settings: {}: {}", field(&first.field), first.message),
        n => format!("print settings have {n} problems; the first: {}: {}", field(&first.field), first.message),
    };
    Err(issues.iter().fold(ApiError::bad_request(error), |e, i| e.with_issue(field(&i.field), &i.message)))
}

/// The boolean option `name` of a request's `fields`: false when absent.
fn flag(fields: &Map<String, Value>, name: &str) -> Result<bool, ApiError> {
    match fields.get(name) {
        None => Ok(false),
        Some(Value::Bool(b)) => Ok(*b),
        // `null` too: the field is a boolean, and a client sending null has a bug worth hearing of.
        Some(_) => Err(ApiError::bad_request(format!("{name} must be true or false"))
            .with_issue(name, "must be true or false (or left out, for false)")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flag_is_a_boolean_or_absent_and_null_is_refused() {
        let fields = |v: Value| json!({ "springs": v }).as_object().cloned().unwrap();
        assert!(!flag(&Map::new(), "springs").unwrap());
        assert!(flag(&fields(json!(true)), "springs").unwrap());
        for bad in [Value::Null, json!("true"), json!(1)] {
            let refused = flag(&fields(bad), "springs").unwrap_err();
            assert_eq!((refused.status, refused.issues[0].field.as_str()), (StatusCode::BAD_REQUEST, "springs"));
        }
    }
}
