//! What the command line says about itself: shell completions and the man page, both generated
//! from the clap definitions so they never disagree with the tool.

use anyhow::{Context as _, Result};

use crate::cli::{CompletionsArgs, command};

/// `relief completions SHELL`: the completion script on stdout.
pub(crate) fn completions(args: &CompletionsArgs) {
    let mut cmd = command();
    clap_complete::generate(args.shell, &mut cmd, "relief", &mut std::io::stdout());
}

/// `relief man`: the man page (roff) on stdout.
pub(crate) fn man() -> Result<()> {
    clap_mangen::Man::new(command()).render(&mut std::io::stdout()).context("writing the man page")
}
