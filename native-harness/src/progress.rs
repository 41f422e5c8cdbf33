//! Spinners for steps that may take longer than a second. Drawn on stderr only when it is a
//! terminal, so piped output and `--json` stay clean.

use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

/// Runs `work` under a spinner labelled `label`; the spinner appears only after a second.
pub fn step<T>(label: &str, work: impl FnOnce() -> T) -> T {
    let bar = ProgressBar::new_spinner();
    bar.set_style(ProgressStyle::with_template("{spinner} {msg} {elapsed}").expect("template"));
    bar.set_message(label.to_string());
    // The first tick comes after a second, so fast steps never draw anything.
    bar.enable_steady_tick(Duration::from_millis(1000));
    let out = work();
    bar.finish_and_clear();
    out
}

/// A bar over the sampler's `steps` on stderr; hidden when `quiet` (e.g. `--json`) or when
/// stderr is not a terminal.
pub fn step_bar(steps: usize, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(steps as u64);
    bar.set_style(
        ProgressStyle::with_template("sampling [{bar:30}] {pos}/{len} steps {elapsed}")
            .expect("template"),
    );
    bar
}
