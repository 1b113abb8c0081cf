//! Heavy jobs (designs and fabrications) are bounded: a few run at once on one shared thread pool, a
//! short queue waits, anything beyond is refused; each client has at most one job of a kind (a new one
//! replaces the old); and a job stops at its next check when its client goes away.

use super::error::ApiError;
use axum::http::StatusCode;
use linkwright_core::synth::{Observer, Progress};
use std::collections::HashMap;
use std::sync::atomic::{AtomicU8, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use tokio::sync::{Notify, OwnedMutexGuard, OwnedSemaphorePermit, Semaphore};

/// Why a job should stop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The client closed the connection (or the server is shutting down).
    ClientGone,
    /// The same client started a newer job.
    Superseded,
}

/// A job's stop flag, shared by the request, the worker and the job table. The worker polls it; a job
/// still waiting in line is woken by it.
#[derive(Debug, Default)]
pub struct StopFlag {
    code: AtomicU8,
    stopped: Notify,
}

impl StopFlag {
    const GO: u8 = 0;
    const GONE: u8 = 1;
    const SUPERSEDED: u8 = 2;

    /// Asks the job to stop; the first reason given is kept.
    pub fn stop(&self, reason: StopReason) {
        let code = match reason {
            StopReason::ClientGone => Self::GONE,
            StopReason::Superseded => Self::SUPERSEDED,
        };
        if self.code.compare_exchange(Self::GO, code, Ordering::SeqCst, Ordering::SeqCst).is_ok() {
            self.stopped.notify_waiters();
        }
    }
    pub fn reason(&self) -> Option<StopReason> {
        match self.code.load(Ordering::SeqCst) {
            Self::GONE => Some(StopReason::ClientGone),
            Self::SUPERSEDED => Some(StopReason::Superseded),
            _ => None,
        }
    }
}

/// Sets its flag when dropped: held by whatever lives exactly as long as the client's interest (the
/// request's future, the event stream), so a closed connection stops the job.
#[derive(Debug)]
pub struct StopOnDrop(pub Arc<StopFlag>);

impl Drop for StopOnDrop {
    fn drop(&mut self) {
        self.0.stop(StopReason::ClientGone);
    }
}

/// What a job does. A client has at most one job of each kind: a fabrication does not stop its design.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    Design,
    Fabrication,
}

/// Limits of the job table.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Jobs running at once. Default 2.
    pub running: usize,
    /// Jobs waiting for a free slot; more are refused with 503. Default 4.
    pub queued: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits { running: 2, queued: 4 }
    }
}

/// One client's slot: its lock (held by its running job) and the flag of its latest job.
struct ClientSlot {
    lock: Arc<tokio::sync::Mutex<()>>,
    latest: Arc<StopFlag>,
}

/// The job table.
pub struct Jobs {
    limits: Limits,
    slots: Arc<Semaphore>,
    waiting: Arc<AtomicUsize>,
    clients: Mutex<HashMap<(Kind, String), ClientSlot>>,
    /// Every job's flag, so a shutdown can stop them all.
    all: Mutex<Vec<std::sync::Weak<StopFlag>>>,
    pub pool: Arc<rayon::ThreadPool>,
}

/// Admission to the queue: the job's flag and its place in line.
pub struct Ticket {
    pub flag: Arc<StopFlag>,
    client_lock: Arc<tokio::sync::Mutex<()>>,
    slots: Arc<Semaphore>,
    waiting: WaitingGuard,
}

/// Counts a ticket as waiting until it starts or is dropped.
struct WaitingGuard(Arc<AtomicUsize>);
impl Drop for WaitingGuard {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// A running job's hold on its slots; dropping it frees them.
pub struct Running {
    _client: OwnedMutexGuard<()>,
    _slot: OwnedSemaphorePermit,
}

impl Jobs {
    pub fn new(limits: Limits, pool: rayon::ThreadPool) -> Jobs {
        Jobs {
            limits,
            slots: Arc::new(Semaphore::new(limits.running.max(1))),
            waiting: Arc::new(AtomicUsize::new(0)),
            clients: Mutex::new(HashMap::new()),
            all: Mutex::new(Vec::new()),
            pool: Arc::new(pool),
        }
    }

    pub fn limits(&self) -> Limits {
        self.limits
    }
    /// Jobs running now.
    pub fn running(&self) -> usize {
        self.limits.running.max(1) - self.slots.available_permits()
    }
    /// Jobs waiting for a slot.
    pub fn waiting(&self) -> usize {
        self.waiting.load(Ordering::SeqCst)
    }

    /// Admits a `kind` job of `client`: stops the client's earlier job of that kind (it is superseded)
    /// and refuses with 503 when the queue is full.
    pub fn admit(&self, kind: Kind, client: &str) -> Result<Ticket, ApiError> {
        let busy = || {
            ApiError::new(
                StatusCode::SERVICE_UNAVAILABLE,
                format!(
                    "the server is busy ({} jobs running, {} waiting); try again in a moment",
                    self.running(),
                    self.waiting()
                ),
            )
            .retry_after(2)
        };
        let queued = self.waiting.fetch_add(1, Ordering::SeqCst);
        let waiting = WaitingGuard(self.waiting.clone());
        if queued >= self.limits.queued {
            return Err(busy());
        }
        let flag = Arc::new(StopFlag::default());
        let mut clients = self.clients.lock().map_err(|_| busy())?;
        // Forget clients whose jobs are all over (nobody else holds their lock).
        clients.retain(|_, slot| Arc::strong_count(&slot.lock) > 1);
        let slot = clients
            .entry((kind, client.to_string()))
            .or_insert_with(|| ClientSlot { lock: Arc::default(), latest: Arc::new(StopFlag::default()) });
        slot.latest.stop(StopReason::Superseded);
        slot.latest = flag.clone();
        let client_lock = slot.lock.clone();
        drop(clients);
        if let Ok(mut all) = self.all.lock() {
            all.retain(|w| w.strong_count() > 0);
            all.push(Arc::downgrade(&flag));
        }
        Ok(Ticket { flag, client_lock, slots: self.slots.clone(), waiting })
    }

