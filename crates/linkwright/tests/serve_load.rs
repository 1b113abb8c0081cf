//! The server under load, on this computer only: many clients at once mixing designs of the bundled
//! examples, fabrications, analyses and the app's own files. Every request is answered (200, a 4xx, or
//! 503 when the job queue is full) within its bound, the server's memory stays bounded, and it still
//! answers afterwards.
//!
//! The normal test run uses a short form (`DEFAULT_CLIENTS` clients for `DEFAULT_SECONDS` seconds).
//! A longer run by hand:
//! `LINKWRIGHT_LOAD_CLIENTS=200 LINKWRIGHT_LOAD_SECONDS=600 cargo test -p linkwright --test serve_load -- --nocapture`

mod common;

use common::{example_text, Server};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use ureq::Agent;

const DEFAULT_CLIENTS: usize = 50;
const DEFAULT_SECONDS: u64 = 12;
/// The deadline the server is started with (`--job-seconds`).
const JOB_SECONDS: u64 = 20;
/// How long any one request may take to be answered: a job waits in line at most its deadline and runs
/// at most its deadline; the rest is margin for a slow, shared machine.
const REQUEST_BOUND: Duration = Duration::from_secs(2 * JOB_SECONDS + 20);
/// The server's resident memory may not exceed this (the kept fabrications alone may take 256 MiB).
const MEMORY_BOUND_KIB: u64 = 2 * 1024 * 1024;
/// Requests a client sends at most, so a fast server does not turn the short form into a long one.
const MAX_REQUESTS_PER_CLIENT: usize = 400;
/// Small examples (one moving body), designed with few samples.
const EXAMPLES: [&str; 5] = ["k1_garbage_truck", "k1_table", "k1_sofa_bed", "k1_monitor", "k1_car_roof"];
const SAMPLES: u64 = 300;

fn env_number(name: &str, default: u64) -> u64 {
    match std::env::var(name) {
        Ok(v) => v.trim().parse().unwrap_or_else(|_| panic!("{name}={v:?} is not a whole number")),
        Err(_) => default,
    }
}

fn agent() -> Agent {
    Agent::config_builder().http_status_as_error(false).timeout_global(Some(REQUEST_BOUND)).build().into()
}

/// A bundled example with a small, seeded search.
fn quick(name: &str, seed: u64) -> Value {
    let mut scene: Value = serde_json::from_str(&example_text(name)).unwrap();
    scene["settings"] = json!({"samples": SAMPLES, "seed": seed});
    scene
}

/// One request of the mix, by what it asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Ask {
    Design,
    Fabrication,
    Simulation,
    Page,
    Script,
    Status,
}

/// What one request got: its status and how long it took.
struct Answer {
    ask: Ask,
    status: u16,
    took: Duration,
}

