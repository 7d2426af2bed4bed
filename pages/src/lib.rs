//! # pages: the simulators' results as pages, figures and CSV files
//!
//! The layer that writes, and runs nothing: the experiments (`reproduce`, `lab`) return result
//! structs, and this crate turns them into figures ([`figures`]), CSV files ([`csv`]) and pages
//! ([`reliability`], [`reproduction`] with its [`waves`] section), rendered
//! from the templates in `pages/templates/` ([`page`]), through `report`'s generic pieces (CSV
//! writer, x–y figure, legend). And what the
//! pages say about the paper: its claims as data ([`claims`]), how ours is judged against each
//! ([`verdict`]), and the paper's marks on the figures ([`marks`]).

pub mod claims;
pub mod csv;
pub mod figures;
pub mod marks;
pub mod page;
pub mod paper;
pub mod reliability;
pub mod reproduction;
pub mod verdict;
pub mod waves;
