//! The generations running now, one per session at most: their progress, and their
//! cancellation when the session starts a newer one.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use axum::http::StatusCode;

use crate::error::ApiError;

/// How many generations and other heavy requests run at once by default: twice the cores,
/// at least 4 (each holds a blocking thread and up to a budget's memory).
pub(crate) fn default_max_jobs() -> usize {
    std::thread::available_parallelism().map_or(4, |n| 2 * n.get()).max(4)
}

/// Where a generation is.
#[derive(Debug, Default, Clone)]
pub(crate) struct JobState {
    /// The step running (see [`relief::Progress`]).
    pub(crate) step: &'static str,
    /// Units of the step done, of `total` (0 of 0 for a step that is not counted).
    pub(crate) done: u64,
    /// Units of the step.
    pub(crate) total: u64,
}

/// One running generation.
#[derive(Debug, Default)]
pub(crate) struct Job {
    cancelled: AtomicBool,
    state: Mutex<JobState>,
}

impl Job {
    /// Asks the generation to stop before its next step or unit of work.
    pub(crate) fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Where it is.
    pub(crate) fn state(&self) -> JobState {
        self.state.lock().unwrap_or_else(PoisonError::into_inner).clone()
    }

    fn set(&self, state: JobState) {
        *self.state.lock().unwrap_or_else(PoisonError::into_inner) = state;
    }
}

/// The pipeline's progress, recorded in a [`Job`]; it reads the job's cancellation.
pub(crate) struct JobProgress(pub(crate) Arc<Job>);

impl relief::Progress for JobProgress {
    fn start(&mut self, step: &'static str) {
        self.0.set(JobState { step, done: 0, total: 0 });
    }

    fn finish(&mut self, _: &'static str, _: Duration) {}

    fn advance(&mut self, step: &'static str, done: u64, total: u64) {
        self.0.set(JobState { step, done, total });
    }

    fn cancelled(&self) -> bool {
        self.0.cancelled.load(Ordering::Relaxed)
    }
}

/// The running generations of named sessions, and how many jobs run in all (generations, and
/// the other work that holds a blocking thread: parsing, uploads, opening, peaks, downloads).
#[derive(Debug)]
pub(crate) struct Jobs {
    by_session: Mutex<HashMap<String, Arc<Job>>>,
    running: Mutex<usize>,
    max_running: usize,
}

/// A job while its request is being answered. Dropping it (the request answered, or abandoned
/// when the client disconnects) cancels the job and frees its place: an aborted request never
/// holds a slot or keeps its generation running past the next step.
pub(crate) struct Running<'a> {
    jobs: &'a Jobs,
    session: Option<String>,
    /// The job.
    pub(crate) job: Arc<Job>,
}

impl Drop for Running<'_> {
    fn drop(&mut self) {
        self.job.cancel();
        self.jobs.end(self.session.as_deref(), &self.job);
    }
}

impl Jobs {
    /// No jobs yet; at most `max_running` at once (at least one).
    pub(crate) fn new(max_running: usize) -> Self {
        Self { by_session: Mutex::default(), running: Mutex::default(), max_running: max_running.max(1) }
    }

    /// A new job for `session`, cancelling the one it replaces; 503 when too many run. The job
    /// ends when the returned guard drops.
    pub(crate) fn run(&self, session: Option<&str>) -> Result<Running<'_>, ApiError> {
        let job = self.start(session)?;
        Ok(Running { jobs: self, session: session.map(str::to_owned), job })
    }

    /// A new job for `session`, cancelling the one it replaces; 503 when too many run.
    pub(crate) fn start(&self, session: Option<&str>) -> Result<Arc<Job>, ApiError> {
        let mut running = self.running.lock().unwrap_or_else(PoisonError::into_inner);
        if *running >= self.max_running {
            let error = format!("{} jobs are running: try again when one ends", self.max_running);
            return Err(ApiError::new(StatusCode::SERVICE_UNAVAILABLE, error));
        }
        *running += 1;
        let job = Arc::new(Job::default());
        if let Some(session) = session {
            let mut jobs = self.by_session.lock().unwrap_or_else(PoisonError::into_inner);
            if let Some(older) = jobs.insert(session.to_owned(), Arc::clone(&job)) {
                older.cancel();
            }
        }
        Ok(job)
    }

    /// `job` ended: it is no longer `session`'s running job (unless a newer one replaced it).
    pub(crate) fn end(&self, session: Option<&str>, job: &Arc<Job>) {
        *self.running.lock().unwrap_or_else(PoisonError::into_inner) -= 1;
        if let Some(session) = session {
            let mut jobs = self.by_session.lock().unwrap_or_else(PoisonError::into_inner);
            if jobs.get(session).is_some_and(|current| Arc::ptr_eq(current, job)) {
                jobs.remove(session);
            }
        }
    }

    /// How many jobs run.
    #[cfg(test)]
    pub(crate) fn running(&self) -> usize {
        *self.running.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// `session`'s running job.
    pub(crate) fn get(&self, session: &str) -> Option<Arc<Job>> {
        self.by_session.lock().unwrap_or_else(PoisonError::into_inner).get(session).cloned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief::Progress as _;

    #[test]
    fn a_newer_job_cancels_the_older_one_of_its_session_only() {
        let jobs = Jobs::new(8);
        let first = jobs.start(Some("a")).unwrap();
        let other = jobs.start(Some("b")).unwrap();
        let anonymous = jobs.start(None).unwrap();
        let second = jobs.start(Some("a")).unwrap();
        let cancelled = |job: &Arc<Job>| JobProgress(Arc::clone(job)).cancelled();
        assert!(cancelled(&first));
        assert!(!cancelled(&second) && !cancelled(&other) && !cancelled(&anonymous));
        // The older job ending leaves the newer one in place.
        jobs.end(Some("a"), &first);
        assert!(Arc::ptr_eq(&jobs.get("a").unwrap(), &second));
        jobs.end(Some("a"), &second);
        assert!(jobs.get("a").is_none());
        jobs.end(Some("b"), &other);
        jobs.end(None, &anonymous);
        assert_eq!(*jobs.running.lock().unwrap(), 0);
    }

    #[test]
    fn a_dropped_guard_cancels_its_job_and_frees_its_place() {
        let jobs = Jobs::new(8);
        let running = jobs.run(Some("a")).unwrap();
        let job = Arc::clone(&running.job);
        assert!(jobs.get("a").is_some() && !job.cancelled.load(Ordering::Relaxed));
        drop(running);
        assert!(job.cancelled.load(Ordering::Relaxed), "an abandoned generation stops");
        assert!(jobs.get("a").is_none());
        assert_eq!(*jobs.running.lock().unwrap(), 0);
    }

    #[test]
    fn progress_is_recorded() {
        let job = Arc::new(Job::default());
        let mut progress = JobProgress(Arc::clone(&job));
        progress.start("growth");
        progress.advance("growth", 3, 10);
        let state = job.state();
        assert_eq!((state.step, state.done, state.total), ("growth", 3, 10));
    }

    #[test]
    fn too_many_running_jobs_are_refused() {
        let jobs = Jobs::new(8);
        let held: Vec<_> = (0..8).map(|_| jobs.start(None).unwrap()).collect();
        assert!(jobs.start(Some("x")).is_err());
        jobs.end(None, &held[0]);
        assert!(jobs.start(Some("x")).is_ok());
    }
}
