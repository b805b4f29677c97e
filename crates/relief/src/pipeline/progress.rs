//! Progress reports: each step of a run starts, then finishes; the timer forwards them to the
//! caller and keeps the timings for the summary.

use std::time::{Duration, Instant};

use serde::Serialize;

use crate::ReliefError;

/// Receives the pipeline's progress: each step starts, then finishes. The contour generator's
/// steps are `"inputs"`, `"graph"`, `"growth"`, `"heights"`, `"contours"`, `"edits"` and
/// `"reconstruction"`; the raster generators name theirs (`"diffusion"`, `"island"`,
/// `"source"`, `"tools"`, `"rasterize"`, `"divide tree"`, `"terrain"`, …); every run then has
/// `"post-process"` (when the scene has any), `"drainage"`, and `"write"` when outputs are
/// written. Steps whose work can be counted also report how far they are ([`Progress::advance`]).
/// The unit type `()` ignores everything.
pub trait Progress {
    /// `step` starts.
    fn start(&mut self, step: &'static str);
    /// `step` finished after `elapsed`.
    fn finish(&mut self, step: &'static str, elapsed: Duration);
    /// Within `step`, `done` of `total` units of work are done: the island's operations, the
    /// Gaussian tools, a DEM's vectorization (its fitting iterations), a diffusion (three units:
    /// holes filled, elevation solved, noise solved), the contour edits, the post-processing
    /// iterations (each erosion pass one unit). Called with `done` rising from 0 to `total`; ignored by default.
    fn advance(&mut self, step: &'static str, done: u64, total: u64) {
        let _ = (step, done, total);
    }

    /// Whether the caller wants the run to stop: checked before each step (and, in counted
    /// steps, before each unit of work; within a DEM's fit after each iteration, within a
    /// diffusion after each batch of hole fills and each solver iteration), the run then ends
    /// with [`ReliefError::Cancelled`].
    /// Never, by default.
    fn cancelled(&self) -> bool {
        false
    }
}

/// What a step returns that can stand for a cancelled step: results whose error is a
/// [`ReliefError`].
pub(crate) trait Interruptible {
    /// The value of a step that did not run.
    fn cancelled() -> Self;
}

impl<T> Interruptible for Result<T, ReliefError> {
    fn cancelled() -> Self {
        Err(ReliefError::Cancelled)
    }
}

impl Progress for () {
    fn start(&mut self, _: &'static str) {}
    fn finish(&mut self, _: &'static str, _: Duration) {}
}

/// The time one step took.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Timing {
    /// The step.
    pub step: &'static str,
    /// Milliseconds.
    pub ms: f64,
}

/// Forwards to the caller's [`Progress`] and keeps the timings for the summary.
pub(crate) struct Timer<'a> {
    progress: &'a mut dyn Progress,
    pub(crate) timings: Vec<Timing>,
}

impl<'a> Timer<'a> {
    pub(crate) fn new(progress: &'a mut dyn Progress) -> Self {
        Self { progress, timings: Vec::new() }
    }

    /// Runs `f` as the step `step`, unless the caller has cancelled the run.
    pub(crate) fn step<T: Interruptible>(&mut self, step: &'static str, f: impl FnOnce() -> T) -> T {
        self.timed(step, |_| f())
    }

    /// Runs `f` as the step `step` of `total` units of work, unless the caller has cancelled
    /// the run; `f` reports each unit done through the [`Tick`] it is given.
    pub(crate) fn counted<T: Interruptible>(
        &mut self,
        step: &'static str,
        total: u64,
        f: impl FnOnce(&mut Tick<'_>) -> T,
    ) -> T {
        self.timed(step, |progress| {
            progress.advance(step, 0, total);
            f(&mut Tick { progress, step, done: 0, total })
        })
    }

    /// Starts `step`, runs `f` with the caller's progress, finishes it and keeps its time; a
    /// cancelled run skips it.
    fn timed<T: Interruptible>(&mut self, step: &'static str, f: impl FnOnce(&mut dyn Progress) -> T) -> T {
        if self.progress.cancelled() {
            return T::cancelled();
        }
        self.progress.start(step);
        let start = Instant::now();
        let out = f(&mut *self.progress);
        let elapsed = start.elapsed();
        self.progress.finish(step, elapsed);
        self.timings.push(Timing { step, ms: elapsed.as_secs_f64() * 1e3 });
        out
    }
}

/// Counts the units of work of one step ([`Timer::counted`]) and reports each to the caller.
pub(crate) struct Tick<'a> {
    progress: &'a mut dyn Progress,
    step: &'static str,
    done: u64,
    total: u64,
}

impl Tick<'_> {
    /// One more unit is done (never counting past the total).
    pub(crate) fn tick(&mut self) {
        self.done = (self.done + 1).min(self.total);
        self.progress.advance(self.step, self.done, self.total);
    }

    /// `done` units are done (a step that counts its own units, as a fit counts its
    /// iterations), never past the total.
    pub(crate) fn reach(&mut self, done: u64) {
        self.done = done.min(self.total);
        self.progress.advance(self.step, self.done, self.total);
    }

    /// Whether the caller has cancelled the run, for work that stops through its own callback.
    pub(crate) fn cancelled(&self) -> bool {
        self.progress.cancelled()
    }

    /// [`ReliefError::Cancelled`] when the caller has cancelled the run: checked by counted
    /// steps between their units.
    pub(crate) fn check(&self) -> Result<(), ReliefError> {
        if self.cancelled() { Err(ReliefError::Cancelled) } else { Ok(()) }
    }
}
