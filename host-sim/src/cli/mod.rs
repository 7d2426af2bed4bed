//! The binary's commands beyond parsing: the `cimax swarm` commands ([`swarm`]). `cimax arena`
//! is the library's [`host_sim::arena::line`].

pub mod swarm;
