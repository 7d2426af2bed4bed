//! A run packed for the page: the header and the events as deltas.
//!
//! `ev` is one flat stream of integers, event after event, each `dt, op, args...` (`dt`: ms
//! since the previous event):
//!
//! | op | event | args |
//! |---:|---|---|
//! | 0, 1, 2 | wave state inactive, active, refractory | robot |
//! | 3 | a frame on air | robot, bytes, n, then n pairs (neighbour's index, [`Outcome`]) |
//! | 4 | LEDs | robot, colour (0 off, 1 green, 2 blue, 10 + s sector s) |
//! | 5 | preferred direction | robot, sector or −1 |
//! | 6 | a decision | index into `decisions` |
//! | 7 | the swarm moved | index into `moves` |
//! | 8, 9 | robot killed, restarted | robot |
//! | 10 | the lamps changed | index into `header.lights` |
//!
//! A frame reaches every robot in `neighbours[sender]` (the robots that ever heard that
//! sender: relative positions never change during a run); only the receivers it did not
//! reach intact are listed with it. So a frame costs a few bytes however many hear it.

use std::collections::BTreeSet;

use hal_emu::{DropReason, TraceEvent};
use serde::{Deserialize, Serialize};

use super::header::{Header, PatternAt};

/// The replay format's version (the page and `cimax view` check it).
pub const REPLAY_VERSION: u32 = 1;

/// Why a neighbour did not get a frame intact (the codes in `ev`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Outcome {
    /// It collided with another frame at the receiver.
    Garbled = 1,
    /// Bytes were corrupted on the way.
    Corrupted = 2,
    /// Lost on the way.
    Lost = 3,
    /// The receiver was transmitting.
    ReceiverTransmitting = 4,
    /// The receiver was dead.
    ReceiverDead = 5,
}

/// A decision, with what it was based on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Decision {
    /// Robot.
    pub robot: usize,
    /// Negotiation period, from 1.
    pub period: u32,
    /// The sector decided, −1 for none.
    pub decision: i16,
    /// The last sensor reading.
    pub reading: f32,
    /// Votes per sector.
    pub votes: Vec<u16>,
    /// Average diversity per sector, `null` where nothing was heard.
    pub scores: Vec<Option<f32>>,
}

/// A move of the swarm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveAt {
    /// When, ms.
    pub t_ms: u64,
    /// The centre before the move, R.
    pub from: [f64; 2],
    /// The centre after it, R.
    pub to: [f64; 2],
    /// Heading, radians, if it moved.
    pub heading: Option<f64>,
    /// Agreement at the move, 0 to 1.
    pub consensus: f64,
}

/// Consensus and diversity against time, for the chart under the picture.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Series {
    /// Times, ms.
    pub t_ms: Vec<u64>,
    /// The fraction of robots showing the most shown decision.
    pub consensus: Vec<f32>,
    /// The mean over decided robots of their most diverse sector's score.
    pub diversity: Vec<f32>,
}

impl Series {
    /// Adds a point (replacing one at the same time).
    pub fn push(&mut self, t_ms: u64, consensus: f32, diversity: f32) {
        if self.t_ms.last() == Some(&t_ms) {
            self.t_ms.pop();
            self.consensus.pop();
            self.diversity.pop();
        }
        self.t_ms.push(t_ms);
        self.consensus.push(consensus);
        self.diversity.push(diversity);
    }
}

/// A run packed for the page.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Replay {
    /// The set-up.
    pub header: Header,
    /// Per robot, the robots its frames reach.
    pub neighbours: Vec<Vec<u32>>,
    /// The event stream (see the module's table).
    pub ev: Vec<i64>,
    /// The decisions `ev` refers to.
    pub decisions: Vec<Decision>,
    /// The moves `ev` refers to.
    pub moves: Vec<MoveAt>,
    /// Consensus and diversity against time.
    pub series: Series,
    /// Where the page opens, ms: the moment a failing run first went wrong (0 otherwise).
    pub open_at_ms: u64,
    /// The robot that went wrong then, if one did (the page shows it).
    pub open_robot: Option<usize>,
}

