//! Every CPU-heavy request (a design with its print pre-check, a fabrication, a check, a simulation, a
//! picture) runs as a job: a few run at once on one shared thread pool, off the async threads that
//! answer every other request; a short queue waits, anything beyond is refused; each client has at most
//! one job of a kind; a job waits in line and runs for a bounded time (its deadline); a job stops at
//! its next check when its client goes away; and past the server's memory budget no job is admitted
//! and running ones stop.

use super::error::ApiError;
use axum::http::StatusCode;
use linkwright_core::{Observer, Progress};
use std::collections::HashMap;
use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicU8, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;
use tokio::sync::{oneshot, Notify, OwnedMutexGuard, OwnedSemaphorePermit, Semaphore};

/// Why a job should stop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum StopReason {
    /// The client closed the connection (or the server is shutting down).
    ClientGone,
    /// The same client started a newer job.
    Superseded,
    /// The job ran longer than [`Limits::deadline`].
    Deadline,
    /// The server's heap grew past [`Limits::memory`] while the job ran.
    Memory,
}

/// A job's stop flag, shared by the request, the worker and the job table. The worker polls it
/// ([`StopFlag::should_stop`]); a job still waiting in line is woken by it.
#[derive(Debug)]
pub(crate) struct StopFlag {
    code: AtomicU8,
    stopped: Notify,
    /// The heap bytes past which the job is stopped ([`Limits::memory`]).
    memory: usize,
}

impl Default for StopFlag {
    fn default() -> Self {
        StopFlag::with_memory_limit(usize::MAX)
    }
}

impl StopFlag {
    /// A flag whose job stops when the heap passes `memory` bytes.
    pub(crate) fn with_memory_limit(memory: usize) -> StopFlag {
        StopFlag { code: AtomicU8::new(Self::GO), stopped: Notify::new(), memory }
    }

    /// True when the job should stop: it was asked to, or the server's heap is past its limit (which
    /// then stops it).
    pub(crate) fn should_stop(&self) -> bool {
        if self.reason().is_none() && crate::memory::live_bytes() > self.memory {
            self.stop(StopReason::Memory);
        }
        self.reason().is_some()
    }

    const GO: u8 = 0;
    const GONE: u8 = 1;
    const SUPERSEDED: u8 = 2;
    const DEADLINE: u8 = 3;
    const MEMORY: u8 = 4;

    /// Asks the job to stop; the first reason given is kept.
    pub(crate) fn stop(&self, reason: StopReason) {
        let code = match reason {
            StopReason::ClientGone => Self::GONE,
            StopReason::Superseded => Self::SUPERSEDED,
            StopReason::Deadline => Self::DEADLINE,
            StopReason::Memory => Self::MEMORY,
        };
        if self.code.compare_exchange(Self::GO, code, Ordering::SeqCst, Ordering::SeqCst).is_ok() {
            self.stopped.notify_waiters();
        }
    }
    pub(crate) fn reason(&self) -> Option<StopReason> {
        match self.code.load(Ordering::SeqCst) {
            Self::GONE => Some(StopReason::ClientGone),
            Self::SUPERSEDED => Some(StopReason::Superseded),
            Self::DEADLINE => Some(StopReason::Deadline),
            Self::MEMORY => Some(StopReason::Memory),
            _ => None,
        }
    }
}

/// Sets its flag when dropped: held by whatever lives exactly as long as the client's interest (the
/// request's future, the event stream), so a closed connection stops the job.
#[derive(Debug)]
pub(super) struct StopOnDrop(pub Arc<StopFlag>);

impl Drop for StopOnDrop {
    fn drop(&mut self) {
        self.0.stop(StopReason::ClientGone);
    }
}

/// What a job does. A client has at most one job of each kind running: a fabrication does not stop
/// its design.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Kind {
    Design,
    Fabrication,
    /// A check, a simulation or a picture of a design: short, so none of them replaces another; the
    /// same client's analyses run one after the other.
    Analysis,
}

impl Kind {
    /// True when a newer job of this kind from the same client replaces the older one: only the answer
    /// to the latest design or fabrication matters to the app (a pose dragged, settings changed).
    fn supersedes(self) -> bool {
        matches!(self, Kind::Design | Kind::Fabrication)
    }
}

