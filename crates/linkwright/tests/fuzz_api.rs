//! Fuzzing of the HTTP API: mutated request bodies for every route that takes one (scenes for designs,
//! `{scene, design}` for the check, the analysis, the torque and springs, the picture and fabrication
//! with its print settings), built from a real design of the garbage truck, sent to a running server.
//! Every request must be answered with a 200 whose numbers are all finite, a 4xx that names the
//! problem, or a 503, within its bound, and the server must stay up.
//!
//! CI runs it for a short budget; by hand, run it long:
//! `LINKWRIGHT_FUZZ_SECONDS=3600 LINKWRIGHT_FUZZ_SEED=7 cargo test --release -p linkwright --test fuzz_api`.
//! A failing request body is written to `target/tmp/fuzz-failures/`.

mod common;
#[path = "../../linkwright-core/tests/fuzz/mod.rs"]
mod fuzz;

use common::{quick_garbage_truck, Server};
use fuzz::{budget, keep_failure, mutate, non_finite, Rng};
use serde_json::{json, Value};
use std::time::{Duration, Instant};
use ureq::Agent;

/// The longest answer accepted: the server's own job deadline (set to 10 s below) plus the wait for a
/// slot and the reading of the body, on a slow shared machine.
const ANSWER_BOUND: Duration = Duration::from_secs(60);

const ROUTES: [&str; 6] =
    ["/api/design", "/api/check", "/api/simulate", "/api/balance", "/api/render", "/api/fabricate"];

fn agent() -> Agent {
    Agent::config_builder().http_status_as_error(false).timeout_global(Some(ANSWER_BOUND)).build().into()
}

/// Posts `body` to `route`; the status, or what went wrong.
fn send(server: &Server, route: &str, body: &str) -> Result<u16, String> {
    let started = Instant::now();
    let response = agent()
        .post(server.at(route))
        .header("content-type", "application/json")
        .header("x-linkwright-client", "fuzzer")
        .send(body)
        .map_err(|e| format!("no answer: {e}"))?;
    let status = response.status().as_u16();
    let mut response = response;
    let text = response.body_mut().read_to_string().unwrap_or_default();
    if started.elapsed() > ANSWER_BOUND {
        return Err(format!("answered after {:?}", started.elapsed()));
    }
    match status {
        // A picture is SVG; every other answer is JSON.
        200 => match serde_json::from_str::<Value>(&text).ok().and_then(|answer| non_finite(&answer)) {
            Some(path) => Err(format!("a number that is not finite at {path}: {text:.2000}")),
            None => Ok(status),
        },
        503 => Ok(status),
        400..=499 => {
            let answer: Value =
                serde_json::from_str(&text).map_err(|_| format!("{status} without a JSON error: {text}"))?;
            if answer["error"].as_str().is_some_and(|e| !e.is_empty()) {
                Ok(status)
            } else {
                Err(format!("{status} without a message: {text}"))
            }
        }
        _ => Err(format!("status {status}: {text}")),
    }
}

#[test]
fn mutated_requests_are_answered_and_the_server_lives_on() {
    let (duration, seed) = budget();
    let server = Server::start(&["--job-seconds", "10"]);
    let mut scene = quick_garbage_truck(2000, 3);
    scene["gravity"] = json!([0.0, -1.0]);
    let design: Value = {
        let mut response = agent().post(server.at("/api/design")).send(scene.to_string()).unwrap();
        serde_json::from_str(&response.body_mut().read_to_string().unwrap()).unwrap()
    };
    assert_eq!(design["status"], "ok", "{design}");
    let compound = json!({"scene": scene, "design": design}).to_string();
    let settings =
        agent().get(server.at("/api/fabricate/settings")).call().unwrap().body_mut().read_to_string().unwrap();
    let settings: Value = serde_json::from_str(&settings).unwrap();
    // The print settings and the gravity the torques and springs are computed with, to be mutated too.
    let made = json!({"scene": scene, "design": design, "settings": settings, "springs": true}).to_string();
    let mut rng = Rng::new(seed);
    let started = Instant::now();
    let mut statuses = std::collections::BTreeMap::new();
    let mut cases = 0usize;
    while cases < 20 || started.elapsed() < duration {
        let route = *rng.pick(&ROUTES);
        let original = match route {
            "/api/design" => scene.to_string(),
            "/api/fabricate" => made.clone(),
            _ => compound.clone(),
        };
        let body = mutate(&original, &mut rng);
        match send(&server, route, &body) {
            Ok(status) => *statuses.entry(status).or_insert(0usize) += 1,
            Err(what) => {
                let path = keep_failure(&format!("api-seed{seed}-case{cases}.json"), &body);
                panic!("case {cases} of seed {seed}, POST {route}: {what}; the body is in {}", path.display());
            }
        }
        cases += 1;
    }
    let status = agent().get(server.at("/api/status")).call().expect("the server is still up").status();
    assert_eq!(status.as_u16(), 200);
    let seconds = started.elapsed().as_secs_f64();
    eprintln!("{cases} mutated requests in {seconds:.1} s, seed {seed}, answers by status {statuses:?}");
}
