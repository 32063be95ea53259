//! `vibroatlas explore`: serves the interactive atlas until Ctrl-C.

use crate::args::ExploreArgs;
use crate::out::outln;
use anyhow::Result;

/// Runs the command.
pub fn run(a: ExploreArgs) -> Result<()> {
    let r = explore::ExploreRequest { file: a.file.clone(), port: a.port, threads: engine::threads(a.threads)? };
    let server = explore::serve(&r)?;
    outln!("exploring {} at {}", a.file.display(), server.url());
    outln!("(Ctrl-C stops the server)");
    if !a.no_browser {
        open_browser(server.url());
    }
    // Ctrl-C or SIGTERM: the server stops, its zooms cancelled and their files removed.
    crate::interrupt::install();
    while !crate::interrupt::requested() {
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    server.stop();
    Ok(())
}

/// Opens the page in the desktop's browser, if there is one (`xdg-open`,
/// `open` on macOS); the URL printed is enough without.
fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") { "open" } else { "xdg-open" };
    let _ = std::process::Command::new(opener)
        .arg(url)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
}
