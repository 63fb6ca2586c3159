//! The `momentlmi` binary: a thin shell over [`momentlmi_cli::main`].

/// mimalloc: the logs' per-sample rows and the reduction's blocks are many
/// allocations; glibc's malloc maps and faults in every large block anew
/// (docs/benchmarks.md has the difference).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    // Clarabel panics on some numerically hopeless problems; the conic layer
    // catches that and reports a solver error, so the panic's own message
    // would only alarm. Every other panic is a bug and is printed as usual.
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let in_solver = info
            .location()
            .is_some_and(|l| l.file().contains("clarabel"));
        if !in_solver {
            default(info);
        }
    }));
    // A reader that closes the pipe (`momentlmi check robot.urdf | head`)
    // ends the process quietly, as it ends other Unix tools, instead of a
    // panic in the next print.
    #[cfg(unix)]
    // SAFETY: restoring the default action of one signal before any thread
    // starts; no handler of ours is involved.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // Transparent huge pages off for this process: mimalloc's arenas would
    // otherwise fault in (and zero) 2 MiB at a time, doubling the peak
    // memory of a streamed identification for no speed (docs/benchmarks.md)
    #[cfg(target_os = "linux")]
    // SAFETY: prctl with an integer option and integer arguments only
    unsafe {
        libc::prctl(libc::PR_SET_THP_DISABLE, 1, 0, 0, 0);
    }
    // SIGINT and SIGTERM remove the staged outputs' temporary files and
    // end the process with 130 or 143
    momentlmi_cli::interrupt::remove_staged_files_on_signals();
    std::process::exit(momentlmi_cli::main());
}