/// The stream being built: the time of its last event, what `ev` refers to, and the
/// LEDs and scores behind the chart.
struct Packer<'h> {
    header: &'h Header,
    ev: Vec<i64>,
    last_t: u64,
    /// Per frame, in order: the neighbours it did not reach intact.
    frames: std::vec::IntoIter<Vec<(u32, Outcome)>>,
    decisions: Vec<Decision>,
    moves: Vec<MoveAt>,
    tracker: Tracker,
    series: Series,
    /// The lamps in force (index into `header.lights`).
    pattern: usize,
}

impl Packer<'_> {
    fn op(&mut self, t_ms: u64, op: i64, args: &[i64]) {
        self.ev.push(t_ms.saturating_sub(self.last_t) as i64);
        self.last_t = self.last_t.max(t_ms);
        self.ev.push(op);
        self.ev.extend_from_slice(args);
    }

    /// A point of the chart at `t_ms`.
    fn chart(&mut self, t_ms: u64) {
        let (c, d) = self.tracker.point();
        self.series.push(t_ms, c, d);
    }

    /// Packs one event (robots beyond the header's are adversaries: not shown).
    fn event(&mut self, e: &TraceEvent) {
        let n = self.header.positions.len();
        match e {
            TraceEvent::State { t_ms, robot, state } if *robot < n => {
                let op = match state.as_ref() {
                    "active" => 1,
                    "refractory" => 2,
                    _ => 0,
                };
                self.op(*t_ms, op, &[*robot as i64]);
            }
            TraceEvent::Sent { t_ms, robot, len } if *robot < n => {
                let exc = self.frames.next().unwrap_or_default();
                let mut args = vec![*robot as i64, *len as i64, exc.len() as i64];
                for (j, o) in exc {
                    args.extend([i64::from(j), o as i64]);
                }
                self.op(*t_ms, 3, &args);
            }
            TraceEvent::Led { t_ms, robot, color } if *robot < n => {
                let c = color_code(color);
                self.op(*t_ms, 4, &[*robot as i64, c]);
                self.tracker.leds[*robot] = c;
                self.chart(*t_ms);
            }
            TraceEvent::Preference {
                t_ms,
                robot,
                preference,
            } if *robot < n => {
                self.op(*t_ms, 5, &[*robot as i64, sector_code(preference)]);
            }
            TraceEvent::Decided { t_ms, robot, .. } if *robot < n => self.decided(e, *t_ms, *robot),
            TraceEvent::Moved { t_ms, .. } => self.moved(e, *t_ms),
            TraceEvent::Killed { t_ms, robot } if *robot < n => {
                self.op(*t_ms, 8, &[*robot as i64]);
            }
            TraceEvent::Restarted { t_ms, robot } if *robot < n => {
                self.op(*t_ms, 9, &[*robot as i64]);
            }
            TraceEvent::Pattern { t_ms, .. } => self.pattern(*t_ms),
            _ => {}
        }
    }

    fn decided(&mut self, e: &TraceEvent, t_ms: u64, robot: usize) {
        let TraceEvent::Decided {
            period,
            decision,
            votes,
            scores,
            reading,
            ..
        } = e
        else {
            return;
        };
        self.op(t_ms, 6, &[self.decisions.len() as i64]);
        self.tracker.best[robot] = scores.iter().flatten().copied().reduce(f32::max);
        self.decisions.push(Decision {
            robot,
            period: *period,
            decision: decision.map_or(-1, i16::from),
            reading: *reading,
            votes: votes.clone(),
            scores: scores.iter().map(|s| s.map(round4)).collect(),
        });
        self.chart(t_ms);
    }

    fn moved(&mut self, e: &TraceEvent, t_ms: u64) {
        let TraceEvent::Moved {
            centre,
            heading,
            step,
            consensus,
            ..
        } = e
        else {
            return;
        };
        self.op(t_ms, 7, &[self.moves.len() as i64]);
        let to = heading.map_or(*centre, |a| {
            [centre[0] + step * a.cos(), centre[1] + step * a.sin()]
        });
        self.moves.push(MoveAt {
            t_ms,
            from: *centre,
            to,
            heading: *heading,
            consensus: *consensus,
        });
    }

    /// The lamps changed: the schedule's next pattern (the first is in force from the start).
    fn pattern(&mut self, t_ms: u64) {
        let lights = &self.header.lights;
        if let Some(i) = (self.pattern + 1..lights.len()).find(|&i| lights[i].t_ms <= t_ms) {
            self.pattern = i;
            self.op(t_ms, 10, &[i as i64]);
            self.tracker.expect(lights.get(i));
            self.chart(t_ms);
        }
    }
}