/// Limits of the job table.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limits {
    /// Jobs running at once. Default 2.
    pub running: usize,
    /// Jobs waiting for a free slot; more are refused with 503. Default 4.
    pub queued: usize,
    /// How long a job may run, and also how long it may wait in line for a slot. Default 60 s: the
    /// bundled examples design in well under 5 s with their own settings (`stats.seconds.total` of
    /// `linkwright design examples/NAME.json --threads 2`), so a minute leaves room for ten times the
    /// samples on a slow, shared machine, while every request is answered within two minutes at worst
    /// (a minute in line, a minute running). Work that needs longer belongs to the command line,
    /// which has no deadline.
    pub deadline: Duration,
    /// Heap bytes the server may hold ([`crate::memory::live_bytes`]): past it, new jobs are refused
    /// and running ones stopped at their next check, so the process never reaches an allocation
    /// that fails (which would abort it). Default 1 GiB: a design at the scene limits peaks at a few
    /// hundred megabytes (260 MB for the garbage truck at 10⁶ samples, 1,000 particles and 200
    /// iterations: `/usr/bin/time -f "%M KB" linkwright design SCENE --threads 2`, as in
    /// docs/security.md), so two run side by side with room for the answers being sent.
    pub memory: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits { running: 2, queued: 4, deadline: Duration::from_secs(60), memory: 1 << 30 }
    }
}

/// How a job ended without its result.
#[derive(Debug, PartialEq, Eq)]
pub(crate) enum JobEnd {
    /// It was stopped (see [`StopFlag`]), before it started or while it ran.
    Stopped(StopReason),
    /// It waited [`Limits::deadline`] in line without getting a slot.
    WaitedTooLong,
    /// The computation panicked (a bug: the panic is caught so the server and its pool live on).
    Panicked,
}

/// One client's slot: its lock (held by its running job) and the flag of its latest job.
struct ClientSlot {
    lock: Arc<tokio::sync::Mutex<()>>,
    latest: Arc<StopFlag>,
}

/// The job table.
pub(crate) struct Jobs {
    limits: Limits,
    slots: Arc<Semaphore>,
    waiting: Arc<AtomicUsize>,
    clients: Mutex<HashMap<(Kind, String), ClientSlot>>,
    /// Requests being read and validated (see [`Jobs::read`]), at most [`Limits::running`] at once.
    reading: Arc<Semaphore>,
    /// Every job's flag, so a shutdown can stop them all.
    all: Mutex<Vec<std::sync::Weak<StopFlag>>>,
    pub pool: Arc<rayon::ThreadPool>,
}

/// The work of a job as the answers name it, with what to change when it runs out of time.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Work {
    /// `design`, `fabrication`, ...
    pub noun: &'static str,
    /// What to change when it takes longer than the deadline.
    pub advice: &'static str,
}

impl Work {
    pub(crate) const DESIGN: Work = Work {
        noun: "design",
        advice: "ask for less (fewer settings.samples, fewer poses or moving bodies), check that the scene's \
                 units and sizes are what you meant, or run `linkwright design` on the command line, which \
                 has no time limit",
    };
    pub(crate) const FABRICATION: Work = Work {
        noun: "fabrication",
        advice: "check that the scene's units and sizes and the print settings are what you meant, or run \
                 `linkwright fabricate` on the command line, which has no time limit",
    };
    pub(crate) const CHECK: Work =
        Work { noun: "check", advice: "check that the scene's units and sizes are what you meant" };
    pub(crate) const SIMULATION: Work = Work {
        noun: "simulation",
        advice: "ask for fewer steps, and check that the scene's units and sizes are what you meant",
    };
    pub(crate) const BALANCE: Work = Work {
        noun: "spring search",
        advice: "ask for fewer steps, or run `linkwright analyze` on the command line, which has no time limit",
    };
    pub(crate) const PICTURE: Work =
        Work { noun: "picture", advice: "check that the scene's units and sizes are what you meant" };

