//! `cargo run --release -p packaging --bin fmu-docs`: write each FMU's page of the docs book
//! (`docs/book/fmus/<modelIdentifier>.md`, the same page as the FMU's `documentation/index.html`).
fn main() -> anyhow::Result<()> {
    for p in packaging::documentation::write_book_pages(&packaging::workspace_root())? {
        println!("wrote {}", p.display());
    }
    Ok(())
}