#[test]
fn many_clients_at_once_are_all_answered_in_bounded_time_and_memory() {
    let clients = env_number("LINKWRIGHT_LOAD_CLIENTS", DEFAULT_CLIENTS as u64) as usize;
    let seconds = env_number("LINKWRIGHT_LOAD_SECONDS", DEFAULT_SECONDS);
    let server = Arc::new(Server::start(&["--job-seconds", &JOB_SECONDS.to_string()]));

    // One design to fabricate and simulate, made before the load starts.
    let truck = quick("k1_garbage_truck", 5);
    let mut made = agent().post(server.at("/api/design")).send(truck.to_string()).expect("the server answers");
    assert_eq!(made.status().as_u16(), 200);
    let design: Value = serde_json::from_str(&made.body_mut().read_to_string().unwrap()).unwrap();
    assert_eq!(design["status"], "ok", "{design}");
    let fabrication = Arc::new(json!({"scene": truck, "design": design}).to_string());
    let simulation = Arc::new(json!({"scene": truck, "design": design, "steps": 120}).to_string());

    // The server's memory, sampled while the load runs.
    let done = Arc::new(AtomicBool::new(false));
    let peak_rss = Arc::new(AtomicU64::new(0));
    let sampler = {
        let (server, done, peak_rss) = (server.clone(), done.clone(), peak_rss.clone());
        std::thread::spawn(move || {
            while !done.load(Ordering::SeqCst) {
                if let Some(rss) = server.memory_kib("VmRSS") {
                    peak_rss.fetch_max(rss, Ordering::SeqCst);
                }
                std::thread::sleep(Duration::from_millis(100));
            }
        })
    };

    let answers = Arc::new(Mutex::new(Vec::<Answer>::new()));
    let until = Instant::now() + Duration::from_secs(seconds);
    let workers: Vec<_> = (0..clients)
        .map(|c| {
            let (server, answers) = (server.clone(), answers.clone());
            let (fabrication, simulation) = (fabrication.clone(), simulation.clone());
            std::thread::spawn(move || {
                let agent = agent();
                let id = format!("load{c}");
                for round in 0..MAX_REQUESTS_PER_CLIENT {
                    if Instant::now() >= until {
                        break;
                    }
                    let ask = match (c + round) % 6 {
                        0 => Ask::Design,
                        1 => Ask::Fabrication,
                        2 => Ask::Simulation,
                        3 => Ask::Page,
                        4 => Ask::Script,
                        _ => Ask::Status,
                    };
                    let post = |path: &str, body: String| {
                        agent.post(server.at(path)).header("x-linkwright-client", &id).send(body)
                    };
                    let start = Instant::now();
                    let response = match ask {
                        Ask::Design => {
                            let scene = quick(EXAMPLES[(c + round) % EXAMPLES.len()], (c * 1000 + round) as u64);
                            post("/api/design", scene.to_string())
                        }
                        Ask::Fabrication => post("/api/fabricate", fabrication.to_string()),
                        Ask::Simulation => post("/api/simulate", simulation.to_string()),
                        Ask::Page => agent.get(server.at("/")).call(),
                        Ask::Script => agent.get(server.at("/js/main.js")).call(),
                        Ask::Status => agent.get(server.at("/api/status")).call(),
                    };
                    let status = match response {
                        // The whole body is read, so the time counts the answer's arrival.
                        Ok(mut r) => {
                            let status = r.status().as_u16();
                            let body = r.body_mut().read_to_vec();
                            assert!(body.is_ok(), "{ask:?}: the body of a {status} did not arrive: {body:?}");
                            status
                        }
                        Err(e) => panic!("{ask:?} from client {c} got no answer after {:?}: {e}", start.elapsed()),
                    };
                    let took = start.elapsed();
                    answers.lock().unwrap().push(Answer { ask, status, took });
                    if status == 503 {
                        // The queue is full: wait a little, as the Retry-After asks, rather than hammer.
                        std::thread::sleep(Duration::from_millis(300));
                    }
                }
            })
        })
        .collect();
    for worker in workers {
        worker.join().expect("a client failed (its message is above)");
    }
    done.store(true, Ordering::SeqCst);
    sampler.join().unwrap();

    let answers = answers.lock().unwrap();
    let mut tally: BTreeMap<(Ask, u16), usize> = BTreeMap::new();
    for a in answers.iter() {
        *tally.entry((a.ask, a.status)).or_default() += 1;
    }
    let slowest = answers.iter().map(|a| a.took).max().unwrap_or_default();
    let peak = peak_rss.load(Ordering::SeqCst).max(server.memory_kib("VmHWM").unwrap_or(0));
    eprintln!(
        "{clients} clients, {seconds} s: {} requests, slowest {slowest:?}, peak memory {} MiB; by (request, status): {tally:?}",
        answers.len(),
        peak / 1024
    );

    for a in answers.iter() {
        let expected = match a.ask {
            // Each client sends one request at a time, so none replaces another (no 409).
            Ask::Design | Ask::Fabrication | Ask::Simulation => a.status == 200 || a.status == 503,
            Ask::Page | Ask::Script | Ask::Status => a.status == 200,
        };
        assert!(expected, "{:?} answered {}", a.ask, a.status);
        assert!(a.took <= REQUEST_BOUND, "{:?} took {:?}", a.ask, a.took);
    }
    for ask in [Ask::Design, Ask::Fabrication, Ask::Simulation, Ask::Page] {
        assert!(tally.get(&(ask, 200)).is_some_and(|&n| n > 0), "no {ask:?} succeeded: {tally:?}");
    }
    if cfg!(target_os = "linux") {
        assert!(peak > 0, "the server's memory could not be read from /proc");
    }
    assert!(peak <= MEMORY_BOUND_KIB, "the server used {} MiB", peak / 1024);

    // Alive, and every job over (the queue drains within the bounds).
    let start = Instant::now();
    loop {
        let mut response = agent().get(server.at("/api/status")).call().expect("the server answers after the load");
        assert_eq!(response.status().as_u16(), 200);
        let status: Value = serde_json::from_str(&response.body_mut().read_to_string().unwrap()).unwrap();
        if status["running"] == 0 && status["queued"] == 0 {
            break;
        }
        assert!(start.elapsed() < REQUEST_BOUND, "jobs still running after the load: {status}");
        std::thread::sleep(Duration::from_millis(100));
    }
}
