//! Linker scripts for the `nucleo_l476` binary, on thumb targets only: cortex-m-rt's `link.x`
//! with the repository's top-level `memory.x` (STM32L476RG), and `defmt.x`.
//!
//! rustc links from the workspace root, so `INCLUDE memory.x` in `link.x` finds the top-level
//! file first; the `-L` below only makes that explicit. This is also why the QEMU board is a
//! package of its own (`qemu/`, own workspace): in this workspace it would get this memory map.

use std::env;
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if !env::var("TARGET").unwrap_or_default().starts_with("thumb") {
        return;
    }
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let root = manifest.parent().expect("firmware/ sits in the workspace");
    println!("cargo:rerun-if-changed={}", root.join("memory.x").display());
    println!("cargo:rustc-link-arg-bin=nucleo_l476=-L{}", root.display());
    println!("cargo:rustc-link-arg-bin=nucleo_l476=-Tlink.x");
    println!("cargo:rustc-link-arg-bin=nucleo_l476=-Tdefmt.x");
}
