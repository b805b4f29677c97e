//! `relief`: terrain from a few strokes of intent, on the command line.
//!
//! `relief demo` generates the built-in scene; `relief generate SCENE.json` any scene file;
//! `contours`, `convert`, `info` and `preview` work on existing DEMs. Argument parsing is clap
//! (derive), progress is indicatif spinners on stderr (hidden when stderr is not a terminal or with
//! `--quiet`), errors are anyhow chains printed on one line. Exit codes: 0 success, 1 failure,
//! 2 usage error.
//!
//! Layout: this file parses the command line, starts the thread pool, dispatches to the command
//! and prints its error; [`cli`] holds the clap types and value parsers; [`commands`] one module
//! per command family (`scenes`: demo, generate, diffuse, schema; `dem`: contours, convert, info,
//! preview; `analyze`; `vector`: vectorize, rasterize); [`ui`] the spinners, timings and budgeted
//! reads every command shares; [`memory`] the allocator's set-up.
#![deny(unsafe_code)]

mod cli;
mod commands;
mod memory;
mod ui;
mod writes;

use std::io::IsTerminal as _;
use std::process::ExitCode;

use anyhow::{Context as _, Result};

use crate::cli::{Cli, Command};
use crate::commands::{analyze, dem, prominence, scenes, serve, shell, vector};
use crate::ui::{Ui, Verbosity};

fn main() -> ExitCode {
    memory::keep_freed_memory();
    // Usage errors exit here, with clap's code 2.
    let cli = Cli::from_env();
    match run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            // On a terminal, show the line of a scene error and point at the column.
            if let Some(snippet) = e.chain().find_map(|c| c.downcast_ref::<commands::scenes::Snippet>())
                && std::io::stderr().is_terminal()
            {
                eprintln!("{}", snippet.caret());
            }
            if over_budget(&e) { ExitCode::from(2) } else { ExitCode::FAILURE }
        }
    }
}

/// Whether `e` refused work over the budget (`--max-cells`, `--max-bytes`, `--max-primitives`,
/// a raster bigger than the read limit): exit 2, as for a usage error, since nothing was tried.
fn over_budget(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<relief::ReliefError>().is_some_and(relief::ReliefError::is_over_budget)
            || c.downcast_ref::<relief::io::IoError>().is_some_and(relief::io::IoError::is_over_limit)
    })
}

fn run(cli: &Cli) -> Result<()> {
    if let Some(n) = cli.threads {
        rayon::ThreadPoolBuilder::new().num_threads(n.into()).build_global().context("starting the thread pool")?;
    }
    let verbosity = match (cli.quiet, cli.verbose) {
        (true, _) => Verbosity::Quiet,
        (false, true) => Verbosity::Verbose,
        (false, false) => Verbosity::Normal,
    };
    let ui = &mut Ui::new(verbosity, cli.force, cli.budget(), cli.read_options());
    match &cli.command {
        Command::Demo(args) => scenes::demo(args, ui),
        Command::Generate(args) => scenes::generate(args, ui),
        Command::Diffuse(args) => scenes::diffuse(args, ui),
        Command::Schema => {
            scenes::schema();
            Ok(())
        }
        Command::Contours(args) => dem::contours(args, ui),
        Command::Convert(args) => dem::convert(args, ui),
        Command::Export(args) => dem::export(args, ui),
        Command::Info(args) => dem::info(args, ui),
        Command::Preview(args) => dem::preview(args, ui),
        Command::Analyze(args) => analyze::analyze(args, ui),
        Command::Prominence(args) => prominence::prominence(args, ui),
        Command::Vectorize(args) => vector::vectorize(args, ui),
        Command::Rasterize(args) => vector::rasterize(args, ui),
        Command::Serve(args) => serve::serve(args, ui),
        Command::Completions(args) => {
            shell::completions(args);
            Ok(())
        }
        Command::Man => shell::man(),
    }
}

/// `error`'s cause chain on one line: its own text, then `: cause` for each cause whose text is
/// not already contained in the line so far.
///
/// The facade's errors both display their source (`ReliefError::Scene` reads `path: <source>`)
/// and return it from [`std::error::Error::source`], so anyhow's `{:#}`, which appends every
/// cause, would tell such a cause twice. Wrappers that do not repeat their source (anyhow's
/// `.context(…)`) still get it appended.
fn one_line(error: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in error.chain() {
        let text = cause.to_string();
        if line.is_empty() {
            line = text;
        } else if !line.contains(&text) {
            line.push_str(": ");
            line.push_str(&text);
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use std::fmt;

    use super::one_line;

    /// An error that, like the facade's, displays its source after a location and also returns it.
    #[derive(Debug)]
    struct Located {
        path: &'static str,
        source: std::io::Error,
    }

    impl fmt::Display for Located {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(f, "{}: {}", self.path, self.source)
        }
    }

    impl std::error::Error for Located {
        fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
            Some(&self.source)
        }
    }

    #[track_caller]
    fn check(error: &anyhow::Error, expected: &str) {
        assert_eq!(one_line(error), expected);
    }

    fn located(path: &'static str, reason: &str) -> anyhow::Error {
        Located { path, source: std::io::Error::other(reason.to_owned()) }.into()
    }

    #[test]
    fn a_cause_already_displayed_is_not_repeated() {
        check(&located("slope.theta", "95 is out of range"), "slope.theta: 95 is out of range");
        check(
            &located("slope.theta", "95 is out of range").context("scene.json"),
            "scene.json: slope.theta: 95 is out of range",
        );
    }

    #[test]
    fn causes_not_yet_displayed_are_appended_in_order() {
        let e = anyhow::anyhow!("No such file").context("reading a.json").context("loading the scene");
        check(&e, "loading the scene: reading a.json: No such file");
        check(&anyhow::anyhow!("alone"), "alone");
    }
}
