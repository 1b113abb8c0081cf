//! `POST /api/fabricate` and its downloads: printable parts for a design (or, for a full-size build,
//! the workshop's files), made as a bounded heavy job. The files stay in memory (see
//! [`super::bundles`]); the answer lists them with the report and, for printed parts, what the 3D
//! preview needs.

use super::api::{counterbalanced, parsed, print_settings, printable_size, AppState, Client, Compound};
use super::bundles::{media_type, Stored, ZIP_NAME};
use super::error::ApiError;
use super::jobs::JobObserver;
use super::jobs::{Kind, StopFlag, Work};
use super::preview::{preview, Preview};
use axum::body::Bytes;
use axum::extract::rejection::{BytesRejection, PathRejection};
use axum::extract::{Path, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use linkwright_core::analysis::{Replay, Which};
use linkwright_core::balance::Balanced;
use linkwright_core::fab::{
    bundle, fabricate_design_or_alternative, sanitize, Chosen, FabError, PrintSettings, Report,
};
use linkwright_core::hooked::{fabricate_with_springs, Hooked, HookedError};
use linkwright_core::statics::Masses;
use linkwright_core::workshop::{self, SpringOrder, Workshop, WorkshopSettings};
use linkwright_core::{Build, DesignFile, Material, Problem, Progress};
use serde::Serialize;
use serde_json::Value;
use std::sync::Arc;

/// What a fabrication request asks for, checked.
struct Request {
    problem: Problem,
    /// The design to fabricate: the request's design, or a view of the alternative it names.
    design: DesignFile,
    /// What [`Answer::used`] adds to the number of the design that was fabricated: 0 for the design
    /// itself, `i + 1` when the request names `alternatives[i]`.
    offset: usize,
    settings: PrintSettings,
    /// Whether to search extension springs and give the parts hooks for them.
    springs: bool,
}

impl Request {
    /// `{scene, design, settings?, alternative?, springs?}`.
    fn parse(text: &str) -> Result<Request, ApiError> {
        let compound = Compound::parse(text)?;
        let settings = print_settings(compound.fields.get("settings"), "settings")?;
        let which = compound.which()?;
        let springs = compound.flag("springs")?;
        let Compound { problem, mut design, .. } = compound;
        printable_size(&problem, &settings, "scene")?;
        if design.mechanism.is_none() {
            let message = "the design has no linkage to fabricate (it found no solution): design one first";
            return Err(ApiError::unprocessable(message).with_issue("design.mechanism", message));
        }
        let (offset, design) = match which {
            Which::Best => (0, design),
            Which::Alternative(i) if i < design.alternatives.len() => {
                let alternative = design.alternatives.swap_remove(i);
                let view = DesignFile {
                    mechanism: Some(alternative.mechanism),
                    motion: Some(alternative.motion),
                    metrics: Some(alternative.metrics),
                    alternatives: Vec::new(),
                    ..design
                };
                (i + 1, view)
            }
            Which::Alternative(i) => {
                let message = format!("the design has {} alternatives; there is no [{i}]", design.alternatives.len());
                return Err(
                    ApiError::unprocessable(format!("alternative: {message}")).with_issue("alternative", message)
                );
            }
        };
        Ok(Request { problem, design, offset, settings, springs })
    }

    /// Fabricates and bundles the design (or its first alternative that can be fabricated; with
    /// springs, the design itself, whose parts they hook on); for a full-size build, plans it.
    fn make(&self, flag: &Arc<StopFlag>) -> Result<Made, ApiError> {
        if let Build::Full(material) = self.problem.build {
            return self.plan(material, flag);
        }
        let (chosen, balance) = if self.springs {
            // The spring search stops with the job (its deadline, or the client gone).
            let observer = JobObserver { flag: flag.clone(), on_progress: |_: &Progress| {} };
            let hooked = fabricate_with_springs(&self.problem, &self.design, &self.settings, &observer).map_err(
                |e| match e {
                    HookedError::Fab(e) => cannot(e),
                    HookedError::Cancelled => {
                        ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "the spring search was cancelled")
                    }
                    HookedError::Statics(_) => {
                        ApiError::unprocessable(e.to_string()).with_issue("design", e.to_string())
                    }
                    HookedError::NoRoomForSprings => {
                        ApiError::unprocessable(format!("cannot fabricate this design with springs: {e}"))
                            .with_issue("springs", e.to_string())
                    }
                },
            )?;
            let Hooked { fabrication, torque, balance } = hooked;
            let balance = serde_json::to_value(Balanced { torque: &torque, balance: &balance }).unwrap_or(Value::Null);
            (Chosen { used: 0, fabrication, passed_over: None }, Some(balance))
        } else {
            let chosen =
                fabricate_design_or_alternative(&self.problem, &self.design, &self.settings).map_err(cannot)?;
            (chosen, None)
        };
        let (which, fab) = (chosen.used, chosen.fabrication);
        let bundle = bundle(&fab).map_err(cannot)?;
        let preview = preview(&fab);
        let stored = self.stored(bundle.files)?;
        let checks_ok = bundle.report.checks.ok();
        let report = Document::Parts(Box::new(bundle.report));
        Ok(Made { used: self.offset + which, checks_ok, report, preview: Some(preview), stored, balance })
    }

    /// Plans the full-size build in `material` (with springs, the stock extension springs that
    /// counterbalance it are in its bill of materials) and keeps its files.
    fn plan(&self, material: Material, flag: &Arc<StopFlag>) -> Result<Made, ApiError> {
        let (springs, balance) = if self.springs {
            let (orders, balance) = self.counterbalance(flag)?;
            (orders, Some(balance))
        } else {
            (Vec::new(), None)
        };
        let settings = WorkshopSettings { springs, ..WorkshopSettings::default() };
        let plan = workshop::plan(&self.problem, &self.design, material, &settings).map_err(|e| {
            ApiError::unprocessable(format!("cannot plan the full-size build: {e}")).with_issue("design", e.to_string())
        })?;
        let stored = self.stored(workshop::files(&plan))?;
        let checks_ok = plan.links.iter().all(|link| link.checks.iter().all(|check| check.ok));
        let report = Document::Workshop(Box::new(plan));
        Ok(Made { used: self.offset, checks_ok, report, preview: None, stored, balance })
    }

    /// The extension springs that lower the crank's peak torque at the object's real masses, as a
    /// workshop orders them, and the torque and springs as `POST /api/balance` answers them.
    fn counterbalance(&self, flag: &Arc<StopFlag>) -> Result<(Vec<SpringOrder>, Value), ApiError> {
        let problem = &self.problem;
        let unprocessable = |what: &str, field: &str, e: &dyn std::fmt::Display| {
            ApiError::unprocessable(format!("{what}: {e}")).with_issue(field, e.to_string())
        };
        let masses = Masses::for_design(problem, Some(&self.design), &self.settings)
            .map_err(|e| unprocessable("the masses cannot be found", "scene", &e))?;
        let replay = Replay::new(problem, &self.design, Which::Best, crate::springs::ANALYZE_STEPS)
            .map_err(|e| unprocessable("the design cannot be replayed", "design", &e))?;
        let (balance, answer) = counterbalanced(problem, &replay, &masses, flag)?;
        Ok((SpringOrder::from_balance(&balance), answer))
    }

    /// `files` kept in memory under the scene's name.
    fn stored(&self, files: Vec<(String, Vec<u8>)>) -> Result<Stored, ApiError> {
        let mut scene = sanitize(&self.problem.name);
        if scene.is_empty() {
            scene = "linkwright".into();
        }
        Stored::new(scene, files).map_err(|e| {
            ApiError::new(StatusCode::INTERNAL_SERVER_ERROR, format!("internal error: {e}; please report it"))
        })
    }
}