impl Replay {
    /// Packs `trace` (events in time order) under `header`; each robot's frames reach the
    /// robots that ever heard it (its `Received` and `Dropped` events).
    pub fn from_trace(header: Header, trace: &[TraceEvent]) -> Replay {
        let n = header.positions.len();
        let neighbours = neighbours(n, trace);
        Replay::with_neighbours(header, trace, neighbours)
    }

    /// [`from_trace`](Self::from_trace) with the robots each robot's frames reach given (the
    /// 2D simulator's neighbour lists: its trace has no receptions).
    pub fn with_neighbours(
        header: Header,
        trace: &[TraceEvent],
        neighbours: Vec<BTreeSet<usize>>,
    ) -> Replay {
        let n = header.positions.len();
        let mut p = Packer {
            header: &header,
            ev: Vec::new(),
            last_t: 0,
            frames: frame_exceptions(n, trace, &neighbours).into_iter(),
            decisions: Vec::new(),
            moves: Vec::new(),
            tracker: Tracker::new(n),
            series: Series::default(),
            pattern: 0,
        };
        p.tracker.expect(header.lights.first());
        for e in trace {
            p.event(e);
        }
        let (ev, decisions, moves, series) = (p.ev, p.decisions, p.moves, p.series);
        let (open_at_ms, open_robot) = open_at(&header, trace, &moves);
        Replay {
            neighbours: neighbours
                .into_iter()
                .map(|s| s.into_iter().map(|r| r as u32).collect())
                .collect(),
            header,
            ev,
            decisions,
            moves,
            series,
            open_at_ms,
            open_robot,
        }
    }
}

/// Per frame sent by a robot, in order, the neighbours it did not reach intact: each reception
/// or drop belongs to its sender's last frame.
fn frame_exceptions(
    n: usize,
    trace: &[TraceEvent],
    neighbours: &[BTreeSet<usize>],
) -> Vec<Vec<(u32, Outcome)>> {
    let mut exceptions: Vec<Vec<(u32, Outcome)>> = Vec::new();
    let mut frame_of: Vec<Option<usize>> = vec![None; n];
    for e in trace {
        let (from, to, o) = match e {
            TraceEvent::Sent { robot, .. } if *robot < n => {
                frame_of[*robot] = Some(exceptions.len());
                exceptions.push(Vec::new());
                continue;
            }
            TraceEvent::Received {
                robot,
                from,
                garbled,
                corrupted,
                ..
            } if *garbled || *corrupted > 0 => {
                let o = if *garbled {
                    Outcome::Garbled
                } else {
                    Outcome::Corrupted
                };
                (*from, *robot, o)
            }
            TraceEvent::Dropped {
                robot,
                from,
                reason,
                ..
            } => {
                let o = match reason {
                    DropReason::Loss => Outcome::Lost,
                    DropReason::ReceiverTransmitting => Outcome::ReceiverTransmitting,
                    DropReason::ReceiverDead => Outcome::ReceiverDead,
                };
                (*from, *robot, o)
            }
            _ => continue,
        };
        if from < n {
            note(&mut exceptions, &frame_of, neighbours, from, to, o);
        }
    }
    exceptions
}