    /// The answer to this work when its job ended without a result.
    pub(crate) fn error(self, end: JobEnd, deadline: Duration) -> ApiError {
        let seconds = deadline.as_secs_f64();
        match end {
            JobEnd::Stopped(StopReason::Superseded) => ApiError::new(
                StatusCode::CONFLICT,
                format!("cancelled: a newer {} request from the same client replaced it", self.noun),
            ),
            JobEnd::Stopped(StopReason::ClientGone) => ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "cancelled"),
            JobEnd::Stopped(StopReason::Memory) => ApiError::new(
                StatusCode::SERVICE_UNAVAILABLE,
                format!(
                    "the {} was stopped: the server ran short of memory while it ran; try again in a moment, \
                     or {}",
                    self.noun, self.advice
                ),
            )
            .retry_after(5),
            JobEnd::Stopped(StopReason::Deadline) => ApiError::new(
                StatusCode::SERVICE_UNAVAILABLE,
                format!(
                    "the {} ran longer than this server's limit of {seconds} s per job and was stopped: {}",
                    self.noun, self.advice
                ),
            ),
            JobEnd::WaitedTooLong => ApiError::new(
                StatusCode::SERVICE_UNAVAILABLE,
                format!(
                    "the server is busy: the {} waited {seconds} s for a free slot; try again in a moment",
                    self.noun
                ),
            )
            .retry_after(2),
            JobEnd::Panicked => ApiError::new(
                StatusCode::INTERNAL_SERVER_ERROR,
                format!("internal error: the {} failed; please report it", self.noun),
            ),
        }
    }
}

/// Admission to the queue: the job's flag and its place in line.
pub(crate) struct Ticket {
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
pub(crate) struct Running {
    _client: OwnedMutexGuard<()>,
    _slot: OwnedSemaphorePermit,
}

impl Jobs {
    pub(crate) fn new(limits: Limits, pool: rayon::ThreadPool) -> Jobs {
        Jobs {
            limits,
            slots: Arc::new(Semaphore::new(limits.running.max(1))),
            waiting: Arc::new(AtomicUsize::new(0)),
            clients: Mutex::new(HashMap::new()),
            reading: Arc::new(Semaphore::new(limits.running.max(1))),
            all: Mutex::new(Vec::new()),
            pool: Arc::new(pool),
        }
    }

    pub(crate) fn limits(&self) -> Limits {
        self.limits
    }
    /// Jobs running now.
    pub(crate) fn running(&self) -> usize {
        self.limits.running.max(1) - self.slots.available_permits()
    }
    /// Jobs waiting for a slot.
    pub(crate) fn waiting(&self) -> usize {
        self.waiting.load(Ordering::SeqCst)
    }
    /// True when the heap is past [`Limits::memory`].
    pub(crate) fn short_of_memory(&self) -> bool {
        crate::memory::live_bytes() > self.limits.memory
    }

    /// Admits a `kind` job of `client`: stops the client's earlier job of that kind (it is superseded)
    /// and refuses with 503 when the queue is full.
    pub(crate) fn admit(&self, kind: Kind, client: &str) -> Result<Ticket, ApiError> {
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
        if self.short_of_memory() {
            let message = format!(
                "the server is short of memory ({} MB in use, its limit is {} MB): answers not yet read by \
                 their clients and running jobs hold it; try again in a moment",
                crate::memory::live_bytes() >> 20,
                self.limits.memory >> 20
            );
            return Err(ApiError::new(StatusCode::SERVICE_UNAVAILABLE, message).retry_after(5));
        }
        let queued = self.waiting.fetch_add(1, Ordering::SeqCst);
        let waiting = WaitingGuard(self.waiting.clone());
        if queued >= self.limits.queued {
            return Err(busy());
        }
        let flag = Arc::new(StopFlag::with_memory_limit(self.limits.memory));
        let mut clients = self.clients.lock().map_err(|_| busy())?;
        // Forget clients whose jobs are all over (nobody else holds their lock).
        clients.retain(|_, slot| Arc::strong_count(&slot.lock) > 1);
        let slot = clients
            .entry((kind, client.to_string()))
            .or_insert_with(|| ClientSlot { lock: Arc::default(), latest: Arc::new(StopFlag::default()) });
        if kind.supersedes() {
            slot.latest.stop(StopReason::Superseded);
        }
        slot.latest = flag.clone();
        let client_lock = slot.lock.clone();
        drop(clients);
        if let Ok(mut all) = self.all.lock() {
            all.retain(|w| w.strong_count() > 0);
            all.push(Arc::downgrade(&flag));
        }
        Ok(Ticket { flag, client_lock, slots: self.slots.clone(), waiting })
    }

