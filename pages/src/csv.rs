//! The CSV files of the swarm experiments (run, sweep, field, profile, cycle length, time
//! course), written with [`create`]; numbers with a fixed number of decimals.

use std::path::Path;

use report::csv_files::{create, fixed, opt};
use swarm_sim::experiment::{Arrow, RadialPoint, RunOutput, SweepPoint};
use swarm_sim::sim::RunConfig;

/// One row per period (row 0 is the start): `period,time_s,x,y,direction_deg,consensus,decided,mean_diversity`.
///
/// # Errors
/// If the file cannot be written.
pub fn write_run_csv(path: &Path, out: &RunOutput, cfg: &RunConfig) -> std::io::Result<()> {
    let mut w = create(path)?;
    w.write_record([
        "period",
        "time_s",
        "x",
        "y",
        "direction_deg",
        "consensus",
        "decided",
        "mean_diversity",
    ])?;
    w.write_record([
        "0".to_owned(),
        "0".to_owned(),
        fixed(out.start.x, 4),
        fixed(out.start.y, 4),
        String::new(),
        String::new(),
        String::new(),
        String::new(),
    ])?;
    for p in &out.periods {
        w.write_record([
            p.index.to_string(),
            (u64::from(p.index) * cfg.period_secs()).to_string(),
            fixed(p.to.x, 4),
            fixed(p.to.y, 4),
            opt(p.direction.map(f64::to_degrees), 2),
            fixed(p.consensus, 4),
            p.decided.to_string(),
            fixed(p.diversity, 4),
        ])?;
    }
    w.flush()
}

/// `x_init,runs,success_rate,mean_success_time`; the time is in negotiation periods (moves),
/// over successful runs, empty if none succeeded.
///
/// # Errors
/// If the file cannot be written.
pub fn write_sweep_csv(path: &Path, points: &[SweepPoint]) -> std::io::Result<()> {
    let mut w = create(path)?;
    w.write_record(["x_init", "runs", "success_rate", "mean_success_time"])?;
    for p in points {
        w.write_record([
            p.x_init.to_string(),
            p.runs.to_string(),
            fixed(p.success_rate(), 4),
            opt(p.mean_success_periods, 3),
        ])?;
    }
    w.flush()
}

/// `x,y,direction_deg,consensus,decided`.
///
/// # Errors
/// If the file cannot be written.
pub fn write_field_csv(path: &Path, arrows: &[Arrow]) -> std::io::Result<()> {
    let mut w = create(path)?;
    w.write_record(["x", "y", "direction_deg", "consensus", "decided"])?;
    for a in arrows {
        w.write_record([
            a.at.x.to_string(),
            a.at.y.to_string(),
            opt(a.direction.map(f64::to_degrees), 2),
            fixed(a.consensus, 4),
            a.decided.to_string(),
        ])?;
    }
    w.flush()
}

/// `distance,runs,inward,inward_se`.
///
/// # Errors
/// If the file cannot be written.
pub fn write_radial_csv(path: &Path, points: &[RadialPoint]) -> std::io::Result<()> {
    let mut w = create(path)?;
    w.write_record(["distance", "runs", "inward", "inward_se"])?;
    for p in points {
        w.write_record([
            p.distance.to_string(),
            p.runs.to_string(),
            fixed(p.inward, 4),
            fixed(p.inward_se, 4),
        ])?;
    }
    w.flush()
}

/// One cycle length of the cycle-length experiment.
#[derive(Clone, Debug)]
pub struct CycleRow {
    /// Cycle length `t_p^max` in seconds.
    pub cycle_s: u64,
    /// Mean waves an agent took part in per gathering cycle (61 = no collisions).
    pub waves_heard: f64,
    /// Agents that initiated a wave in that cycle (the rest were busy at their initiation's
    /// second), over the runs that measured `waves_heard`.
    pub initiating: u64,
    /// Agents over those runs (agent-cycles).
    pub agent_cycles: u64,
    /// Success at each initial position.
    pub points: Vec<SweepPoint>,
}

impl CycleRow {
    /// The share of agent-cycles with an initiation.
    pub fn initiating_share(&self) -> f64 {
        self.initiating as f64 / self.agent_cycles.max(1) as f64
    }
}

/// `cycle_s,waves_heard,initiating_share,x_init,runs,success_rate,mean_success_time`.
///
/// # Errors
/// If the file cannot be written.
pub fn write_cycle_csv(path: &Path, rows: &[CycleRow]) -> std::io::Result<()> {
    let mut w = create(path)?;
    w.write_record([
        "cycle_s",
        "waves_heard",
        "initiating_share",
        "x_init",
        "runs",
        "success_rate",
        "mean_success_time",
    ])?;
    for r in rows {
        for p in &r.points {
            w.write_record([
                r.cycle_s.to_string(),
                fixed(r.waves_heard, 2),
                fixed(r.initiating_share(), 4),
                p.x_init.to_string(),
                p.runs.to_string(),
                fixed(p.success_rate(), 4),
                opt(p.mean_success_periods, 3),
            ])?;
        }
    }
    w.flush()
}

/// The averaged course of one scenario, one row per placement and period:
/// `placement,t,runs,arrived,diversity_mean,diversity_q10,diversity_q90,consensus_mean,consensus_q10,consensus_q90`.
///
/// # Errors
/// If the file cannot be written.
pub fn write_course_csv(
    path: &Path,
    courses: &[(&str, &swarm_sim::timecourse::TimeCourse)],
) -> std::io::Result<()> {
    let mut w = create(path)?;
    w.write_record([
        "placement",
        "t",
        "runs",
        "arrived",
        "diversity_mean",
        "diversity_q10",
        "diversity_q90",
        "consensus_mean",
        "consensus_q10",
        "consensus_q90",
    ])?;
    for (name, c) in courses {
        for p in &c.points {
            w.write_record([
                (*name).to_owned(),
                p.t.to_string(),
                c.runs.to_string(),
                p.arrived.to_string(),
                fixed(p.diversity.mean, 4),
                fixed(p.diversity.q10, 4),
                fixed(p.diversity.q90, 4),
                fixed(p.consensus.mean, 4),
                fixed(p.consensus.q10, 4),
                fixed(p.consensus.q90, 4),
            ])?;
        }
    }
    w.flush()
}

/// The data of an x–y figure, one row per point: `line,X,Y,se` (`se` empty where the figure
/// draws no error bar), with the figure's axis names as the column names of x and y.
///
/// # Errors
/// If the file cannot be written.
pub fn write_lines_csv(
    path: &Path,
    x: &str,
    y: &str,
    lines: &[report::plot::Line],
) -> std::io::Result<()> {
    let mut w = create(path)?;
    w.write_record(["line", x, y, "se"])?;
    for l in lines {
        for &(px, py, se) in &l.points {
            let se = if se == 0.0 {
                String::new()
            } else {
                fixed(se, 4)
            };
            w.write_record([l.label.clone(), fixed(px, 4), fixed(py, 4), se])?;
        }
    }
    w.flush()
}
