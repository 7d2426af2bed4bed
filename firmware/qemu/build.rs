//! cortex-m-rt's `link.x`, with this directory's `memory.x` (mps2-an386).

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory.x");
    if std::env::var("TARGET")
        .unwrap_or_default()
        .starts_with("thumb")
    {
        let dir = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it");
        println!("cargo:rustc-link-arg-bins=-L{dir}");
        println!("cargo:rustc-link-arg-bins=-Tlink.x");
    }
}
