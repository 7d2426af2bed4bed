//! `cimax`: placeholder until the arena exists.
fn main() {}