    /// Stops every job (at shutdown).
    pub fn stop_all(&self) {
        if let Ok(all) = self.all.lock() {
            for flag in all.iter().filter_map(|w| w.upgrade()) {
                flag.stop(StopReason::ClientGone);
            }
        }
    }
}

impl Ticket {
    /// True when a slot is free and the client has no job running, so [`Ticket::start`] will not wait.
    pub fn can_start_now(&self) -> bool {
        self.slots.available_permits() > 0 && self.client_lock.try_lock().is_ok()
    }

    /// Waits for the client's earlier job to end and for a free slot. `None` when the job is stopped
    /// before it starts (its client went away or replaced it), which frees its place in line at once.
    pub async fn start(self) -> Option<Running> {
        let stopped = self.flag.stopped.notified();
        tokio::pin!(stopped);
        // Registered before the flag is read, so a stop between the two is not missed.
        stopped.as_mut().enable();
        if self.flag.reason().is_some() {
            return None;
        }
        let acquire = async {
            let client = self.client_lock.clone().lock_owned().await;
            let slot = self.slots.clone().acquire_owned().await.ok()?;
            Some(Running { _client: client, _slot: slot })
        };
        let running = tokio::select! {
            running = acquire => running?,
            () = &mut stopped => return None,
        };
        if self.flag.reason().is_some() {
            return None;
        }
        drop(self.waiting);
        Some(running)
    }
}

/// The observer of a running synthesis: forwards progress (dropping reports when the receiver lags)
/// and answers `cancelled` from the job's flag.
pub struct JobObserver<F: Fn(&Progress) + Sync> {
    pub flag: Arc<StopFlag>,
    pub on_progress: F,
}

impl<F: Fn(&Progress) + Sync> Observer for JobObserver<F> {
    fn progress(&self, progress: &Progress) {
        (self.on_progress)(progress);
    }
    fn cancelled(&self) -> bool {
        self.flag.reason().is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn jobs(running: usize, queued: usize) -> Jobs {
        Jobs::new(Limits { running, queued }, rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap())
    }

    #[tokio::test]
    async fn a_new_job_supersedes_the_same_clients_old_one() {
        let jobs = jobs(2, 4);
        let first = jobs.admit(Kind::Design, "a").unwrap();
        let first_flag = first.flag.clone();
        let running = first.start().await.unwrap();
        let second = jobs.admit(Kind::Design, "a").unwrap();
        assert_eq!(first_flag.reason(), Some(StopReason::Superseded));
        assert!(!second.can_start_now(), "the old job still holds the client's slot");
        drop(running);
        assert!(second.can_start_now());
        let other = jobs.admit(Kind::Design, "b").unwrap();
        assert_eq!(second.flag.reason(), None, "another client's job leaves it alone");
        let fabrication = jobs.admit(Kind::Fabrication, "a").unwrap();
        assert_eq!(second.flag.reason(), None, "so does the same client's job of another kind");
        drop((other, fabrication));
    }

    #[tokio::test]
    async fn a_full_queue_refuses_with_503() {
        let jobs = jobs(1, 2);
        let a = jobs.admit(Kind::Design, "a").unwrap();
        let b = jobs.admit(Kind::Design, "b").unwrap();
        let refused = jobs.admit(Kind::Design, "c").err().unwrap();
        assert_eq!(refused.status, StatusCode::SERVICE_UNAVAILABLE);
        assert_eq!(refused.retry_after, Some(2));
        assert_eq!(jobs.waiting(), 2);
        let running = a.start().await.unwrap();
        assert_eq!((jobs.running(), jobs.waiting()), (1, 1));
        drop(b);
        drop(running);
        assert_eq!((jobs.running(), jobs.waiting()), (0, 0));
    }

    #[tokio::test]
    async fn a_waiting_job_that_is_stopped_leaves_the_line_at_once() {
        let jobs = jobs(1, 4);
        let running = jobs.admit(Kind::Design, "a").unwrap().start().await.unwrap();
        let waiting = jobs.admit(Kind::Design, "b").unwrap();
        let flag = waiting.flag.clone();
        let waited = tokio::spawn(waiting.start());
        tokio::task::yield_now().await;
        assert_eq!(jobs.waiting(), 1);
        flag.stop(StopReason::ClientGone);
        assert!(waited.await.unwrap().is_none());
        assert_eq!(jobs.waiting(), 0);
        drop(running);
    }

    #[test]
    fn dropping_the_guard_stops_the_job_once() {
        let flag = Arc::new(StopFlag::default());
        flag.stop(StopReason::Superseded);
        drop(StopOnDrop(flag.clone()));
        assert_eq!(flag.reason(), Some(StopReason::Superseded), "the first reason is kept");
    }
}
