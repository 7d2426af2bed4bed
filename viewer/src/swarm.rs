//! The replay of a 2D simulation (`cimax swarm run --html`): agents instead of robots, a hop
//! per second, each agent's decided bearing binned into [`TRACE_SECTORS`] sectors for its
//! colour.

use std::collections::BTreeSet;

use hal_emu::TraceEvent;

use super::{Header, Kind, Replay, goal_of, heatmap, move_verdict};
use swarm_sim::experiment::RunOutput;
use swarm_sim::scenario::Scenario;
use swarm_sim::sim::TRACE_SECTORS;

/// The replay of `out`, a run of `scn` with `seed` recorded as `trace`.
pub fn replay(scn: &Scenario, out: &RunOutput, seed: u64, trace: &[TraceEvent]) -> Replay {
    let swarm = &out.swarm;
    let n = swarm.len();
    let mut h = Header::empty(Kind::Swarm);
    let periods = out.periods.len() as u32;
    h.title = format!(
        "cimax swarm run: {} ({n} agents) from ({:.2}, {:.2}), {periods} periods, seed {seed}",
        scn.name, out.start.x, out.start.y
    );
    h.seed = seed;
    h.duration_ms = u64::from(periods) * scn.run.period_secs() * 1000;
    h.sectors = TRACE_SECTORS;
    h.ids = (0..n).map(|i| i as u16).collect();
    h.positions = swarm.offsets().iter().map(|v| [v.x, v.y]).collect();
    h.start = [out.start.x, out.start.y];
    // A message takes its one-second hop: shown on air for that second.
    h.airtime_ms_per_byte = 1000.0;
    let mut centres = vec![h.start];
    centres.extend(out.periods.iter().map(|p| [p.to.x, p.to.y]));
    let reach = h
        .positions
        .iter()
        .map(|p| p[0].hypot(p[1]))
        .fold(0.0, f64::max);
    h.field = Some(heatmap(
        &scn.field,
        &centres,
        reach + 1.0,
        &format!("field {} (X)", scn.name),
    ));
    h.goal = goal_of(scn.success);
    let end = out.periods.last().map_or(out.start, |p| p.to);
    let leds = final_leds(n, trace);
    h.verdict = Some(move_verdict(
        h.goal.as_ref(),
        out.success_at,
        periods,
        "periods",
        [end.x, end.y],
        leds,
    ));
    let neighbours = (0..n)
        .map(|i| {
            swarm
                .neighbours(i)
                .iter()
                .map(|l| l.agent as usize)
                .collect::<BTreeSet<_>>()
        })
        .collect();
    Replay::with_neighbours(h, trace, neighbours)
}

/// Each agent's last colour: its decided sector's digit, `-` for none.
fn final_leds(n: usize, trace: &[TraceEvent]) -> String {
    let mut leds = vec!['-'; n];
    for e in trace {
        if let TraceEvent::Led { robot, color, .. } = e
            && let Some(l) = leds.get_mut(*robot)
        {
            *l = color
                .strip_prefix("sector ")
                .and_then(|s| s.chars().next())
                .unwrap_or('-');
        }
    }
    leds.into_iter().collect()
}
