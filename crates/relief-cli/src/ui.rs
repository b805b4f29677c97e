//! What the user sees besides a command's report: spinners on stderr, step timings with `-v`,
//! warnings, and the budget that every read and scene runs under.

use std::io::IsTerminal as _;
use std::path::Path;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use relief::Progress;
use relief::heightfield::Heightfield;

use crate::writes::Writes;

/// How much a command tells besides its errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Verbosity {
    /// `-q`: nothing.
    Quiet,
    /// Its report, warnings, and spinners on a terminal.
    Normal,
    /// `-v`: also the time of every step.
    Verbose,
}

/// Spinners on stderr, step timings with `-v`, reports on stdout unless `-q`.
pub(crate) struct Ui {
    /// What every command reads under: the budget's cell cap and the global read flags.
    read: relief::io::ReadOptions,
    /// The budget scenes run under.
    budget: relief::Budget,
    verbosity: Verbosity,
    /// `--force`: outputs may replace existing files.
    force: bool,
    bar: Option<ProgressBar>,
    draw: bool,
}

impl Ui {
    pub(crate) fn new(
        verbosity: Verbosity,
        force: bool,
        budget: relief::Budget,
        read: relief::io::ReadOptions,
    ) -> Self {
        let draw = verbosity != Verbosity::Quiet && std::io::stderr().is_terminal();
        Self { read, budget, verbosity, force, bar: None, draw }
    }

    /// The files a command reads and writes, to check before it works ([`Writes::check`]).
    pub(crate) fn writes(&self) -> Writes {
        Writes::new(self.force)
    }

    /// Whether reports are silenced (`-q`).
    pub(crate) fn quiet(&self) -> bool {
        self.verbosity == Verbosity::Quiet
    }

    /// The budget the flags set.
    pub(crate) fn budget(&self) -> relief::Budget {
        self.budget
    }

    /// The options every read uses: the budget's cell cap.
    pub(crate) fn read_options(&self) -> relief::io::ReadOptions {
        self.read.clone()
    }

    /// Reads a heightfield under the cell budget, as a timed step.
    pub(crate) fn read(&mut self, path: &Path) -> Result<Heightfield, relief::io::IoError> {
        let read = self.read.clone();
        self.read_with(path, &read)
    }

    /// Reads a heightfield with `options` (derived from [`Ui::read_options`]), as a timed step.
    pub(crate) fn read_with(
        &mut self,
        path: &Path,
        options: &relief::io::ReadOptions,
    ) -> Result<Heightfield, relief::io::IoError> {
        let (dem, notes) = self.step("read", || relief::io::read_with_notes(path, options))?;
        for note in notes {
            self.warn(format_args!("{}: {note}", path.display()));
        }
        Ok(dem)
    }

    /// Prints a line of the report on stdout, unless `-q`.
    pub(crate) fn say(&self, message: std::fmt::Arguments<'_>) {
        if !self.quiet() {
            println!("{message}");
        }
    }

    /// Prints `warning: message` on stderr, unless `-q`.
    pub(crate) fn warn(&self, message: std::fmt::Arguments<'_>) {
        if !self.quiet() {
            eprintln!("warning: {message}");
        }
    }

    /// Runs `f` as a step with a spinner.
    pub(crate) fn step<T>(&mut self, name: &'static str, f: impl FnOnce() -> T) -> T {
        self.start(name);
        let start = Instant::now();
        let out = f();
        self.finish(name, start.elapsed());
        out
    }

    /// A progress bar of `len` steps drawn with `template` (an indicatif template), hidden where
    /// spinners are.
    pub(crate) fn bar(&self, len: u64, template: &str) -> ProgressBar {
        let bar = ProgressBar::with_draw_target(Some(len), self.draw_target());
        bar.set_style(ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()));
        bar
    }

    fn draw_target(&self) -> ProgressDrawTarget {
        if self.draw { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() }
    }
}

impl Progress for Ui {
    fn start(&mut self, step: &'static str) {
        let bar = ProgressBar::with_draw_target(None, self.draw_target());
        bar.set_style(
            ProgressStyle::with_template("{spinner} {msg} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.set_message(step);
        bar.enable_steady_tick(Duration::from_millis(100));
        self.bar = Some(bar);
    }

    fn advance(&mut self, _: &'static str, done: u64, total: u64) {
        let Some(bar) = &self.bar else { return };
        if total == 0 {
            return;
        }
        if bar.length() != Some(total) {
            bar.set_length(total);
            bar.set_style(
                ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} {elapsed}, about {eta} left")
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
        }
        bar.set_position(done);
    }

    fn finish(&mut self, step: &'static str, elapsed: Duration) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
        if self.verbosity == Verbosity::Verbose {
            eprintln!("{step:>15} {:>9.1} ms", elapsed.as_secs_f64() * 1e3);
        }
    }
}
