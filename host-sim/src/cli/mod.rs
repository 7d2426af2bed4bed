//! The binary's commands beyond parsing: `cimax arena` ([`arena`]) and the `cimax swarm`
//! commands ([`swarm`]). Each turns its options into the library's experiments and prints or
//! writes what they return.

pub mod arena;
pub mod swarm;
