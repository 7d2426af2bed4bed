//! Writes the seed corpus (`src/corpus.rs`) to `fuzz/corpus/<target>/`, replacing it.
//!
//! ```text
//! cd fuzz && cargo run --example gen_corpus
//! ```

use std::path::Path;

fn main() -> std::io::Result<()> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus");
    let n = protocol_fuzz::corpus::write(&dir)?;
    println!("wrote {n} seed files under {}", dir.display());
    Ok(())
}
