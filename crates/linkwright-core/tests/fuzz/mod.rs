//! What the fuzz tests share: a structure-aware mutator of JSON documents, which edits a valid file
//! the way a careless or hostile writer would (wild numbers, missing or repeated fields, wrong types,
//! huge arrays, broken text) deterministically from a seed, so a failing case can be replayed; the
//! budget read from the environment; running one case within its bound; keeping a failing input.
#![allow(dead_code, reason = "each fuzz target uses a different part of this module")]

use serde_json::{Map, Value};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// The most one case may take: the formats' limits bound the work of everything a valid input
/// reaches, and a case takes well under a second in release builds.
pub(crate) const CASE_BOUND: Duration = Duration::from_secs(60);

/// How long to fuzz and from which seed: `LINKWRIGHT_FUZZ_SECONDS` (default 15, the CI budget) and
/// `LINKWRIGHT_FUZZ_SEED` (default 0).
pub(crate) fn budget() -> (Duration, u64) {
    let number = |name: &str, default: u64| std::env::var(name).ok().and_then(|s| s.parse().ok()).unwrap_or(default);
    (Duration::from_secs(number("LINKWRIGHT_FUZZ_SECONDS", 15)), number("LINKWRIGHT_FUZZ_SEED", 0))
}

/// Runs `case` on a thread of its own: its result, or its failure (a panic, or running past
/// [`CASE_BOUND`]; the worker is then left running, and the failing test's process ends with it).
pub(crate) fn bounded<T: Send + 'static>(case: impl FnOnce() -> T + Send + 'static) -> Result<T, String> {
    let (done, finished) = mpsc::channel();
    let started = Instant::now();
    let worker = std::thread::spawn(move || {
        let caught = std::panic::catch_unwind(std::panic::AssertUnwindSafe(case));
        let _ = done.send(caught.ok());
    });
    match finished.recv_timeout(CASE_BOUND) {
        Ok(Some(result)) => {
            let _ = worker.join();
            Ok(result)
        }
        Ok(None) | Err(mpsc::RecvTimeoutError::Disconnected) => Err("panicked".into()),
        Err(mpsc::RecvTimeoutError::Timeout) => Err(format!("ran past {CASE_BOUND:?} ({:?})", started.elapsed())),
    }
}

/// Writes a failing input to `target/tmp/fuzz-failures/NAME`; returns its path.
pub(crate) fn keep_failure(name: &str, text: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-failures");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// SplitMix64: small, fast and good enough to choose mutations; the seed alone replays a case.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Rng {
        Rng(seed)
    }
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// A number in `0..n` (`n` > 0).
    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    pub(crate) fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Numbers that break naive code: zeros, extremes, the edges of the formats' limits, integers beyond
/// f64's exact range.
const WILD_NUMBERS: &[f64] =
    &[0.0, -0.0, 1.0, -1.0, 0.5, 1e-300, 1e-9, 1e6, 1e6 + 1.0, 1e7, 1e9, 1e15, 1e18, 1e308, -1e308, 360.0, 1e5, 3.0];

/// A path to a node of a document: keys of objects and indices of arrays.
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn paths(value: &Value, here: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    out.push(here.clone());
    match value {
        Value::Object(map) => {
            for (k, v) in map {
                here.push(Step::Key(k.clone()));
                paths(v, here, out);
                here.pop();
            }
        }
        Value::Array(items) => {
            for (i, v) in items.iter().enumerate() {
                here.push(Step::Index(i));
                paths(v, here, out);
                here.pop();
            }
        }
        _ => {}
    }
}

fn at<'a>(value: &'a mut Value, path: &[Step]) -> &'a mut Value {
    path.iter().fold(value, |v, step| match step {
        Step::Key(k) => &mut v[k.as_str()],
        Step::Index(i) => &mut v[*i],
    })
}

