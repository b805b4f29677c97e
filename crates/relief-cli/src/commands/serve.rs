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
        let mut config = relief_studio::Config::new(&args.workspace).with_budget(ui.budget());
        // `::ffff:127.0.0.1` is loopback too.
        let loopback = args.host.to_canonical().is_loopback();
        config.loopback_only = loopback;
        let mut url = format!("http://{address}/");
        if !loopback {
            // Other machines can reach it: only those given the printed address get in.
            let token = relief_studio::new_token().context("drawing the studio's token")?;
            url = format!("{url}?token={token}");
            config.token = Some(token);
        }
        ui.say(format_args!("relief studio at {url} (workspace {}; Ctrl-C stops it)", args.workspace.display()));
        if !loopback {
            ui.warn(format_args!(
                "listening on {}: other machines can reach the studio; it answers only those given the address \
                 above (its token), over plain HTTP",
                args.host
            ));
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
