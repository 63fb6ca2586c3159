//! `cargo run --release -p momentlmi-downstream --example leg`

fn main() {
    match momentlmi_downstream::run(10.0) {
        Ok(r) => println!("{r:#?}"),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    }
}
