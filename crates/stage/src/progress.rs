//! Progress bars that show on a terminal and stay silent otherwise (CI, pipes, tests).

use std::io::IsTerminal;
use std::sync::OnceLock;

use indicatif::{MultiProgress, ProgressBar, ProgressStyle};

/// A progress bar over `len` steps labelled `label`, with the elapsed time and an estimate of
/// the time left; hidden when stderr is not a terminal or
/// when the `CI` environment variable is set. Bars shown at the same time (the mesher's three
/// surfaces run side by side) each keep a line of their own.
pub fn bar(len: u64, label: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() || std::env::var_os("CI").is_some() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len);
    let style = ProgressStyle::with_template("{prefix:>10} [{bar:30}] {percent:>3}% {elapsed} (ETA {eta})")
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ");
    bar.set_style(style);
    bar.set_prefix(label.to_string());
    static SHOWN: OnceLock<MultiProgress> = OnceLock::new();
    SHOWN.get_or_init(MultiProgress::new).add(bar)
}