/// Per sender, the robots its frames reached or failed to reach.
fn neighbours(n: usize, trace: &[TraceEvent]) -> Vec<BTreeSet<usize>> {
    let mut out = vec![BTreeSet::new(); n];
    for e in trace {
        if let TraceEvent::Received { robot, from, .. } | TraceEvent::Dropped { robot, from, .. } =
            e
            && *from < n
            && *robot < n
        {
            out[*from].insert(*robot);
        }
    }
    out
}

/// Records that `from`'s last frame did not reach `to` intact.
fn note(
    exceptions: &mut [Vec<(u32, Outcome)>],
    frame_of: &[Option<usize>],
    neighbours: &[BTreeSet<usize>],
    from: usize,
    to: usize,
    o: Outcome,
) {
    let (Some(f), Some(j)) = (
        frame_of[from],
        neighbours[from].iter().position(|&r| r == to),
    ) else {
        return;
    };
    exceptions[f].push((j as u32, o));
}

/// Each robot's LEDs and best score so far, and the LEDs expected under the lamps of the
/// time: the chart's consensus and diversity.
struct Tracker {
    leds: Vec<i64>,
    best: Vec<Option<f32>>,
    expected: Option<Vec<i64>>,
}

impl Tracker {
    fn new(n: usize) -> Self {
        Tracker {
            leds: vec![0; n],
            best: vec![None; n],
            expected: None,
        }
    }

    /// The lamps are now `p`: its expected LEDs (if it has a verdict) are what counts.
    fn expect(&mut self, p: Option<&PatternAt>) {
        self.expected = p.and_then(|p| p.expected.as_ref()).map(|x| {
            x.chars()
                .map(|c| match c {
                    'L' => 1,
                    'R' => 2,
                    _ => 0,
                })
                .collect()
        });
    }

    /// (consensus, diversity) now: the share of robots showing the expected LEDs (lamps with
    /// a verdict) or else the most shown colour, and the mean best score of the robots that
    /// have one.
    fn point(&self) -> (f32, f32) {
        let n = self.leds.len().max(1);
        let top = match &self.expected {
            Some(x) => self.leds.iter().zip(x).filter(|(l, x)| l == x).count(),
            None => {
                let mut counts = std::collections::BTreeMap::new();
                for &c in self.leds.iter().filter(|&&c| c != 0) {
                    *counts.entry(c).or_insert(0usize) += 1;
                }
                counts.values().copied().max().unwrap_or(0)
            }
        };
        let scored: Vec<f32> = self.best.iter().flatten().copied().collect();
        let d = if scored.is_empty() {
            0.0
        } else {
            scored.iter().sum::<f32>() / scored.len() as f32
        };
        (round4(top as f32 / n as f32), round4(d))
    }
}

/// The page's colour code of a traced LED colour (anything else, such as a sector beyond
/// what a trace file can mean, reads as off).
fn color_code(c: &str) -> i64 {
    match c {
        "green" => 1,
        "blue" => 2,
        _ => c
            .strip_prefix("sector ")
            .and_then(|s| s.parse::<u8>().ok())
            .map_or(0, |s| 10 + i64::from(s)),
    }
}

/// The sector of a traced preference, −1 for none.
fn sector_code(p: &str) -> i64 {
    match p {
        "right" => 0,
        "left" => 1,
        _ => p
            .strip_prefix("sector ")
            .and_then(|s| s.parse::<u8>().ok())
            .map_or(-1, i64::from),
    }
}

