//! Progress on stderr: spinners for the long steps of every command (indicatif), hidden when
//! stderr is not a terminal (indicatif's own check) or with `-q`.

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

static QUIET: AtomicBool = AtomicBool::new(false);

/// Sets `-q` for the whole run.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Relaxed);
}

/// True with `-q`: no progress and no notes on stderr.
pub fn quiet() -> bool {
    QUIET.load(Relaxed)
}

/// A spinner with `message` and the elapsed time, ticking on its own until it is dropped or
/// finished (hidden with `-q`).
pub fn spinner(message: impl Into<std::borrow::Cow<'static, str>>) -> ProgressBar {
    if quiet() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr()).with_style(
        ProgressStyle::with_template("{spinner} {msg} {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    bar.set_message(message);
    bar.enable_steady_tick(Duration::from_millis(100));
    bar
}

/// A bar counting `len` items (files of a batch), hidden with `-q`.
pub fn counter(len: usize, message: &'static str) -> ProgressBar {
    if quiet() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(len as u64), ProgressDrawTarget::stderr())
        .with_style(
            ProgressStyle::with_template("{bar:30} {pos}/{len} {msg} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
    bar.set_message(message);
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}

/// Runs `work` under a spinner saying `message`, then clears it.
pub fn step<T>(message: impl Into<std::borrow::Cow<'static, str>>, work: impl FnOnce() -> T) -> T {
    let bar = spinner(message);
    let result = work();
    bar.finish_and_clear();
    result
}

/// `n` and the noun for it: `1 vertex`, `2 vertices`.
pub fn counted(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// Writes a note on stderr unless `-q`.
macro_rules! note {
    ($($arg:tt)*) => {
        if !$crate::progress::quiet() {
            eprintln!($($arg)*);
        }
    };
}
pub(crate) use note;
