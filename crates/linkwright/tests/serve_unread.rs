//! Clients that ask for large answers and never read them: answers are bounded in size, an unread one
//! is dropped with its connection after the write timeout, and past its memory budget the server
//! refuses work instead of growing, so it outlives its clients under an address-space limit.
//!
//! The load test's client count and spacing can be changed by hand:
//! `LINKWRIGHT_UNREAD_CLIENTS=256 cargo test --release -p linkwright --test serve_unread -- --nocapture`

mod common;

use common::{quick_garbage_truck, Server};
use serde_json::{json, Value};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use ureq::Agent;

/// Dyads stacked on the design's linkage, each one joint and two links: 116 joints and 228 parts in
/// all (a four-bar's 4 and 4), a valid one-degree-of-freedom design whose every joint a simulation
/// reports.
const DYADS: usize = 112;
/// The address space the server may take in the load test (as `ulimit -v`, KiB): 6 GiB.
const ADDRESS_SPACE_KIB: u64 = 6 * 1024 * 1024;

fn agent() -> Agent {
    Agent::config_builder().http_status_as_error(false).timeout_global(Some(Duration::from_secs(120))).build().into()
}

fn post(server: &Server, path: &str, body: &Value) -> (u16, Value) {
    let mut response = agent().post(server.at(path)).send(body.to_string()).expect("the server answers");
    let text = response.body_mut().with_config().limit(64 << 20).read_to_string().expect("a text body");
    (response.status().as_u16(), serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text:.200}")))
}

fn status(server: &Server) -> Value {
    let mut response = agent().get(server.at("/api/status")).call().expect("the server answers");
    assert_eq!(response.status().as_u16(), 200);
    serde_json::from_str(&response.body_mut().read_to_string().unwrap()).unwrap()
}

/// A scene and a design of it with [`DYADS`] dyads stacked on its linkage: each new joint hangs from
/// the crank's tip and a joint of the body by two links of its own.
fn many_joint_design(server: &Server) -> (Value, Value) {
    let scene = quick_garbage_truck(300, 1);
    let (code, mut design) = post(server, "/api/design", &scene);
    assert_eq!(code, 200, "{design}");
    let mechanism = &mut design["mechanism"];
    let tip = mechanism["driver"]["tip"].as_str().unwrap().to_string();
    let parts = mechanism["parts"].as_array().unwrap();
    let body = parts.iter().find(|p| p["kind"] == "body").unwrap();
    let on_body = body["joints"].as_array().unwrap().iter().map(|j| j.as_str().unwrap()).find(|&j| j != tip);
    let on_body = on_body.unwrap().to_string();
    let at = |name: &str| {
        let p = &mechanism["joints"][name];
        (p[0].as_f64().unwrap(), p[1].as_f64().unwrap())
    };
    let ((ax, ay), (bx, by)) = (at(&tip), at(&on_body));
    for k in 0..DYADS {
        // Off the line through the two, a little farther each time: no two joints coincide and no dyad
        // is stretched straight.
        let off = 0.3 + 0.002 * k as f64;
        let joint = format!("x{k}");
        mechanism["joints"][&joint] = json!([(ax + bx) / 2.0 - off * (by - ay), (ay + by) / 2.0 + off * (bx - ax)]);
        let parts = mechanism["parts"].as_array_mut().unwrap();
        parts.push(json!({"name": format!("a{k}"), "kind": "link", "joints": [tip, joint]}));
        parts.push(json!({"name": format!("b{k}"), "kind": "link", "joints": [on_body, joint]}));
    }
    design["alternatives"] = json!([]);
    (scene, design)
}

/// The most steps a simulation of `joints` joints may ask for, as `/api/status`'s limits say.
fn most_steps(server: &Server, joints: usize) -> usize {
    let limit = status(server)["limits"]["joint_steps"].as_u64().unwrap() as usize;
    (limit / joints).min(5000)
}

#[test]
fn a_simulation_answer_is_bounded_whatever_the_design() {
    let server = Server::start(&[]);
    let (scene, design) = many_joint_design(&server);
    let joints = design["mechanism"]["joints"].as_object().unwrap().len();
    assert_eq!((joints, design["mechanism"]["parts"].as_array().unwrap().len()), (116, 228));
    // At the most steps an analysis takes, this design once answered about 60 MB.
    let (code, body) = post(&server, "/api/simulate", &json!({"scene": scene, "design": design, "steps": 5000}));
    assert_eq!(code, 422, "{body:.300}");
    let most = most_steps(&server, joints);
    assert!(body["issues"][0]["field"] == "steps", "{body}");
    assert!(body["error"].as_str().unwrap().contains(&format!("at most {most} steps")), "{body}");

    let request = json!({"scene": scene, "design": design, "steps": most});
    let mut response = agent().post(server.at("/api/simulate")).send(request.to_string()).unwrap();
    assert_eq!(response.status().as_u16(), 200);
    let bytes = response.body_mut().with_config().limit(64 << 20).read_to_vec().unwrap();
    assert!(bytes.len() < 6 << 20, "{} bytes", bytes.len());
    let answer: Value = serde_json::from_slice(&bytes).unwrap();
    assert!(answer.as_object().is_some_and(|a| !a.is_empty()));

    // A picture asks for no steps: it is drawn in as many as the design may have.
    let request = json!({"scene": scene, "design": design, "kind": "animation"});
    let mut response = agent().post(server.at("/api/render")).send(request.to_string()).unwrap();
    assert_eq!(response.status().as_u16(), 200);
    let svg = response.body_mut().with_config().limit(64 << 20).read_to_string().unwrap();
    assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"), "{svg:.200}");
}