    /// Requests being read and validated now.
    pub(crate) fn reading(&self) -> usize {
        self.limits.running.max(1) - self.reading.available_permits()
    }

    /// Parses and validates a request body with `read`, off the async threads: validating a scene of
    /// tens of thousands of vertices takes seconds, and on the async threads it would hold up every
    /// other request. At most [`Limits::running`] requests are read at once (each holds its place until
    /// its computation ends, even when the request gave up), and a request waits and reads at most the
    /// deadline. Bad input is answered from here, without waiting in the job queue.
    pub(crate) async fn read<T: Send + 'static>(
        &self,
        read: impl FnOnce() -> Result<T, ApiError> + Send + 'static,
    ) -> Result<T, ApiError> {
        let deadline = self.limits.deadline;
        let seconds = deadline.as_secs_f64();
        let busy = || {
            let message =
                format!("the server is busy: the request waited {seconds} s to be read; try again in a moment");
            ApiError::new(StatusCode::SERVICE_UNAVAILABLE, message).retry_after(2)
        };
        let permit = match tokio::time::timeout(deadline, self.reading.clone().acquire_owned()).await {
            Ok(Ok(permit)) => permit,
            _ => return Err(busy()),
        };
        let reading = tokio::task::spawn_blocking(move || {
            let _permit = permit;
            read()
        });
        match tokio::time::timeout(deadline, reading).await {
            Ok(Ok(result)) => result,
            Ok(Err(_)) => Err(ApiError::new(
                StatusCode::INTERNAL_SERVER_ERROR,
                "internal error: reading the request failed; please report it",
            )),
            Err(_) => Err(ApiError::new(
                StatusCode::SERVICE_UNAVAILABLE,
                format!(
                    "reading and checking the request took longer than this server's limit of {seconds} s: send \
                     smaller shapes (fewer vertices), or use the command line, which has no time limit"
                ),
            )),
        }
    }

    /// Runs `work` on the pool as the job that holds `running`, and waits for its result at most
    /// [`Limits::deadline`]. At the deadline the job's flag is set, so work that checks it stops; work
    /// that cannot check it (the print pre-check, a fabrication) finishes on its thread, still holding
    /// its slot so the pool is never asked for more than the limits allow, and its result is dropped.
    /// The wait also ends at once when the flag is set for another reason (the client went away or
    /// replaced the job): nobody wants the answer any more.
    pub(crate) async fn execute<T: Send + 'static>(
        &self,
        running: Running,
        flag: Arc<StopFlag>,
        work: impl FnOnce(&Arc<StopFlag>) -> T + Send + 'static,
    ) -> Result<T, JobEnd> {
        let (tx, rx) = oneshot::channel();
        let job_flag = flag.clone();
        self.pool.spawn(move || {
            if job_flag.should_stop() {
                return;
            }
            // A panic in a rayon task would abort the whole process; here it is this job's failure.
            let result = std::panic::catch_unwind(AssertUnwindSafe(|| work(&job_flag)));
            // The slot is free before the answer goes out, so whoever reads the answer sees it free.
            drop(running);
            let _ = tx.send(result.map_err(|_| JobEnd::Panicked));
        });
        let stopped = flag.stopped.notified();
        tokio::pin!(stopped);
        stopped.as_mut().enable();
        let reason = || flag.reason().unwrap_or(StopReason::ClientGone);
        if flag.reason().is_some() {
            return Err(JobEnd::Stopped(reason()));
        }
        tokio::select! {
            result = rx => result.unwrap_or_else(|_| Err(JobEnd::Stopped(reason()))),
            () = tokio::time::sleep(self.limits.deadline) => {
                flag.stop(StopReason::Deadline);
                Err(JobEnd::Stopped(reason()))
            }
            () = &mut stopped => Err(JobEnd::Stopped(reason())),
        }
    }

    /// A whole job for a plain request: admitted (or refused), waiting its turn (at most the deadline),
    /// then [`Jobs::execute`]; `what` names the work in the answers. The job stops when the returned
    /// future is dropped (the client hung up).
    pub(crate) async fn run<T: Send + 'static>(
        &self,
        kind: Kind,
        client: &str,
        what: Work,
        work: impl FnOnce(&Arc<StopFlag>) -> Result<T, ApiError> + Send + 'static,
    ) -> Result<T, ApiError> {
        let ticket = self.admit(kind, client)?;
        let flag = ticket.flag.clone();
        let _guard = StopOnDrop(flag.clone());
        let ended = |end| what.error(end, self.limits.deadline);
        let running = ticket.start_within(self.limits.deadline).await.map_err(ended)?;
        match self.execute(running, flag.clone(), work).await {
            Ok(Ok(value)) => Ok(value),
            // Work that was stopped fails (a cancelled synthesis); the answer says why it was stopped.
            Ok(Err(error)) => match flag.reason() {
                Some(reason) => Err(ended(JobEnd::Stopped(reason))),
                None => Err(error),
            },
            Err(end) => Err(ended(end)),
        }
    }

    /// Stops every job (at shutdown).
    pub(crate) fn stop_all(&self) {
        if let Ok(all) = self.all.lock() {
            for flag in all.iter().filter_map(|w| w.upgrade()) {
                flag.stop(StopReason::ClientGone);
            }
        }
    }
}