/// What was made: a printed model's `fabrication.json`, or a full-size build's `workshop.json`
/// (their `linkwright` field says which).
#[derive(Serialize)]
#[serde(untagged)]
enum Document {
    Parts(Box<Report>),
    Workshop(Box<Workshop>),
}

/// A design that cannot be fabricated: the library's message says what to change.
fn cannot(e: FabError) -> ApiError {
    let (status, field) = match e {
        FabError::Settings(_) => (StatusCode::BAD_REQUEST, "settings"),
        _ => (StatusCode::UNPROCESSABLE_ENTITY, "design"),
    };
    ApiError::new(status, format!("cannot fabricate this design: {e}")).with_issue(field, e.to_string())
}

/// A finished fabrication, before it is stored.
struct Made {
    used: usize,
    checks_ok: bool,
    report: Document,
    preview: Option<Preview>,
    stored: Stored,
    balance: Option<Value>,
}

/// The answer of `POST /api/fabricate`.
#[derive(Serialize)]
pub(super) struct Answer {
    /// Names the stored files: `GET /api/fabricate/{id}/{name}`.
    id: String,
    /// Which design was fabricated: 0 the design itself, k its `alternatives[k - 1]`.
    used: usize,
    /// True when every fabrication check passed (`report.checks`; for a full-size build, every
    /// strength check of every part).
    checks_ok: bool,
    /// The `fabrication.json` document, or for a full-size build the `workshop.json` one.
    report: Document,
    /// With `springs`: the torque and the springs hooked, as `POST /api/balance` answers them.
    #[serde(skip_serializing_if = "Option::is_none")]
    balance: Option<Value>,
    files: Vec<FileEntry>,
    /// All the files in one zip.
    zip: FileEntry,
    /// The printed parts moving with the linkage (none for a full-size build).
    #[serde(skip_serializing_if = "Option::is_none")]
    preview: Option<Preview>,
}