/// `x` to four significant digits (a smaller file; the page shows three).
fn round4(x: f32) -> f32 {
    if x == 0.0 || !x.is_finite() {
        return if x.is_finite() { x } else { 0.0 };
    }
    let scale = 10f32.powi(3 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

/// Where a failing run should open, and the robot that went wrong: on a line, the first LED
/// change to a colour other than the expected one under the lamps of the time; on a plane,
/// the first move away from the goal. The end if nothing went wrong before it, 0 for a run
/// that passed.
fn open_at(header: &Header, trace: &[TraceEvent], moves: &[MoveAt]) -> (u64, Option<usize>) {
    if header.verdict.as_ref().is_none_or(|v| v.success) {
        return (0, None);
    }
    if let Some(goal) = &header.goal {
        let t = moves
            .iter()
            .find(|m| {
                m.heading
                    .is_some_and(|a| a.cos() * (goal.x - m.from[0]).signum() < 0.0)
            })
            .map_or(header.duration_ms, |m| m.t_ms);
        return (t, None);
    }
    for e in trace {
        let TraceEvent::Led { t_ms, robot, color } = e else {
            continue;
        };
        let expected = header
            .lights
            .iter()
            .rev()
            .find(|p| p.t_ms <= *t_ms)
            .and_then(|p| p.expected.as_ref())
            .and_then(|x| x.chars().nth(*robot));
        let shown = match color.as_ref() {
            "green" => 'L',
            "blue" => 'R',
            _ => '-',
        };
        if let Some(x) = expected
            && shown != '-'
            && shown != x
        {
            return (*t_ms, Some(*robot));
        }
    }
    (header.duration_ms, None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Kind;

    fn header(n: usize) -> Header {
        let mut h = Header::empty(Kind::Line);
        h.positions = vec![[0.0, 0.0]; n];
        h.duration_ms = 1000;
        h
    }

    #[test]
    fn a_frame_lists_only_the_neighbours_it_did_not_reach_intact() {
        let t = [
            TraceEvent::Sent {
                t_ms: 10,
                robot: 1,
                len: 32,
            },
            TraceEvent::Received {
                t_ms: 43,
                robot: 0,
                from: 1,
                sector: 0,
                len: 32,
                garbled: false,
                corrupted: 0,
            },
            TraceEvent::Dropped {
                t_ms: 43,
                robot: 2,
                from: 1,
                reason: DropReason::ReceiverTransmitting,
            },
            TraceEvent::State {
                t_ms: 50,
                robot: 2,
                state: "active".into(),
            },
        ];
        let r = Replay::from_trace(header(3), &t);
        assert_eq!(r.neighbours, vec![vec![], vec![0, 2], vec![]]);
        // dt 10, frame of robot 1, 32 bytes, one exception: neighbour #1 (robot 2), code 4;
        // then dt 40, robot 2 active.
        assert_eq!(r.ev, vec![10, 3, 1, 32, 1, 1, 4, 40, 1, 2]);
    }

    #[test]
    fn a_failing_line_opens_at_the_first_wrong_led() {
        let mut h = header(2);
        h.lights = vec![PatternAt {
            t_ms: 0,
            lights: "10".into(),
            expected: Some("LL".into()),
        }];
        h.verdict = Some(crate::Verdict {
            success: false,
            leds: "LR".into(),
            expected: Some("LL".into()),
            text: String::new(),
        });
        let led = |t_ms, robot, c: &'static str| TraceEvent::Led {
            t_ms,
            robot,
            color: c.into(),
        };
        let t = [
            led(100, 0, "green"),
            led(200, 1, "blue"),
            led(300, 1, "green"),
        ];
        let r = Replay::from_trace(h.clone(), &t);
        assert_eq!((r.open_at_ms, r.open_robot), (200, Some(1)));
        h.verdict.as_mut().unwrap().success = true;
        let r = Replay::from_trace(h, &t);
        assert_eq!((r.open_at_ms, r.open_robot), (0, None));
    }

    #[test]
    fn colours_and_sectors_from_a_hostile_trace_cannot_overflow() {
        assert_eq!(color_code("sector 9223372036854775807"), 0);
        assert_eq!(color_code("sector 3"), 13);
        assert_eq!(sector_code("sector -5"), -1);
        assert_eq!(sector_code("left"), 1);
    }

    #[test]
    fn consensus_counts_the_most_shown_colour() {
        let led = |t_ms, robot, c: &'static str| TraceEvent::Led {
            t_ms,
            robot,
            color: c.into(),
        };
        let r = Replay::from_trace(
            header(4),
            &[led(1, 0, "blue"), led(2, 1, "blue"), led(2, 2, "green")],
        );
        assert_eq!(r.series.t_ms, vec![1, 2]);
        assert_eq!(r.series.consensus, vec![0.25, 0.5]);
    }
}
