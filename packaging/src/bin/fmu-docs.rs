//! `cargo run --release -p packaging --bin fmu-docs`: write each FMU's page of the docs book
//! (`docs/book/fmus/<modelIdentifier>.md`, the same page as the FMU's `documentation/index.html`).
//! `-- --html DIR` also writes each FMU's `documentation/index.html` as `DIR/<modelIdentifier>.html`
//! (to look at it without building the FMUs).
use anyhow::Context;

fn main() -> anyhow::Result<()> {
    for p in packaging::documentation::write_book_pages(&packaging::workspace_root())? {
        println!("wrote {}", p.display());
    }
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.as_slice() {
        [] => {}
        [flag, dir] if flag == "--html" => {
            std::fs::create_dir_all(dir).with_context(|| dir.clone())?;
            for p in &packaging::PRODUCTS {
                let md = (p.description)();
                let path = std::path::Path::new(dir).join(format!("{}.html", md.model_identifier().unwrap_or("fmu")));
                std::fs::write(&path, packaging::documentation_html(md, p.documentation))
                    .with_context(|| path.display().to_string())?;
                println!("wrote {}", path.display());
            }
        }
        _ => anyhow::bail!("usage: fmu-docs [--html DIR]"),
    }
    Ok(())
}