/// One downloadable file.
#[derive(Serialize)]
struct FileEntry {
    /// The path in the bundle (`parts/crank.stl`).
    name: String,
    media_type: &'static str,
    bytes: usize,
    url: String,
}

/// `POST /api/fabricate`: `{scene, design, settings?, alternative?, springs?}` in; the report, the files
/// to download and the 3D preview out (with `springs: true`, the parts carry hooks for the extension
/// springs that balance them, and `balance` says which).
pub(super) async fn fabricate(
    State(state): State<AppState>,
    Client(client): Client,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<Answer>, ApiError> {
    let request = parsed(&state, body, Request::parse).await?;
    // A client that hangs up while the job waits in line frees its place at once. A running
    // fabrication cannot be stopped midway (the library has no cancellation hook); it finishes, still
    // counted as running, and its answer is dropped.
    let make = move |flag: &Arc<StopFlag>| request.make(flag);
    let made = state.jobs.run(Kind::Fabrication, &client, Work::FABRICATION, make).await?;
    let Made { used, checks_ok, report, preview, stored, balance } = made;
    let (id, stored) = state.bundles.insert(stored);
    let entry = |name: &str, bytes: &Bytes| FileEntry {
        name: name.to_string(),
        media_type: media_type(name),
        bytes: bytes.len(),
        url: format!("/api/fabricate/{id}/{name}"),
    };
    Ok(Json(Answer {
        files: stored.files.iter().map(|(name, bytes)| entry(name, bytes)).collect(),
        zip: entry(ZIP_NAME, &stored.zip),
        checks_ok,
        id,
        used,
        report,
        balance,
        preview,
    }))
}

/// `GET /api/fabricate/{id}/{path}`: one file of a kept fabrication (or `fabrication.zip`), as a
/// download.
pub(super) async fn download(
    State(state): State<AppState>,
    at: Result<Path<(String, String)>, PathRejection>,
) -> Result<Response, ApiError> {
    let Path((id, path)) = at.map_err(|e| ApiError::bad_request(e.body_text()))?;
    let stored = state.bundles.get(&id).ok_or_else(|| {
        ApiError::not_found(format!(
            "no fabrication \"{id}\" is kept (the server keeps the latest {}); fabricate again",
            state.bundles.limits().count
        ))
    })?;
    let (name, bytes) =
        stored.file(&path).ok_or_else(|| ApiError::not_found(format!("fabrication {id} has no file \"{path}\"")))?;
    let headers = [
        (header::CONTENT_TYPE, media_type(&path).to_string()),
        (header::CONTENT_DISPOSITION, format!("attachment; filename=\"{name}\"")),
        // A kept file never changes under its id.
        (header::CACHE_CONTROL, "private, max-age=3600, immutable".to_string()),
    ];
    Ok((headers, bytes).into_response())
}

/// `GET /api/fabricate/settings`: the default print settings, millimetres.
pub(super) async fn default_settings() -> Json<PrintSettings> {
    Json(PrintSettings::default())
}
