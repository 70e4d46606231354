//! `cargo run --release -p packaging`: build and write `target/fmu/*.fmu` and `ClosedLoop.ssp`.
fn main() -> anyhow::Result<()> {
    for p in packaging::package_all()? {
        println!("wrote {}", p.display());
    }
    Ok(())
}
