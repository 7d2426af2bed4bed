//! What the pages say about the paper: its claims as data ([`claims`]), how ours is judged
//! against each ([`verdict`]), and the paper's marks on the figures ([`marks`]). The
//! simulators (`swarm`, `arena`) return result structs; this layer turns them into verdicts and
//! marks; `report` draws and renders.

pub mod claims;
pub mod csv;
pub mod figures;
pub mod marks;
pub mod reliability;
pub mod reproduction;
pub mod shapes;
pub mod verdict;
pub mod waves;
