//! Ctrl-C and friends: a stopped run leaves no partial output file.
//!
//! Every file is written to a temporary file and renamed into place when complete
//! ([`crestline::io::write_atomically`]). A process ended by a signal runs no destructors, so
//! the temporary files of the writes in progress would stay behind: a watcher thread waits for
//! SIGINT, SIGTERM and SIGHUP, removes them ([`crestline::io::abandon_writes`]) and ends the
//! process with the shell's status for that signal (128 + its number: 130 for Ctrl-C, 143 for
//! SIGTERM, 129 for SIGHUP). Files finished before the signal (earlier meshes of a batch) stay.
//!
//! A closed or full standard output or error (`crestline info m.obj | head -1`, `2>/dev/full`)
//! ends the process the same way, quietly: 141 for a closed pipe (128 + SIGPIPE, as the tools
//! a shell pipes into expect), 1 otherwise ([`end_quietly_when_output_fails`]).

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
use signal_hook::iterator::Signals;

/// Starts the watcher thread. Without it (the signals could not be registered, which does not
/// happen on a normal system) a signal ends the process as by default, temporary files left.
pub fn remove_partial_outputs_on_signals() {
    let Ok(mut signals) = Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    let watcher = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                crestline::io::abandon_writes();
                // The line a spinner may have left unfinished is ended first.
                eprintln!("\nerror: interrupted (signal {signal}): no partial output left");
                std::process::exit(128 + signal);
            }
        });
    // A thread that cannot start leaves the default behaviour, as above.
    drop(watcher);
}

/// Makes a failed write to standard output or error (the print macros panic on it: a closed
/// pipe, a full device) end the process without a panic message and without partial output
/// files, with status 141 for a closed pipe and 1 otherwise. Other panics are reported as
/// before.
pub fn end_quietly_when_output_fails() {
    let report = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.starts_with("failed printing to std") {
            crestline::io::abandon_writes();
            let closed = message.contains("Broken pipe") || message.contains("os error 32");
            std::process::exit(if closed { 141 } else { 1 });
        }
        report(info);
    }));
}
