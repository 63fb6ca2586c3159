//! The `momentlmi` binary: a thin shell over [`momentlmi_cli::main`].
fn main() {
    std::process::exit(momentlmi_cli::main());
}
