//! The binary's commands beyond parsing: `cimax arena` ([`arena`]), the `cimax swarm`
//! commands ([`swarm`]) and `cimax merge` ([`merge`], the parts of sharded commands put
//! together). Each turns its options into the library's experiments and prints or writes what
//! they return.

pub mod arena;
pub mod files;
pub mod job;
pub mod merge;
pub mod out;
pub mod swarm;
pub mod values;
