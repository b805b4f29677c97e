//! `relief serve`: the studio ([`relief_studio`]) on a local port.

use anyhow::{Context as _, Result};

use crate::cli::ServeArgs;
use crate::ui::Ui;

/// Binds, prints the address, optionally opens a browser, and serves until Ctrl-C.
pub(crate) fn serve(args: &ServeArgs, ui: &mut Ui) -> Result<()> {
    let runtime = tokio::runtime::Runtime::new().context("starting the server's runtime")?;
    runtime.block_on(async {
        let listener = tokio::net::TcpListener::bind((args.host, args.port))
            .await
            .with_context(|| format!("listening on {}:{} (try another --port)", args.host, args.port))?;
        let address = listener.local_addr().context("reading the bound address")?;
        let url = format!("http://{address}/");
        let mut config = relief_studio::Config::new(&args.workspace).with_budget(ui.budget());
        config.loopback_only = args.host.is_loopback();
        ui.say(format_args!("relief studio at {url} (workspace {}; Ctrl-C stops it)", args.workspace.display()));
        if !args.host.is_loopback() {
            ui.warn(format_args!("listening on {}: other machines can reach the studio", args.host));
        }
        if args.open
            && let Err(error) = open_browser(&url)
        {
            ui.warn(format_args!("could not open a browser ({error}): open {url} yourself"));
        }
        relief_studio::serve(listener, config).await.context("serving the studio")
    })
}

/// Opens `url` with the desktop's handler.
fn open_browser(url: &str) -> std::io::Result<()> {
    let mut command = if cfg!(target_os = "macos") {
        std::process::Command::new("open")
    } else if cfg!(windows) {
        let mut c = std::process::Command::new("cmd");
        c.args(["/C", "start", ""]);
        c
    } else {
        std::process::Command::new("xdg-open")
    };
    command.arg(url).stdout(std::process::Stdio::null()).stderr(std::process::Stdio::null()).spawn().map(drop)
}