/// `linkwright serve` under an address-space limit (a shell's `ulimit -v`), printing its URL first.
fn server_with_address_space(kib: u64) -> Server {
    let script = format!("ulimit -v {kib} && exec \"$0\" serve --port 0 --threads 2");
    let child = Command::new("sh")
        .args(["-c", &script, env!("CARGO_BIN_EXE_linkwright")])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("sh starts");
    Server::from_child(child)
}

/// Sends `body` as a POST to `path` and never reads the answer.
fn send_and_never_read(host: &str, path: &str, body: &str) -> Option<TcpStream> {
    let mut stream = TcpStream::connect(host).ok()?;
    let head = format!(
        "POST {path} HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n",
        body.len()
    );
    stream.write_all(head.as_bytes()).ok()?;
    stream.write_all(body.as_bytes()).ok()?;
    Some(stream)
}

#[cfg(target_os = "linux")]
#[test]
fn clients_that_never_read_their_answers_do_not_take_the_server_down() {
    let clients: usize = std::env::var("LINKWRIGHT_UNREAD_CLIENTS").map_or(256, |v| v.parse().unwrap());
    let server = server_with_address_space(ADDRESS_SPACE_KIB);
    let (scene, design) = many_joint_design(&server);
    let joints = design["mechanism"]["joints"].as_object().unwrap().len();
    let most = most_steps(&server, joints);
    let budget = status(&server)["limits"]["memory_bytes"].as_u64().unwrap();
    let host = server.url.trim_start_matches("http://").trim_end_matches('/').to_string();
    let bound = Duration::from_secs(status_bound(&server));
    // Half ask for the largest answer there is (about 5 MB each, 1.3 GB for all: past the budget),
    // half for more steps than allowed (which once answered 60 MB each, 7.7 GB for all).
    let largest = json!({"scene": scene, "design": design, "steps": most}).to_string();
    let too_many = json!({"scene": scene, "design": design, "steps": 5000}).to_string();
    let start = Instant::now();
    let mut open = Vec::new();
    for i in 0..clients {
        let body = if i % 2 == 0 { &largest } else { &too_many };
        open.extend(send_and_never_read(&host, "/api/simulate", body));
        // Spaced so that most are admitted rather than refused as a full queue.
        std::thread::sleep(Duration::from_millis(40));
    }
    assert!(open.len() >= clients * 9 / 10, "{} of {clients} connected", open.len());
    let peak_while_held = server.memory_kib("VmHWM").unwrap();
    eprintln!("{} clients sent in {:?}; peak {peak_while_held} KiB", open.len(), start.elapsed());

    // Unread answers are dropped with their connections after the write timeout; the 503s' kept-alive
    // connections after the head timeout: then there is room to connect again.
    let answered = (|| {
        let waited = Instant::now();
        while waited.elapsed() < bound {
            if let Some(mut probe) = send_status(&host) {
                let mut head = [0u8; 12];
                if probe.read_exact(&mut head).is_ok() {
                    return Some(String::from_utf8_lossy(&head).into_owned());
                }
            }
            std::thread::sleep(Duration::from_millis(500));
        }
        None
    })();
    assert_eq!(answered.as_deref(), Some("HTTP/1.1 200"), "the server answers while its clients hold on");
    // The unread answers are let go (the clients still hold their ends).
    let waited = Instant::now();
    let mut held = u64::MAX;
    while waited.elapsed() < bound && held > budget / 8 {
        std::thread::sleep(Duration::from_secs(1));
        held = status(&server)["memory_bytes"].as_u64().unwrap();
    }
    let peak = server.memory_kib("VmHWM").unwrap();
    eprintln!(
        "heap {} MiB after {:?}; peak resident {} MiB (budget {} MiB)",
        held >> 20,
        start.elapsed(),
        peak >> 10,
        budget >> 20
    );
    assert!(held <= budget / 8, "the server still holds {held} bytes of unread answers");
    assert!(peak < 2 * 1024 * 1024, "peak resident memory {peak} KiB");
    drop(open);
}

/// How long the server may take to drop its unread answers: its write timeout, after the last job
/// ran, with margin for a slow machine.
fn status_bound(server: &Server) -> u64 {
    let limits = &status(server)["limits"];
    limits["write_seconds"].as_f64().unwrap() as u64 + limits["job_seconds"].as_f64().unwrap() as u64 + 30
}

fn send_status(host: &str) -> Option<TcpStream> {
    let mut stream = TcpStream::connect(host).ok()?;
    stream.set_read_timeout(Some(Duration::from_secs(5))).ok()?;
    stream
        .write_all(format!("GET /api/status HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n").as_bytes())
        .ok()?;
    Some(stream)
}
