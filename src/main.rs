//! The `momentlmi` binary: a thin shell over [`momentlmi::cli`].
fn main() {
    std::process::exit(momentlmi::cli::main());
}
