//! Compiles the C shim that implements the variadic FMI logger callback.
fn main() {
    println!("cargo:rerun-if-changed=csrc/logger_shim.c");
    cc::Build::new().file("csrc/logger_shim.c").warnings(true).extra_warnings(true).compile("fmi_master_logger_shim");
}
