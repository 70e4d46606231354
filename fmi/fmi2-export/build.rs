//! Wraps `src/exports.rs` (the one list of FMI entry points, also read by
//! cbindgen) into the `export_fmi2!` macro.
fn main() {
    let src = std::path::Path::new("src/exports.rs");
    println!("cargo:rerun-if-changed={}", src.display());
    let body = std::fs::read_to_string(src).expect("read src/exports.rs");
    let macro_src = format!(
        "/// Export the FMI 2.0 Co-Simulation C API of `$model` from this cdylib.\n\
         ///\n\
         /// Invoke once, at the crate root of a `cdylib` whose library name is the\n\
         /// model's `modelIdentifier`. `$model` must be a path that resolves from a\n\
         /// child module (e.g. `my_crate::MyModel` or `crate::MyModel`).\n\
         #[macro_export]\n\
         macro_rules! export_fmi2 {{\n    ($model:ty) => {{\n\
         #[doc(hidden)]\n\
         #[allow(non_snake_case, missing_docs, clippy::missing_safety_doc, unused_imports)]\n\
         pub mod __fmi2_exports {{\n\
         use super::*;\n\
         use ::fmi2_export::abi::*;\n\
         type Model = $model;\n\
         {body}\n\
         }}\n    }};\n}}\n"
    );
    let out = std::path::PathBuf::from(std::env::var("OUT_DIR").unwrap()).join("export_macro.rs");
    std::fs::write(out, macro_src).expect("write export_macro.rs");
}
