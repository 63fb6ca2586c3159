//! SIGINT (Ctrl-C) and SIGTERM: the temporary files outputs are staged in
//! are removed ([`momentlmi::tempfiles::remove_all`]: the previous outputs
//! stay as they were) and the process ends with 128 + the signal's number
//! (130, 143), as a shell reports a command a signal stopped.

/// Starts the thread that waits for SIGINT and SIGTERM; a warning if the
/// handlers cannot be installed (the signals then end the process as by
/// default, and may leave staged files behind).
#[cfg(unix)]
pub fn remove_staged_files_on_signals() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut signals = match signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) {
        Ok(s) => s,
        Err(e) => {
            eprintln!(
                "warning: cannot handle SIGINT and SIGTERM ({e}): an interrupted run may leave .momentlmi-*.tmp files"
            );
            return;
        }
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            momentlmi::tempfiles::remove_all();
            std::process::exit(128 + signal);
        }
    });
}

#[cfg(not(unix))]
pub fn remove_staged_files_on_signals() {}