/// One random edit of one random node of `doc`.
pub(crate) fn mutate_value(doc: &mut Value, rng: &mut Rng) {
    let mut all = Vec::new();
    paths(doc, &mut Vec::new(), &mut all);
    let path = rng.pick(&all).clone();
    let node = at(doc, &path);
    match rng.below(10) {
        0 | 1 => {
            let sign = if rng.below(4) == 0 { -1.0 } else { 1.0 };
            *node = Value::from(sign * rng.pick(WILD_NUMBERS));
        }
        2 => {
            if let Some(n) = node.as_f64() {
                // A small nudge: near-degenerate geometry rather than absurd geometry.
                *node = Value::from(n * (1.0 + (rng.below(2001) as f64 - 1000.0) * 1e-4) + rng.below(3) as f64 - 1.0);
            }
        }
        3 => match node {
            Value::Object(map) if !map.is_empty() => {
                let key = map.keys().nth(rng.below(map.len())).cloned().unwrap_or_default();
                map.remove(&key);
            }
            Value::Array(items) if !items.is_empty() => {
                let i = rng.below(items.len());
                items.remove(i);
            }
            _ => *node = Value::Null,
        },
        4 => {
            if let Value::Array(items) = node {
                if !items.is_empty() {
                    // Repeats: from a duplicated vertex to arrays far beyond every limit.
                    let copies = *rng.pick(&[1, 2, 5, 60, 600, 3000]);
                    let item = items[rng.below(items.len())].clone();
                    let at = rng.below(items.len() + 1);
                    items.splice(at..at, std::iter::repeat_n(item, copies));
                }
            }
        }
        5 => {
            if let Value::Array(items) = node {
                let keep = rng.below(items.len() + 1);
                items.truncate(keep);
            }
        }
        6 => {
            if let Value::Array(items) = node {
                for i in (1..items.len()).rev() {
                    items.swap(i, rng.below(i + 1));
                }
            }
        }
        7 => {
            *node = rng
                .pick(&[
                    Value::Null,
                    Value::Bool(true),
                    Value::String(String::new()),
                    Value::String("../../ESCAPED".into()),
                    Value::String("a\u{0}b\u{1b}c<&>\"'".into()),
                    Value::String("é".repeat(3000)),
                    Value::Array(Vec::new()),
                    Value::Object(Map::new()),
                    Value::from(u64::MAX),
                    Value::from(i64::MIN),
                ])
                .clone();
        }
        8 => {
            if let Value::Object(map) = node {
                let key = rng.pick(&["extra", "name", "poses", "polygon", "settings", "samples", "linkwright"]);
                map.insert((*key).to_string(), Value::from(rng.pick(WILD_NUMBERS) * 3.0));
            }
        }
        _ => {
            // Nest the node in arrays: deep documents must not exhaust the parser's stack.
            let depth = *rng.pick(&[1, 3, 200]);
            let mut v = node.take();
            for _ in 0..depth {
                v = Value::Array(vec![v]);
            }
            *node = v;
        }
    }
}

/// A mutated copy of `text`: mostly edits of its JSON structure, sometimes of its bytes (which the
/// parser must refuse cleanly).
pub(crate) fn mutate(text: &str, rng: &mut Rng) -> String {
    if rng.below(8) == 0 {
        let mut bytes = text.as_bytes().to_vec();
        for _ in 0..=rng.below(4) {
            if bytes.is_empty() {
                break;
            }
            let i = rng.below(bytes.len());
            match rng.below(3) {
                0 => bytes.truncate(i),
                1 => bytes[i] = rng.next() as u8,
                _ => bytes.insert(i, *rng.pick(b"{}[],:\"0-e.\\\x00\xff")),
            }
        }
        return String::from_utf8_lossy(&bytes).into_owned();
    }
    let Ok(mut doc) = serde_json::from_str::<Value>(text) else { return text.to_string() };
    for _ in 0..=rng.below(3) {
        mutate_value(&mut doc, rng);
    }
    doc.to_string()
}

/// Where `answer` holds a number that was not finite: serde writes NaN and infinities as `null`, so
/// a null in an array that also holds numbers (a point, a row of torques) is one. The path of the
/// first such value, if any. A lone numeric field written as null is not caught here.
pub(crate) fn non_finite(answer: &Value) -> Option<String> {
    fn walk(v: &Value, path: &mut String) -> Option<String> {
        match v {
            Value::Array(items) => {
                let numbers = items.iter().any(Value::is_number);
                if let Some(i) = items.iter().position(Value::is_null).filter(|_| numbers) {
                    return Some(format!("{path}[{i}]"));
                }
                items.iter().enumerate().find_map(|(i, item)| {
                    let len = path.len();
                    path.push_str(&format!("[{i}]"));
                    let found = walk(item, path);
                    path.truncate(len);
                    found
                })
            }
            Value::Object(fields) => fields.iter().find_map(|(k, item)| {
                let len = path.len();
                path.push_str(&format!(".{k}"));
                let found = walk(item, path);
                path.truncate(len);
                found
            }),
            _ => None,
        }
    }
    walk(answer, &mut String::new())
}
