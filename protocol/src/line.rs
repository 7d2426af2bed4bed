//! A line of robots wired directly, for tests and quick experiments.
//!
//! Every message a robot sends is framed with [`crate::frame::encode`], and the bytes are fed at
//! once to the deframers of its immediate neighbours, on the receiver facing the sender (robot
//! `i − 1` hears robot `i` on its right, robot `i + 1` on its left). There is no light medium:
//! no transmission time, no loss, no collision (the emulator, `hal-emu`, models those). Time
//! jumps from one deadline to the next, so hours of robot time take milliseconds.
//!
//! Robot `i` has the tag `i mod 16` ([`Tag::from_id`]), so every robot within a message's reach
//! has a tag of its own.
//!
//! Everything is deterministic: robots are served in index order, and each has its own RNG.
//!
//! ## One of three lines, on purpose
//! The workspace wires robots in a line at three depths, and each tests what the others cannot:
//! - this one: the protocol core alone ([`FusedNode`]s and real frames, driven synchronously
//!   from deadline to deadline, no robot program, no executor). It lives here because the
//!   protocol's own tests may not depend on the firmware above it, and it exposes every node
//!   and deframer for inspection;
//! - `firmware::wired::run_line`: the real robot program (`Robot::run`: sampling, one
//!   deframer per receiver, timeouts, LEDs) on in-memory pipes, `no_std` and without tokio, so
//!   that the QEMU board runs it on a Cortex-M;
//! - `hal-emu`'s arena (`ArenaConfig::line`): the real robot program in the modelled light
//!   medium (airtime, range, collisions, loss), with kills, restarts and adversaries, on tokio.
//!
//! Merging any two would either pull a runtime into a `no_std` crate or take away the
//! synchronous, inspectable core the protocol's tests step through.

use rand_core::RngCore;

use crate::direction::Sector;
use crate::frame::{Deframer, encode};
use crate::fused::{Event, FusedNode};
use crate::message::{Level, MAX_TAGS, Message, Tag};
use crate::params::{ParamError, Params};
use crate::time::Instant;

/// What [`Line::run_until`] reports to its observer.
#[derive(Clone, Copy, Debug)]
pub enum Happening<'a> {
    /// The robot broadcast this message.
    Sent(&'a Message),
    /// The robot emitted this event.
    Event(Event),
}

/// `N` robots in a line, each with its own RNG `R`.
#[derive(Debug)]
pub struct Line<R: RngCore, const N: usize> {
    nodes: [FusedNode; N],
    /// Per robot: the deframer of its left receiver, then of its right one.
    deframers: [[Deframer; 2]; N],
    rngs: [R; N],
    now: Instant,
}

impl<R: RngCore, const N: usize> Line<R, N> {
    /// `N` robots starting at time zero with these readings and RNGs; robot `i` has the tag
    /// `i mod 16`.
    ///
    /// # Errors
    /// The [`ParamError`] if `params` do not validate.
    pub fn new(params: Params, readings: [Level; N], mut rngs: [R; N]) -> Result<Self, ParamError> {
        params.validate()?;
        let mut nodes: [Option<FusedNode>; N] = [const { None }; N];
        for (i, (slot, rng)) in nodes.iter_mut().zip(rngs.iter_mut()).enumerate() {
            let tag = Tag::from_id((i % MAX_TAGS) as u16);
            *slot = Some(FusedNode::new(params, tag, Instant::ZERO, rng)?);
        }
        let mut nodes = nodes.map(|n| n.expect("every slot was filled above"));
        for (n, r) in nodes.iter_mut().zip(readings) {
            n.handle_reading(r);
        }
        Ok(Line {
            nodes,
            deframers: [const { [Deframer::new(), Deframer::new()] }; N],
            rngs,
            now: Instant::ZERO,
        })
    }

    /// The robots, left to right.
    pub fn nodes(&self) -> &[FusedNode; N] {
        &self.nodes
    }

    /// Every robot's receivers, left then right.
    pub fn deframers(&self) -> &[[Deframer; 2]; N] {
        &self.deframers
    }

    /// The time reached so far.
    pub fn now(&self) -> Instant {
        self.now
    }

    /// New readings, from now on (e.g. the light pattern changed).
    pub fn set_readings(&mut self, readings: [Level; N]) {
        for (n, r) in self.nodes.iter_mut().zip(readings) {
            n.handle_reading(r);
        }
    }

    /// Every robot's current decision, left to right.
    pub fn decisions(&self) -> [Option<Sector>; N] {
        core::array::from_fn(|i| self.nodes[i].decision())
    }

    /// Runs every deadline up to and including `end`, reporting what happens to `observe`
    /// (time, robot index, happening).
    pub fn run_until(
        &mut self,
        end: Instant,
        mut observe: impl FnMut(Instant, usize, Happening<'_>),
    ) {
        loop {
            let next = (0..N).map(|i| (self.nodes[i].poll_timeout(), i)).min();
            let Some((t, i)) = next.filter(|&(t, _)| t <= end) else {
                self.now = self.now.max(end);
                return;
            };
            self.now = t;
            self.nodes[i].handle_timeout(t, &mut self.rngs[i]);
            self.settle(t, i, &mut observe);
        }
    }

    /// Delivers what robot `first` sends at `t`, and what that makes others send, until quiet.
    fn settle(
        &mut self,
        t: Instant,
        first: usize,
        observe: &mut impl FnMut(Instant, usize, Happening<'_>),
    ) {
        let mut dirty = [false; N];
        dirty[first] = true;
        while let Some(i) = dirty.iter().position(|&d| d) {
            dirty[i] = false;
            while let Some(e) = self.nodes[i].poll_event() {
                observe(t, i, Happening::Event(e));
            }
            while let Some(m) = self.nodes[i].poll_transmit() {
                observe(t, i, Happening::Sent(&m));
                let Ok(frame) = encode(&m) else { continue };
                let left = i.checked_sub(1).map(|j| (j, Sector::RIGHT));
                let right = (i + 1 < N).then_some((i + 1, Sector::LEFT));
                for (j, from) in left.into_iter().chain(right) {
                    let side = usize::from(from == Sector::RIGHT);
                    for msg in self.deframers[j][side].frames(&frame).flatten() {
                        self.nodes[j].handle_message(t, from, &msg, &mut self.rngs[j]);
                    }
                    dirty[j] = true;
                }
            }
        }
    }
}