impl Ticket {
    /// True when a slot is free and the client has no job running, so [`Ticket::start`] will not wait.
    pub(crate) fn can_start_now(&self) -> bool {
        self.slots.available_permits() > 0 && self.client_lock.try_lock().is_ok()
    }

    /// Waits for the client's earlier job to end and for a free slot. `None` when the job is stopped
    /// before it starts (its client went away or replaced it), which frees its place in line at once.
    pub(crate) async fn start(self) -> Option<Running> {
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

    /// [`Ticket::start`], waiting at most `wait`.
    pub(crate) async fn start_within(self, wait: Duration) -> Result<Running, JobEnd> {
        let flag = self.flag.clone();
        match tokio::time::timeout(wait, self.start()).await {
            Ok(Some(running)) => Ok(running),
            Ok(None) => Err(JobEnd::Stopped(flag.reason().unwrap_or(StopReason::ClientGone))),
            Err(_) => Err(JobEnd::WaitedTooLong),
        }
    }
}

/// The observer of a running synthesis: forwards progress (dropping reports when the receiver lags)
/// and answers `cancelled` from the job's flag.
pub(super) struct JobObserver<F: Fn(&Progress) + Sync> {
    pub flag: Arc<StopFlag>,
    pub on_progress: F,
}

impl<F: Fn(&Progress) + Sync> Observer for JobObserver<F> {
    fn progress(&self, progress: &Progress) {
        (self.on_progress)(progress);
    }
    fn cancelled(&self) -> bool {
        self.flag.should_stop()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn jobs(running: usize, queued: usize) -> Jobs {
        jobs_with_deadline(running, queued, Limits::default().deadline)
    }

    fn jobs_with_deadline(running: usize, queued: usize, deadline: Duration) -> Jobs {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        Jobs::new(Limits { running, queued, deadline, ..Limits::default() }, pool)
    }

    /// Work that spins until its flag is set, as a synthesis does between its checks.
    fn until_stopped(flag: &Arc<StopFlag>) -> Option<StopReason> {
        while flag.reason().is_none() {
            std::thread::sleep(Duration::from_millis(5));
        }
        flag.reason()
    }

    #[tokio::test]
    async fn a_job_past_its_deadline_is_stopped_and_answered() {
        let jobs = jobs_with_deadline(1, 4, Duration::from_millis(200));
        let ticket = jobs.admit(Kind::Design, "a").unwrap();
        let flag = ticket.flag.clone();
        let running = ticket.start().await.unwrap();
        let ended = jobs.execute(running, flag.clone(), until_stopped).await;
        assert_eq!(ended, Err(JobEnd::Stopped(StopReason::Deadline)));
        assert_eq!(flag.reason(), Some(StopReason::Deadline), "the work is told to stop");
        let error = Work::DESIGN.error(JobEnd::Stopped(StopReason::Deadline), Duration::from_secs(60));
        assert_eq!(error.status, StatusCode::SERVICE_UNAVAILABLE);
        assert!(error.error.contains("limit of 60 s") && error.error.contains("settings.samples"), "{}", error.error);
    }

    #[tokio::test]
    async fn work_that_cannot_be_stopped_keeps_its_slot_until_it_ends() {
        let jobs = jobs_with_deadline(1, 4, Duration::from_millis(100));
        let (release, released) = std::sync::mpsc::channel::<()>();
        let ticket = jobs.admit(Kind::Fabrication, "a").unwrap();
        let flag = ticket.flag.clone();
        let running = ticket.start().await.unwrap();
        // Ignores its flag, like the print pre-check: ends only when told here.
        let stubborn = move |_: &Arc<StopFlag>| released.recv().is_ok();
        let ended = jobs.execute(running, flag, stubborn).await;
        assert_eq!(ended, Err(JobEnd::Stopped(StopReason::Deadline)), "answered at the deadline");
        assert_eq!(jobs.running(), 1, "still counted while its thread computes");
        let waiting = jobs.admit(Kind::Fabrication, "b").unwrap();
        assert_eq!(waiting.start_within(Duration::from_millis(100)).await.err(), Some(JobEnd::WaitedTooLong));
        release.send(()).unwrap();
        let next = jobs.admit(Kind::Fabrication, "c").unwrap();
        assert!(next.start_within(Duration::from_secs(10)).await.is_ok(), "the slot is free once it ends");
    }

    #[tokio::test]
    async fn a_panicking_job_is_a_failure_not_a_dead_server() {
        let jobs = jobs(1, 4);
        let ticket = jobs.admit(Kind::Analysis, "a").unwrap();
        let flag = ticket.flag.clone();
        let running = ticket.start().await.unwrap();
        let ended = jobs.execute(running, flag, |_: &Arc<StopFlag>| -> u8 { panic!("a bug") }).await;
        assert_eq!(ended, Err(JobEnd::Panicked));
        let answer = jobs.run(Kind::Analysis, "a", Work::CHECK, |_| Ok::<u8, ApiError>(7)).await;
        assert_eq!(answer.ok(), Some(7), "the pool still works");
        assert_eq!((jobs.running(), jobs.waiting()), (0, 0));
    }

    #[tokio::test]
    async fn analyses_of_one_client_wait_for_each_other_instead_of_replacing() {
        let jobs = jobs(2, 4);
        let first = jobs.admit(Kind::Analysis, "a").unwrap();
        let running = first.start().await.unwrap();
        let second = jobs.admit(Kind::Analysis, "a").unwrap();
        assert_eq!(second.flag.reason(), None);
        assert!(!second.can_start_now(), "it waits for the first");
        drop(running);
        assert!(second.can_start_now());
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

    /// Past its memory limit the server admits no job and stops the running ones at their next check,
    /// each answered with a 503 that says why.
    #[tokio::test]
    async fn past_the_memory_limit_jobs_are_refused_and_stopped() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        // Any program holds some heap: a limit of one byte is always passed.
        let jobs = Jobs::new(Limits { memory: 1, ..Limits::default() }, pool);
        let refused = jobs.admit(Kind::Design, "a").err().expect("refused");
        assert_eq!(refused.status, StatusCode::SERVICE_UNAVAILABLE);
        assert!(refused.error.contains("short of memory"), "{}", refused.error);

        let flag = StopFlag::with_memory_limit(1);
        assert!(flag.should_stop());
        assert_eq!(flag.reason(), Some(StopReason::Memory));
        let answer = Work::DESIGN.error(JobEnd::Stopped(StopReason::Memory), Duration::from_secs(60));
        assert_eq!(answer.status, StatusCode::SERVICE_UNAVAILABLE);
        assert!(answer.error.contains("ran short of memory") && answer.error.contains("settings.samples"));
        assert!(!StopFlag::default().should_stop(), "no limit by default");
    }

    #[test]
    fn dropping_the_guard_stops_the_job_once() {
        let flag = Arc::new(StopFlag::default());
        flag.stop(StopReason::Superseded);
        drop(StopOnDrop(flag.clone()));
        assert_eq!(flag.reason(), Some(StopReason::Superseded), "the first reason is kept");
    }
}
